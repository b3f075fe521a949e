#!/usr/bin/env python3
"""The paper's dam break, FEM and SPH side by side (issue 12): front, energy and water volume.

    build/twinflow parameters/dam_break.prm            # both methods, ~75 min on 2 cores
    /usr/bin/python3 benchmarks/dam_break_fem_sph/plot_fem_sph.py output/dam_break OUT.png

Three panels against time: the surge front x_f (furthest wetted floor point) of both methods,
with the wall at x = 5.3 m and the wall-impact times of OpenFOAM interFoam on these machines
(BENCHMARKS.md: 1.00 s at 8,610 cells, 0.87 s at 34,440 cells) as reference points; the
mechanical energy E/E0 of the water (a dam break is dissipative: E/E0 <= 1); the FEM water
volume drift (SPH conserves mass per particle). Prints the wall-impact times and the energy
at 1 s and 2.5 s.
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

WALL = 5.3
INTERFOAM_IMPACT = [(1.00, "interFoam, 8,610 cells"), (0.87, "interFoam, 34,440 cells")]


def load(path):
    rows = [l for l in open(path) if l.strip() and not l.startswith("#")]
    header = [h.strip().split(" [")[0] for h in rows[0].split(",")]
    cols = list(zip(*[[float(v) for v in r.split(",")] for r in rows[1:]]))
    return dict(zip(header, cols))


def impact(front):
    return next((t for t, x in zip(front["time"], front["x_front"]) if x >= WALL - 0.01), None)


def main(run, png):
    fig, axes = plt.subplots(3, 1, figsize=(7.5, 8.5), sharex=True)
    for method, colour in (("fem", "C0"), ("sph", "C1")):
        d = os.path.join(run, method)
        if not os.path.isdir(d):
            continue
        front, energy = load(os.path.join(d, "front.csv")), load(os.path.join(d, "energy.csv"))
        e = energy["total energy"]
        t_hit = impact(front)
        label = f"{method.upper()} (wall impact {t_hit:.3f} s)" if t_hit else method.upper()
        axes[0].plot(front["time"], front["x_front"], colour, label=label)
        axes[1].plot(energy["time"], [v / e[0] for v in e], colour, label=method.upper())
        at = lambda t: min(zip(energy["time"], e), key=lambda p: abs(p[0] - t))[1] / e[0]  # noqa: E731
        print(f"{method}: wall impact {t_hit} s, E/E0 max {max(e) / e[0]:.4f}, at 1 s {at(1.0):.4f}, "
              f"at 2.5 s {at(2.5):.4f}")
        if method == "fem":
            volume = load(os.path.join(d, "volume.csv"))
            key = [k for k in volume if "drift" in k][0]
            axes[2].plot(volume["time"], volume[key], colour, label="FEM")
    for t, label in INTERFOAM_IMPACT:
        axes[0].plot([t], [WALL], "ko" if "8,610" in label else "ks", mfc="none", label=label)
    axes[0].axhline(WALL, color="k", lw=0.8, ls="--")
    axes[0].set_ylabel("front x_f [m]")
    axes[1].axhline(1.0, color="k", lw=0.8, ls="--", label="E0 (a dam break only dissipates)")
    axes[1].set_ylabel("E / E0 (water)")
    axes[2].set_ylabel("water volume drift [-]")
    axes[2].set_xlabel("time [s]")
    for ax in axes:
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize="small")
    axes[0].set_title("Paper dam break (H = 1 m): FEM 8,192 cells, SPH 45,000 particles")
    fig.tight_layout()
    fig.savefig(png, dpi=100)
    print("wrote", png)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
