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

With --fit-oscillation the centre is instead the equilibrium y_eq of the damped oscillation
y(t) = y_eq + e^(-lambda t) (a cos w t + b sin w t) fitted by least squares to t >= T0: a
lightly damped heave (the FEM's) biases a time average over a window that is not a whole
number of periods by up to its amplitude over the number of periods. The fit also gives the
period and the damping ratio lambda / sqrt(lambda^2 + w^2), which compare the methods' damping.

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


def solve3(m, r):
    # Gaussian elimination with partial pivoting of a 3x3 system
    a = [row[:] + [v] for row, v in zip(m, r)]
    for c in range(3):
        piv = max(range(c, 3), key=lambda k: abs(a[k][c]))
        a[c], a[piv] = a[piv], a[c]
        if abs(a[c][c]) < 1e-300:
            return None
        for k in range(c + 1, 3):
            f = a[k][c] / a[c][c]
            for j in range(c, 4):
                a[k][j] -= f * a[c][j]
    x = [0.0] * 3
    for c in (2, 1, 0):
        x[c] = (a[c][3] - sum(a[c][j] * x[j] for j in range(c + 1, 3))) / a[c][c]
    return x


def fit_damped_oscillation(t, y, w):
    """Least squares y ~ y_eq + e^(-lam s)(a cos om s + b sin om s), s = t - t[0], weights w:
    linear in (y_eq, a, b), a grid over (om, lam) refined three times around the best.
    Returns (y_eq, om, lam, amplitude at t[0], rms residual)."""
    s = [tk - t[0] for tk in t]
    # first guess of the frequency: mean spacing of the upward mean crossings
    mean = sum(yk * wk for yk, wk in zip(y, w)) / sum(w)
    ups = [s[k] for k in range(1, len(s)) if y[k - 1] < mean <= y[k]]
    span = s[-1] if s[-1] > 0 else 1.0
    om0 = 2 * math.pi * (len(ups) - 1) / (ups[-1] - ups[0]) if len(ups) >= 2 else 2 * math.pi / span

    def residual(om, lam):
        m = [[0.0] * 3 for _ in range(3)]
        r = [0.0] * 3
        for sk, yk, wk in zip(s, y, w):
            e = math.exp(-lam * sk)
            phi = (1.0, e * math.cos(om * sk), e * math.sin(om * sk))
            for i in range(3):
                r[i] += wk * phi[i] * yk
                for j in range(3):
                    m[i][j] += wk * phi[i] * phi[j]
        x = solve3(m, r)
        if x is None:
            return float("inf"), None
        res = 0.0
        for sk, yk, wk in zip(s, y, w):
            e = math.exp(-lam * sk)
            res += wk * (yk - x[0] - e * (x[1] * math.cos(om * sk) + x[2] * math.sin(om * sk))) ** 2
        return res, x

    best = (float("inf"), om0, 0.0, None)
    om_lo, om_hi, lam_lo, lam_hi = 0.5 * om0, 1.5 * om0, 0.0, om0
    for _ in range(4):
        for i in range(21):
            om = om_lo + (om_hi - om_lo) * i / 20
            for j in range(21):
                lam = lam_lo + (lam_hi - lam_lo) * j / 20
                res, x = residual(om, lam)
                if res < best[0]:
                    best = (res, om, lam, x)
        _, om, lam, _ = best
        dom, dlam = (om_hi - om_lo) / 10, (lam_hi - lam_lo) / 10
        om_lo, om_hi, lam_lo, lam_hi = om - dom, om + dom, max(0.0, lam - dlam), lam + dlam
    res, om, lam, x = best
    rms = math.sqrt(res / sum(w))
    return x[0], om, lam, math.hypot(x[1], x[2]), rms


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
    p.add_argument("--fit-oscillation", action="store_true")
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
    if a.fit_oscillation:
        # at most ~800 samples of the window, each weighted by the time it stands for
        idx = [k for k in range(len(t)) if t[k] >= a.t0]
        idx = idx[:: max(1, len(idx) // 800)]
        tw, yw = [t[k] for k in idx], [y[k] for k in idx]
        ww = [0.5 * ((tw[min(k + 1, len(tw) - 1)] - tw[k]) + (tw[k] - tw[max(k - 1, 0)])) for k in range(len(tw))]
        y_eq, om, lam, amp, rms = fit_damped_oscillation(tw, yw, ww)
        zeta = lam / math.hypot(lam, om)
        print(f"time average {mean_y:.5f} m ({100 * abs(mean_y - yc) / a.radius:.2f} % of R from Archimedes)")
        print(f"damped-oscillation fit over t >= {a.t0}: equilibrium {y_eq:.5f} m, amplitude {amp:.4f} m at "
              f"t = {a.t0}, period {2 * math.pi / om:.4f} s, damping ratio {zeta:.4f}, rms residual {rms:.2e} m")
        mean_y = y_eq
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
