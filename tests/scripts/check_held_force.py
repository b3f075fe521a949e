#!/usr/bin/env python3
"""Force on a half-submerged disk held fixed in still water, at two particle spacings.

usage: check_held_force.py COARSE_FORCES_CSV [FINE_FORCES_CSV] --radius R [--rho 1000] [--gravity 9.8]
                           [--from T0] [--tolerance 0.02]

Reference: the weight of the displaced water rho g pi R^2 / 2 (per unit depth). Over t >= T0
the mean vertical force of each run (one, or two at spacings dx and dx/2) must lie within
TOLERANCE of it and the horizontal force below 1 % of it. With two runs the observed order and
the first-order Richardson extrapolation 2 F_fine - F_coarse are printed: with p = 0 at the
centres of the surface particles (the paper's form, SPH/Free-surface offset off) the force
carries a first-order deficit (12.6 % / 7.1 % at R/6 and R/12), which the extrapolation
removes; with the surface half a spacing above them neither run has it.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "scripts"))
from twinflow_csv import read  # noqa: E402


def mean_forces(path, t0):
    header, rows = read(path)
    rows = [r for r in rows if r[0] >= t0]
    if not rows or any(not math.isfinite(v) for r in rows for v in r):
        raise SystemExit(f"FAIL: {path}: no rows after t = {t0}, or a non-finite value")
    return sum(r[1] for r in rows) / len(rows), sum(r[2] for r in rows) / len(rows)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("coarse")
    p.add_argument("fine", nargs="?")
    p.add_argument("--radius", type=float, required=True)
    p.add_argument("--rho", type=float, default=1000.0)
    p.add_argument("--gravity", type=float, default=9.8)
    p.add_argument("--from", dest="t0", type=float, default=0.1)
    p.add_argument("--tolerance", type=float, default=0.02)
    a = p.parse_args()
    ref = a.rho * a.gravity * math.pi * a.radius**2 / 2
    if a.fine is None:
        fx, fy = mean_forces(a.coarse, a.t0)
        e = abs(fy - ref) / ref
        print(f"rho g V_submerged = {ref:.2f} N; mean vertical force {fy:.2f} N ({100 * e:.2f} %, tolerance "
              f"{100 * a.tolerance:.1f} %); horizontal {fx:.3g} N")
        ok = e <= a.tolerance and abs(fx) < 0.01 * ref
        print("PASS" if ok else "FAIL")
        return 0 if ok else 1
    (fx_c, fy_c), (fx_f, fy_f) = mean_forces(a.coarse, a.t0), mean_forces(a.fine, a.t0)
    e_c, e_f = abs(fy_c - ref) / ref, abs(fy_f - ref) / ref
    rate = math.log2(e_c / e_f) if e_f > 0 else float("inf")
    extrapolated = 2 * fy_f - fy_c
    e_x = abs(extrapolated - ref) / ref
    print(f"rho g V_submerged = {ref:.2f} N; coarse {fy_c:.2f} N ({100 * e_c:.2f} %), fine {fy_f:.2f} N "
          f"({100 * e_f:.2f} %), order {rate:.2f}; extrapolated {extrapolated:.2f} N ({100 * e_x:.2f} %)")
    print(f"horizontal force: coarse {fx_c:.3g} N, fine {fx_f:.3g} N")
    ok = max(e_c, e_f) <= a.tolerance and max(abs(fx_c), abs(fx_f)) < 0.01 * ref
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
