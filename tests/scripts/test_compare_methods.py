#!/usr/bin/env python3
"""benchmarks/falling_cylinder/compare_methods.py on synthetic body histories of known damping.

usage: test_compare_methods.py WORKDIR

Two body_cylinder.csv files: a lightly damped heave (the FEM's kind, damping ratio 0.06) and a
faster decaying one (the SPH's kind, 0.18), both about the Archimedes position with a period of
1.0 s, each with a force that settles on the weight plus step-to-step noise. The tool must
recover each damping ratio and period to 3 %, the equilibrium to 1e-4 m, the mean force to
1 % of the weight (3 standard deviations of the mean of the noise over the last quarter, plus
the undecayed force oscillation), draw one PNG, and refuse a history holding a NaN.
"""
import math
import os
import random
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from check_floating import equilibrium_centre  # noqa: E402
from testlib import check, failures, png_size  # noqa: E402

TOOL = os.path.join(HERE, "..", "..", "benchmarks", "falling_cylinder", "compare_methods.py")
HEADER = ("# twinflow monitor: body\n"
          "time [s],x [m],y [m],z [m],vx [m/s],vy [m/s],vz [m/s],Fx [N],Fy [N],Fz [N]\n")


def write_body(path, zeta, period, y_eq, weight, noise, seed, nan_at=None):
    rng = random.Random(seed)
    om_d = 2 * math.pi / period
    lam = zeta * om_d / math.sqrt(1 - zeta**2)  # zeta = lam / sqrt(lam^2 + om_d^2)
    with open(path, "w") as f:
        f.write(HEADER)
        for k in range(0, 6001):
            t = k * 1e-3
            y = y_eq - 0.2 * math.exp(-lam * t) * math.cos(om_d * t)
            fy = weight * (1 + 0.5 * math.exp(-lam * t) * math.cos(om_d * t)) + noise * rng.uniform(-1, 1)
            if nan_at is not None and k == nan_at:
                fy = float("nan")
            f.write(f"{t:.6e},0.5,{y:.9e},0.1,0,0,0,0,{fy:.9e},0\n")


def run(*args):
    r = subprocess.run([sys.executable, TOOL, *args], capture_output=True, text=True)
    return r.returncode, r.stdout + r.stderr


def main():
    work = sys.argv[1]
    os.makedirs(work, exist_ok=True)
    y_eq = equilibrium_centre(0.5, 1.0, 0.12, 0.7, True)
    weight = 0.7 * 1000 * 9.8 * math.pi * 0.12**2 * 0.2
    fem, sph, png = (os.path.join(work, n) for n in ("fem.csv", "sph.csv", "both.png"))
    write_body(fem, 0.06, 1.0, y_eq, weight, 2.0, 1)
    write_body(sph, 0.18, 1.0, y_eq, weight, 10.0, 2)
    code, out = run(fem, sph, png, "--from", "1.0")
    print(out)
    check(code == 0, "the tool runs on two histories")
    fits = re.findall(r"equilibrium ([0-9.]+) m .*?period ([0-9.]+) s, damping ratio ([0-9.]+)", out)
    check(len(fits) == 2, "a damped-oscillation fit for each method")
    for (y, period, zeta), expected in zip(fits, (0.06, 0.18)):
        check(abs(float(zeta) - expected) <= 0.03 * expected, f"damping ratio {zeta} recovers {expected} to 3 %")
        check(abs(float(period) - 1.0) <= 0.03, f"period {period} s recovers 1.0 s to 3 %")
        check(abs(float(y) - y_eq) <= 1e-4, f"equilibrium {y} m recovers {y_eq:.5f} m to 1e-4 m")
    forces = re.findall(r"mean F_y over t >= [0-9.]+ s: ([0-9.]+) N", out)
    check(len(forces) == 2 and all(abs(float(v) - weight) <= 0.01 * weight for v in forces),
          f"mean force over the last quarter within 1 % of the weight {weight:.2f} N: {forces}")
    size = png_size(png) if os.path.exists(png) else None
    check(size is not None and size[0] > 400 and size[1] > 300, f"one PNG drawn ({size})")
    bad = os.path.join(work, "nan.csv")
    write_body(bad, 0.06, 1.0, y_eq, weight, 2.0, 3, nan_at=2500)
    code, out = run(bad, sph, os.path.join(work, "nan.png"))
    check(code != 0 and "non-finite" in out, "a history holding a NaN is refused by name")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
