#!/usr/bin/env python3
"""Stability check of a run's energy monitor: total energy stays finite and never exceeds its
initial value by more than a relative tolerance (a dissipative flow must not gain energy).

usage: check_energy.py energy.csv MAX_RELATIVE_GAIN [MAX_KINETIC_FRACTION]

With MAX_KINETIC_FRACTION (a flow at rest): the kinetic energy must also stay below that
fraction of |initial total energy| at every output.
"""
import math
import sys

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from compare_csv import read  # noqa: E402


def main():
    header, rows = read(sys.argv[1])
    tol = float(sys.argv[2])
    col = [h.split(" [")[0] for h in header].index("total energy")
    e = [r[col] for r in rows]
    finite = all(math.isfinite(v) for v in e)
    gain = (max(e) - e[0]) / abs(e[0])
    print(f"energy: initial {e[0]:.6g}, max {max(e):.6g}, final {e[-1]:.6g}; relative gain {gain:.3e} "
          f"(tolerance {tol:.1e}); finite: {finite}")
    ok = finite and gain <= tol
    if len(sys.argv) > 3:
        kin = [r[[h.split(" [")[0] for h in header].index("kinetic energy")] for r in rows]
        bound = float(sys.argv[3]) * abs(e[0])
        worst = max(kin)
        print(f"kinetic energy: max {worst:.3e} at t = {rows[kin.index(worst)][0]:.3f} (bound {bound:.3e} = "
              f"{float(sys.argv[3]):.1e} |E0|)")
        ok = ok and worst <= bound
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
