#!/usr/bin/env python3
"""A FEM run with a rigid body restarted from a checkpoint continues as the uninterrupted one.

usage: check_body_restart.py TWINFLOW SCENE.prm WORKDIR T_CHECKPOINT T_END

Run U: SCENE (FEM only) from 0 to T_END. Run R: 0 to T_CHECKPOINT with a checkpoint there,
then restarted from it into its own directory up to T_END. The checkpoint carries the bodies'
state (position, orientation, velocity, angular momentum, last accelerations for the added
mass) and the loads they last moved under, so every row of R's body CSV (kept up to the restart,
written after it) must equal U's: to 1e-9 of each column's scale (the solves stop at relative
tolerances, so bit equality is not asked of the parallel reductions). Columns that are zero up
to round-off (a disk released on its axis keeps x and the angle at 1e-13) are compared against
the column's scale, not their own.
"""
import csv
import os
import shutil
import subprocess
import sys


# columns whose values are round-off for a body released on its axis (x, angle, torque, ...)
# are measured against their physical family: lengths and angles, speeds, forces and torques
GROUP = {"m": "length", "rad": "length", "-": "length", "m/s": "speed", "rad/s": "speed", "N": "load",
         "N m": "load", "J": "energy", "s": "time"}


def rows(path):
    with open(path) as f:
        data = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    return data[0], [[float(v) for v in r] for r in data[1:]]


def run(twinflow, scene, out, *sets):
    args = [twinflow, scene, "--set", "Scene/Methods=fem", "--set", "Scene/Output interval=0",
            "--set", f"Scene/Output directory={out}"]
    for s in sets:
        args += ["--set", s]
    r = subprocess.run(args, capture_output=True, text=True)
    if r.returncode != 0:
        print(r.stdout + r.stderr)
        sys.exit(f"FAIL: {' '.join(args)} exited with {r.returncode}")
    return r.stdout


def main():
    twinflow, scene, work, t_cp, t_end = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    u, r = os.path.join(work, "u"), os.path.join(work, "r")
    run(twinflow, scene, u, f"Scene/End time={t_end}")
    run(twinflow, scene, r, f"Scene/End time={t_cp}", f"FEM/Checkpoint interval={t_cp}")
    log = run(twinflow, scene, r, f"Scene/End time={t_end}", f"FEM/Restart file={r}/fem/checkpoint")
    if "FEM restart from" not in log:
        sys.exit("FAIL: the second run did not report a restart")
    names = [n for n in os.listdir(os.path.join(u, "fem")) if n.startswith("body_") and n.endswith(".csv")]
    if not names:
        sys.exit("FAIL: no body CSV in the uninterrupted run")
    ok = True
    for name in names:
        head, a = rows(os.path.join(u, "fem", name))
        _, b = rows(os.path.join(r, "fem", name))
        if len(a) != len(b) or len(a) < 3:
            print(f"FAIL  {name}: {len(a)} rows uninterrupted, {len(b)} restarted")
            ok = False
            continue
        own = [max(abs(row[k]) for row in a) for k in range(len(head))]
        group = [GROUP.get(h[h.find("[") + 1:h.find("]")], h) for h in head]
        scale = [max(own[k], max(own[j] for j in range(len(head)) if group[j] == group[k]), 1e-30)
                 for k in range(len(head))]
        worst, where = 0.0, ""
        for ra, rb in zip(a, b):
            for k in range(len(head)):
                d = abs(ra[k] - rb[k]) / scale[k]
                if d > worst:
                    worst, where = d, f"{head[k]} at t = {ra[0]}"
        good = worst <= 1e-9
        ok = ok and good
        print(f"{'ok' if good else 'FAIL':5s} {name}: {len(a)} rows, largest difference {worst:.2e} of the column scale"
              f" ({where}); bound 1e-9")
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
