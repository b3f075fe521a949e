#!/usr/bin/env python3
"""Closure of the SPH energy budget: at every step the columns of energy_budget.csv
(viscous, body force work, pressure correction, potential of the move, shifting, density-error
displacement; sums from t = 0) add up to the change of the total energy in energy.csv, to
round-off (both measured from the files' first row: a run restarted into another directory
starts them at its restart). Prints each term at the energy peak, so a gain can be traced to
its source.

With --zero COLUMN (repeatable), that column must be exactly zero at every step: a term the
scene does not call for (the density-error displacement at alpha = 0) must not act.

usage: check_energy_budget.py energy.csv energy_budget.csv [--zero COLUMN]...
"""
import math
import sys

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from compare_csv import read  # noqa: E402


def main():
    args = sys.argv[1:]
    zero = [args[k + 1] for k in range(len(args) - 1) if args[k] == "--zero"]
    eh, erows = read(args[0])
    bh, brows = read(args[1])
    total = [h.split(" [")[0] for h in eh].index("total energy")
    names = [h.split(" [")[0] for h in bh][1:]
    if len(erows) != len(brows) or not erows:
        print(f"energy.csv has {len(erows)} rows, energy_budget.csv {len(brows)}: they must match, one per step")
        return 1
    e0 = erows[0][total]
    scale = max(abs(e0), max(abs(r[total] - e0) for r in erows), 1e-300)
    worst, worst_t = 0.0, 0.0
    for er, br in zip(erows, brows):
        if abs(er[0] - br[0]) > 1e-12 * max(1.0, abs(er[0])):
            print(f"time {br[0]} of energy_budget.csv does not match {er[0]} of energy.csv")
            return 1
        gap = abs(sum(br[1:]) - sum(brows[0][1:]) - (er[total] - e0))
        if not math.isfinite(gap) or gap > worst:
            worst, worst_t = gap, er[0]
    print(f"budget closure: largest |sum of terms - (E - E0)| = {worst:.3e} J at t = {worst_t:.4g} s "
          f"(relative to {scale:.4g} J: {worst / scale:.1e}; tolerance 1e-9)")
    peak = max(range(len(erows)), key=lambda k: erows[k][total])
    print(f"at the energy peak t = {erows[peak][0]:.4g} s (E - E0 = {erows[peak][total] - e0:.4g} J): " +
          ", ".join(f"{n} {v:.4g}" for n, v in zip(names, brows[peak][1:])))
    ok = math.isfinite(worst) and worst <= 1e-9 * scale
    for column in zero:
        if column not in names:
            print(f"--zero {column!r}: energy_budget.csv has no such column (it has: {', '.join(names)})")
            return 1
        k = names.index(column) + 1
        nonzero = [r[0] for r in brows if r[k] != 0.0]
        print(f"{column}: " + ("zero at every step" if not nonzero else
                               f"non-zero from t = {nonzero[0]:.4g} s ({len(nonzero)} rows), expected none"))
        ok = ok and not nonzero
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
