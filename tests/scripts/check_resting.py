#!/usr/bin/env python3
"""A 2D disk denser than the water resting on the tank's floor (wall contact, solids/coupling.h).

usage: check_resting.py BODY_CSV --radius R --density-ratio S [--floor Y0] [--from T0]

Over t >= T0 the disk must lie on the floor, not in it and not above it: its centre within
[Y0 + R - 1e-9 m, Y0 + R (1 + 1e-3)] (the contact puts it back on the wall after every
sub-step; the fluid can lift it only with more than its weight less buoyancy), and it must
rest: at rest vertically (|v_y| <= 1e-9 m/s: the contact stops the approach at every sub-step)
in at least 90 % of the rows, and never faster than 0.05 m/s (the SPH force's spikes above the
weight lift it by microns for a step). Every value must be finite. Printed, not asserted: the mean vertical fluid force
against Archimedes' rho_w g pi R^2 (the fluid is excluded from the unresolved gap under the
disk, so the measured one is lower) and the contact's mean reaction (weight minus it).
"""
import argparse
import math
import sys

sys.path.insert(0, __import__("os").path.join(__import__("os").path.dirname(__file__), "..", "..", "scripts"))
from twinflow_csv import read  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("--radius", type=float, required=True)
    ap.add_argument("--density-ratio", type=float, required=True)
    ap.add_argument("--floor", type=float, default=0.0)
    ap.add_argument("--from", dest="t0", type=float, default=1.0)
    ap.add_argument("--gravity", type=float, default=9.81)
    ap.add_argument("--rho-water", type=float, default=1000.0)
    a = ap.parse_args()
    header, rows = read(a.csv)
    col = {h.strip(): k for k, h in enumerate(header)}
    t, y, vy, fy = (col[n] for n in ("time [s]", "y [m]", "vy [m/s]", "Fy [N]"))
    ok = True
    if any(not math.isfinite(v) for r in rows for v in r):
        print("FAIL: a value is not finite")
        return 1
    window = [r for r in rows if r[t] >= a.t0]
    if len(window) < 10:
        print(f"FAIL: fewer than 10 rows after t = {a.t0} s (the run ended at {rows[-1][t]} s)")
        return 1
    lo, hi = a.floor + a.radius - 1e-9, a.floor + a.radius * (1 + 1e-3)
    y_min, y_max = min(r[y] for r in window), max(r[y] for r in window)
    v_max = max(abs(r[vy]) for r in window)
    resting = sum(1 for r in window if abs(r[vy]) <= 1e-9) / len(window)
    print(f"centre over t >= {a.t0} s: {y_min:.9f} .. {y_max:.9f} m (on the floor: [{lo:.9f}, {hi:.9f}])")
    print(f"at rest (|v_y| <= 1e-9 m/s) in {100 * resting:.1f} % of the rows (>= 90 %); "
          f"largest vertical speed {v_max:.3e} m/s (<= 0.05)")
    if not (lo <= y_min and y_max <= hi):
        print("FAIL: the disk is not resting on the floor")
        ok = False
    if resting < 0.9 or v_max > 0.05:
        print("FAIL: the disk does not rest")
        ok = False
    area = math.pi * a.radius**2
    weight = a.density_ratio * a.rho_water * area * a.gravity
    buoyancy = a.rho_water * area * a.gravity
    f_mean = sum(r[fy] for r in window) / len(window)
    print(f"mean vertical fluid force {f_mean:.1f} N (Archimedes {buoyancy:.1f} N, weight {weight:.1f} N); "
          f"the wall's mean reaction {weight - f_mean:.1f} N")
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
