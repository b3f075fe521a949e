#!/usr/bin/env python3
"""Floating equilibrium of a 2D disk (Archimedes) from a body_<name>.csv monitor.

usage: check_floating.py BODY_CSV --depth H --width W --radius R --density-ratio S
                         [--from T0] [--position-tolerance F] [--force-tolerance F]
                         [--water-rises]

The disk of radius R and density S rho_w floats with a fraction S of its area below the
waterline: its centre lies d below it, where the dry cap's half-angle a solves
(2a - sin 2a) / (2 pi) = 1 - S and d = -R cos a. With --water-rises the waterline is the
still-water depth H lifted by the displaced area S pi R^2 / W (the disk started out of the
water); otherwise H. Over t >= T0 the time-averaged centre must lie within F R of that
(default 2 %) and the mean vertical fluid force within F of the weight (default 2 %); every
value must be finite.

With --bounded-only H (hard cases: a violent entry that has not settled by the end) only
boundedness is checked: every value finite and the body's kinetic energy never above its
initial value plus the work gravity and buoyancy can do over the height H of the tank,
(m g + rho_w g V) H; an unstable coupling or fluid exceeds that by orders of magnitude.
"""
import argparse
import math
import sys

sys.path.insert(0, __import__("os").path.join(__import__("os").path.dirname(__file__), "..", "..", "scripts"))
from twinflow_csv import read  # noqa: E402


def equilibrium_centre(depth, width, radius, ratio, water_rises):
    # dry cap: half-angle a, area fraction (2a - sin 2a) / (2 pi) = 1 - ratio (bisection)
    lo, hi = 0.0, math.pi
    for _ in range(200):
        a = 0.5 * (lo + hi)
        if (2 * a - math.sin(2 * a)) / (2 * math.pi) < 1 - ratio:
            lo = a
        else:
            hi = a
    a = 0.5 * (lo + hi)
    waterline = depth + (ratio * math.pi * radius**2 / width if water_rises else 0.0)
    return waterline - radius * math.cos(a)  # the centre lies R cos a below the waterline


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("csv")
    p.add_argument("--depth", type=float, required=True)
    p.add_argument("--width", type=float, required=True)
    p.add_argument("--radius", type=float, required=True)
    p.add_argument("--density-ratio", type=float, required=True)
    p.add_argument("--gravity", type=float, default=9.8)
    p.add_argument("--length", type=float, default=1.0,
                   help="axial length of a 3D cylinder spanning the depth (forces in N, not N/m)")
    p.add_argument("--rho-water", type=float, default=1000.0)
    p.add_argument("--from", dest="t0", type=float, default=0.0)
    p.add_argument("--position-tolerance", type=float, default=0.02)
    p.add_argument("--force-tolerance", type=float, default=0.02)
    p.add_argument("--water-rises", action="store_true")
    p.add_argument("--bounded-only", type=float, default=None, metavar="H")
    a = p.parse_args()
    header, rows = read(a.csv)
    names = [h.split(" [")[0] for h in header]
    cols = {n: [r[k] for r in rows] for k, n in enumerate(names)}
    t, y, fy = cols["time"], cols["y"], cols["Fy"]
    for name, values in cols.items():
        if any(not math.isfinite(v) for v in values):
            print(f"FAIL: column '{name}' of {a.csv} holds a non-finite value")
            return 1
    if a.bounded_only is not None:
        volume = math.pi * a.radius**2 * a.length
        mass = a.density_ratio * a.rho_water * volume
        bound = cols["kinetic energy"][0] + (mass + a.rho_water * volume) * a.gravity * a.bounded_only
        peak = max(cols["kinetic energy"])
        print(f"body kinetic energy: peak {peak:.3f} J, bound {bound:.3f} J (initial + (m g + rho_w g V) H); "
              f"lowest centre {min(y):.4f} m")
        print("PASS" if peak <= bound else "FAIL")
        return 0 if peak <= bound else 1
    # time averages (trapezoid) over t >= t0
    sy = sf = st = 0.0
    for k in range(1, len(t)):
        if t[k - 1] >= a.t0:
            dt = t[k] - t[k - 1]
            sy += 0.5 * (y[k] + y[k - 1]) * dt
            sf += fy[k] * dt  # the load of step k acts over that step
            st += dt
    if st <= 0:
        print(f"FAIL: no rows after t = {a.t0}")
        return 1
    mean_y, mean_f = sy / st, sf / st
    yc = equilibrium_centre(a.depth, a.width, a.radius, a.density_ratio, a.water_rises)
    weight = a.density_ratio * a.rho_water * math.pi * a.radius**2 * a.length * a.gravity
    dy = abs(mean_y - yc) / a.radius
    df = abs(mean_f - weight) / weight
    window = [v for tk, v in zip(t, y) if tk >= a.t0]
    print(f"mean centre {mean_y:.5f} m (Archimedes {yc:.5f} m): {100 * dy:.2f} % of R (tolerance "
          f"{100 * a.position_tolerance:.1f} %); oscillation {min(window):.4f}..{max(window):.4f} m")
    print(f"mean vertical fluid force {mean_f:.2f} N (weight {weight:.2f} N): {100 * df:.2f} % (tolerance "
          f"{100 * a.force_tolerance:.1f} %)")
    ok = dy <= a.position_tolerance and df <= a.force_tolerance
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
