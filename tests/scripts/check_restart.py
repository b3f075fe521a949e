#!/usr/bin/env python3
"""Checkpoint/restart of an SPH run continues it bit for bit.

usage: check_restart.py TWINFLOW SCENE.prm WORKDIR T_CHECKPOINT ['SECTION/Entry=value' ...]

Run A: SCENE from t = 0 to its end time, writing a checkpoint every T_CHECKPOINT (the last one
before the end remains in checkpoint.bin). Run B: a copy of A's output directory, restarted
from that checkpoint into itself. The engine's whole state is x, u and p (the pressure warm
start), so B must reproduce A exactly: every monitor row (written with 12 digits), the ParaView
series and the summary's monitor values. Also checks that a restart with another particle
spacing is refused with an input error naming the entry.

The optional entries are set on every run (e.g. 'SPH/Density error correction=velocity'; whichever form a run uses, its
density-error pressure must also be restored or rebuilt exactly).

Snapshots (Scene/Snapshot times, two before and two after the checkpoint): B does not rewrite
the ones written before the restart time (a marker put into one survives) and writes the later
ones (removed from the copy) exactly as A did.
"""
import json
import os
import re
import shutil
import subprocess
import sys


def derived_scene(scene, path, extra):
    """SCENE with relative reference files made absolute and @p extra appended."""
    base = os.path.dirname(os.path.abspath(scene))
    text = []
    for line in open(scene):
        m = re.match(r"(\s*set\s+Front position file\s*=\s*)(\S.*)$", line)
        if m and not os.path.isabs(m.group(2).strip()):
            line = m.group(1) + os.path.normpath(os.path.join(base, m.group(2).strip())) + "\n"
        text.append(line)
    with open(path, "w") as f:
        f.write("".join(text) + "\n" + extra)


def fail(message, log=""):
    if log:
        print(log)
    print("FAIL: " + message)
    return 1


EXTRA = []  # --set entries of every run (command line)


def run(twinflow, prm, out):
    # the SPH checkpoint is under test: the scene's FEM half (Methods = fem, sph) is not run
    cmd = [twinflow, prm, "-o", out, "--set", "Scene/Methods=sph"]
    for entry in EXTRA:
        cmd += ["--set", entry]
    r = subprocess.run(cmd, capture_output=True, text=True)
    return r.returncode, r.stdout + r.stderr


SNAPSHOTS = "subsection Scene\n  set Snapshot times = 0, 0.05, 0.15, 0.18\nend\n"
SNAPSHOT_MARKER = "# marker put by check_restart.py: a restart must not rewrite this snapshot\n"


def check_snapshots(a_dir, b_dir, t0):
    """Snapshots before the restart time t0 kept (marker intact), later ones as in run A."""
    a_snap, b_snap = (os.path.join(d, "sph", "snapshots") for d in (a_dir, b_dir))
    names = sorted(os.listdir(a_snap))
    ok = names == ["sph_t0.000.csv", "sph_t0.050.csv", "sph_t0.150.csv", "sph_t0.180.csv"]
    print(f"{'ok' if ok else 'FAIL':5s} run A snapshots: {names}")
    for name in names:
        t = float(name[len("sph_t"):-len(".csv")])
        a, b = (open(os.path.join(d, name)).read() if os.path.exists(os.path.join(d, name)) else None
                for d in (a_snap, b_snap))
        if t <= t0:
            same = b == SNAPSHOT_MARKER if name == "sph_t0.050.csv" else b == a
            print(f"{'ok' if same else 'FAIL':5s} {name} (before the restart): {'kept' if same else 'rewritten'}")
        else:
            same = b == a
            print(f"{'ok' if same else 'FAIL':5s} {name} (after the restart): {'as run A' if same else 'different'}")
        ok = ok and same
    return ok


def main():
    twinflow, scene, work, interval = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])
    EXTRA.extend(sys.argv[5:])
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    a_dir, b_dir = os.path.join(work, "a"), os.path.join(work, "b")
    prm_a, prm_b, prm_bad = (os.path.join(work, n) for n in ("a.prm", "b.prm", "bad.prm"))
    derived_scene(scene, prm_a, f"subsection SPH\n  set Checkpoint interval = {interval}\nend\n" + SNAPSHOTS)
    rc, log = run(twinflow, prm_a, a_dir)
    if rc != 0:
        return fail("run A failed", log)
    checkpoint = os.path.join(a_dir, "sph", "checkpoint.bin")
    if not os.path.isfile(checkpoint):
        return fail("run A wrote no checkpoint.bin")
    shutil.copytree(a_dir, b_dir)
    os.remove(os.path.join(b_dir, "sph", "summary.json"))
    b_snap = os.path.join(b_dir, "sph", "snapshots")
    open(os.path.join(b_snap, "sph_t0.050.csv"), "w").write(SNAPSHOT_MARKER)
    for name in ("sph_t0.150.csv", "sph_t0.180.csv"):
        os.remove(os.path.join(b_snap, name))
    derived_scene(scene, prm_b,
                  f"subsection SPH\n  set Restart file = {os.path.join(b_dir, 'sph', 'checkpoint.bin')}\nend\n" + SNAPSHOTS)
    rc, log = run(twinflow, prm_b, b_dir)
    if rc != 0:
        return fail("run B (restart) failed", log)
    m = re.search(r"SPH restart from .*: t = (\S+) s, step (\d+)", log)
    if not m:
        return fail("run B did not report a restart", log)
    t0, s0 = float(m.group(1)), int(m.group(2))
    print(f"restarted at t = {t0} s, step {s0}")
    ok = 0 < s0
    sa, sb = (json.load(open(os.path.join(d, "sph", "summary.json"))) for d in (a_dir, b_dir))
    na, nb = (s["time_stepping"]["steps"] for s in (sa, sb))
    ok = ok and na == nb and na > s0
    print(f"steps: A {na}, B {nb} (restarted after {s0})")
    for name in ("energy.csv", "front.csv", "solver.csv", "particles.pvd"):
        fa, fb = ([line for line in open(os.path.join(d, "sph", name)).read().splitlines()
                   if "generated by the deal.II library" not in line] for d in (a_dir, b_dir))
        same = fa == fb
        rows = sum(1 for line in fa if line and (line[0].isdigit() or "DataSet" in line))
        print(f"{'ok' if same else 'FAIL':5s} {name}: {rows} rows, {'identical' if same else 'different'}")
        ok = ok and same
    ma, mb = sa.get("monitors", {}), sb.get("monitors", {})
    # values computed from the carried-over monitor rows (front error, noise average) see
    # them as written, with 12 significant digits
    # (a term that never acts, e.g. the velocity form's density-error displacement, is written as 0)
    def number(v):
        return isinstance(v, (int, float)) and not isinstance(v, bool)

    diff = [k for k in ma if not (number(ma[k]) and number(mb.get(k)) and
                                  abs(ma[k] - mb[k]) <= 1e-9 * max(abs(ma[k]), 1e-300))]
    print(f"{'ok' if not diff else 'FAIL':5s} summary monitors: {len(ma)} values agree to 1e-9, different: {diff}")
    ok = ok and not diff and len(ma) > 0
    ok = check_snapshots(a_dir, b_dir, t0) and ok

    # Another spacing: a clear input error, and the run's results stay as they are.
    spacing = float(re.search(r"set\s+Particle spacing\s*=\s*(\S+)", open(scene).read()).group(1)) * 5 / 6
    text = open(prm_b).read().replace("subsection SPH\n  set Restart", f"subsection SPH\n  set Particle spacing = {spacing}\n  set Restart")
    open(prm_bad, "w").write(text)
    before = open(os.path.join(b_dir, "sph", "energy.csv")).read()
    rc, log = run(twinflow, prm_bad, b_dir)
    refused = rc != 0 and "SPH/Restart file" in log and "Particle spacing" in log
    intact = open(os.path.join(b_dir, "sph", "energy.csv")).read() == before
    print(f"{'ok' if refused and intact else 'FAIL':5s} restart with another spacing: exit {rc}, "
          f"results {'intact' if intact else 'changed'}: {log.strip().splitlines()[-1] if log.strip() else ''}")
    ok = ok and refused and intact
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
