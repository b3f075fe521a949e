#!/usr/bin/env python3
"""The falling cylinder (paper 4.3, issue 13), FEM and SPH side by side: position, vertical
fluid force and the damping of the heave.

    build/twinflow parameters/falling_cylinder.prm --set Scene/Methods=sph --set SPH/Particle\\ spacing=0.02 -o RUN
    mpirun -np 2 build/twinflow parameters/falling_cylinder.prm --set Scene/Methods=fem -o RUN
    /usr/bin/python3 benchmarks/falling_cylinder/compare_methods.py RUN OUT.png [--from 1.0]

(or FEM_CSV SPH_CSV in place of RUN: two body_cylinder.csv files of separate runs). Two panels
against time: the centre height y(t) with the Archimedes position, and the vertical fluid force
F_y(t) (a running mean over --window, the raw history faint behind) with the weight
rho_s g pi r^2 L = 62.07 N. For each method it prints the deepest point
of the plunge, the damped-oscillation fit y = y_eq + e^(-lambda t)(a cos wt + b sin wt) over
t >= --from (period, damping ratio lambda / sqrt(lambda^2 + w^2), equilibrium against
Archimedes), and the mean force over the last quarter of its run against the weight. The paper
reports that SPH damps the heave faster than the FEM; the damping ratios compare that.
"""
import argparse
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "tests", "scripts"))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "scripts"))
from check_floating import equilibrium_centre, fit_damped_oscillation  # noqa: E402
from twinflow_csv import read  # noqa: E402

RADIUS, LENGTH, DEPTH, WIDTH, RATIO, G, RHO_W = 0.12, 0.2, 0.5, 1.0, 0.7, 9.8, 1000.0


def load(path):
    header, rows = read(path)
    names = [h.split(" [")[0] for h in header]
    return {n: [r[k] for r in rows] for k, n in enumerate(names)}


def running_mean(t, v, window):
    """Centred running mean over a time window (the SPH force carries step-to-step pressure noise)."""
    out, lo, hi, acc = [], 0, 0, 0.0
    for k in range(len(t)):
        while hi < len(t) and t[hi] <= t[k] + 0.5 * window:
            acc += v[hi]
            hi += 1
        while t[lo] < t[k] - 0.5 * window:
            acc -= v[lo]
            lo += 1
        out.append(acc / (hi - lo))
    return out


def summarise(name, body, t_fit, y_arch, weight):
    t, y, f = body["time"], body["y"], body["Fy"]
    k_min = min(range(len(y)), key=lambda k: y[k])
    out = {"name": name, "end": t[-1], "deepest": (y[k_min], t[k_min])}
    # mean force over the last quarter of the run (the load of row k acts over step k)
    t_q = t[-1] - 0.25 * (t[-1] - t[0])
    num = den = 0.0
    for k in range(1, len(t)):
        if t[k - 1] >= t_q:
            num += f[k] * (t[k] - t[k - 1])
            den += t[k] - t[k - 1]
    out["force"] = (num / den, t_q) if den > 0 else (float("nan"), t_q)
    idx = [k for k in range(len(t)) if t[k] >= t_fit]
    if len(idx) > 20 and t[idx[-1]] - t[idx[0]] > 1.0:
        idx = idx[:: max(1, len(idx) // 800)]
        tw, yw = [t[k] for k in idx], [y[k] for k in idx]
        ww = [0.5 * ((tw[min(k + 1, len(tw) - 1)] - tw[k]) + (tw[k] - tw[max(k - 1, 0)])) for k in range(len(tw))]
        y_eq, om, lam, amp, rms = fit_damped_oscillation(tw, yw, ww)
        out["fit"] = {"y_eq": y_eq, "period": 2 * math.pi / om, "zeta": lam / math.hypot(lam, om), "amp": amp,
                      "rms": rms}
    print(f"{name}: run to t = {t[-1]:.3f} s; deepest y = {y[k_min]:.4f} m at t = {t[k_min]:.3f} s")
    if "fit" in out:
        fit = out["fit"]
        print(f"  fit over t >= {t_fit}: equilibrium {fit['y_eq']:.5f} m ({100 * (fit['y_eq'] - y_arch) / RADIUS:+.2f} %"
              f" of r from Archimedes {y_arch:.5f} m), period {fit['period']:.3f} s, damping ratio {fit['zeta']:.4f},"
              f" amplitude {fit['amp']:.4f} m at t = {t_fit}, rms residual {fit['rms']:.1e} m")
    else:
        print(f"  no damped-oscillation fit: less than 1 s of the run after t = {t_fit}")
    print(f"  mean F_y over t >= {t_q:.2f} s: {out['force'][0]:.2f} N ({100 * (out['force'][0] - weight) / weight:+.2f} %"
          f" of the weight {weight:.2f} N)")
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("inputs", nargs="+", help="RUN directory (with fem/ and sph/) or FEM_CSV SPH_CSV")
    p.add_argument("png")
    p.add_argument("--from", dest="t_fit", type=float, default=1.0,
                   help="start of the damped-oscillation fit (after the plunge; default 1 s)")
    p.add_argument("--window", type=float, default=0.05, help="running-mean window of the force plot [s]")
    a = p.parse_args()
    if len(a.inputs) == 1:
        csvs = [os.path.join(a.inputs[0], m, "body_cylinder.csv") for m in ("fem", "sph")]
    elif len(a.inputs) == 2:
        csvs = a.inputs
    else:
        p.error("give one run directory or two CSV files (FEM, SPH)")
    y_arch = equilibrium_centre(DEPTH, WIDTH, RADIUS, RATIO, True)
    weight = RATIO * RHO_W * G * math.pi * RADIUS**2 * LENGTH
    fig, (ax_y, ax_f) = plt.subplots(2, 1, figsize=(7.5, 6.5), sharex=True)
    for method, path, colour in (("FEM", csvs[0], "C0"), ("SPH", csvs[1], "C1")):
        if not os.path.exists(path):
            print(f"{method}: no {path}, left out")
            continue
        body = load(path)
        bad = [n for n, v in body.items() if any(not math.isfinite(x) for x in v)]
        if bad:
            print(f"FAIL: {path} holds non-finite values in {', '.join(bad)}")
            return 1
        s = summarise(method, body, a.t_fit, y_arch, weight)
        label = method + (f" (damping ratio {s['fit']['zeta']:.3f})" if "fit" in s else "")
        ax_y.plot(body["time"], body["y"], color=colour, lw=1.2, label=label)
        ax_f.plot(body["time"], body["Fy"], color=colour, lw=0.5, alpha=0.25)
        ax_f.plot(body["time"], running_mean(body["time"], body["Fy"], a.window), color=colour, lw=1.2,
                  label=f"{method} (running mean over {a.window} s; raw behind)")
    ax_y.axhline(y_arch, color="k", ls="--", lw=0.8, label=f"Archimedes {y_arch:.4f} m")
    ax_y.axhline(DEPTH, color="0.6", ls=":", lw=0.8, label="still water 0.5 m")
    ax_y.set_ylabel("centre y [m]")
    ax_y.legend(fontsize=8)
    ax_f.axhline(weight, color="k", ls="--", lw=0.8, label=f"weight {weight:.2f} N")
    ax_f.set_ylabel("vertical fluid force F_y [N]")
    ax_f.set_xlabel("t [s]")
    ax_f.set_ylim(-0.5 * weight, 4 * weight)
    ax_f.legend(fontsize=8)
    fig.suptitle("Falling cylinder 3D (r = 0.12 m, L = 0.2 m, rho_s = 0.7 rho_w): FEM and SPH")
    fig.tight_layout()
    fig.savefig(a.png, dpi=120)
    print(f"wrote {a.png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
