#!/usr/bin/env python3
"""Test of scripts/plot_snapshots.py and of the run's snapshot plot step.

usage: test_plot_snapshots.py WORKDIR [TWINFLOW SCENE.prm]

1. Synthetic run directory: FEM level sets (x, y, phi; water phi < 0) at t = 0 and 0.5 and SPH
   particles (x, y, speed, pressure, kind) at t = 0, 0.5 and 1. One PNG per time, all of the
   same pixel size; the JSON beside each lists the panels drawn (FEM above SPH where both
   exist) with the right node, water-node, particle and marker counts, the same speed scale
   for every time (the largest fluid speed: the markers' are ignored), and the PNG shows the
   water colour only where the FEM has water. --speed-max sets the scale; a snapshot without
   the phi column is an error naming the file; a run without snapshots draws nothing.
2. With TWINFLOW and SCENE: a short SPH run of SCENE with Scene/Snapshot times set writes the
   snapshots and its plot step draws them into <output>/plots.
"""
import json
import os
import shutil
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from testlib import png_size  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(ROOT, "scripts", "plot_snapshots.py")
WATER_RGB = (0x3B, 0x7D, 0xD8)


def run(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


def water_pixels(path):
    import matplotlib.image as mpimg
    rgb = (mpimg.imread(path)[:, :, :3] * 255).round()
    return int(np.all(np.abs(rgb - np.array(WATER_RGB)) <= 2, axis=2).sum())


def write_fem(path, water_width):
    """Nodes of a 41 x 21 grid on [0, 2] x [0, 1]; water x < water_width, y < 0.5 (none if 0)."""
    x, y = np.meshgrid(np.linspace(0, 2, 41), np.linspace(0, 1, 21))
    phi = np.maximum(x - water_width, y - 0.5) if water_width > 0 else np.full(x.shape, 0.3)
    with open(path, "w") as f:
        f.write("# synthetic FEM level set\nx,y,phi\n")
        for a, b, c in zip(x.ravel(), y.ravel(), phi.ravel()):
            f.write(f"{a},{b},{c}\n")
    return int((phi < 0).sum()), x.size


def write_sph(path, top_speed):
    """Fluid block on [0, 0.5] x [0, 0.5] (spacing 0.05), speeds up to top_speed; a wall
    row below the floor (speed 99: must not set the colour scale)."""
    rows = []
    for i in range(10):
        for j in range(10):
            rows.append((0.025 + 0.05 * i, 0.025 + 0.05 * j, top_speed * (i + j) / 18.0, 1000.0, 0))
    for i in range(-2, 42):
        rows.append((0.025 + 0.05 * i, -0.025, 99.0, 0.0, 1))
    with open(path, "w") as f:
        f.write("# twinflow SPH snapshot (synthetic)\n# kind: 0 = fluid, 1 = wall\n")
        f.write("x [m],y [m],speed [m/s],pressure [Pa],kind\n")
        for r in rows:
            f.write(",".join(str(v) for v in r) + "\n")
    return 100, 44


def synthetic(work, failures):
    run_dir = os.path.join(work, "synthetic")
    fem, sph = os.path.join(run_dir, "fem", "snapshots"), os.path.join(run_dir, "sph", "snapshots")
    os.makedirs(fem)
    os.makedirs(sph)
    expected_fem = {"0.000": write_fem(os.path.join(fem, "fem_t0.000.csv"), 0.8),
                    "0.500": write_fem(os.path.join(fem, "fem_t0.500.csv"), 0.0)}
    expected_sph = {t: write_sph(os.path.join(sph, f"sph_t{t}.csv"), v)
                    for t, v in (("0.000", 0.0), ("0.500", 2.5), ("1.000", 1.5))}
    r = run(run_dir)
    if r.returncode != 0:
        failures.append(f"plot_snapshots.py failed: {r.stdout} {r.stderr}")
        return
    plots = os.path.join(run_dir, "plots")
    sizes = set()
    for t in ("0.000", "0.500", "1.000"):
        png, js = (os.path.join(plots, f"snapshot_t{t}.{e}") for e in ("png", "json"))
        if not os.path.isfile(png) or not os.path.isfile(js):
            failures.append(f"t = {t}: no PNG or JSON in {plots}")
            continue
        size = png_size(png)
        sizes.add(size)
        rec = json.load(open(js))
        methods = [p["method"] for p in rec["panels"]]
        want = ["fem", "sph"] if t in expected_fem else ["sph"]
        if methods != want:
            failures.append(f"t = {t}: panels {methods}, expected {want} (FEM above SPH)")
        if abs(rec["time"] - float(t)) > 1e-12 or rec["size_px"] != list(size):
            failures.append(f"t = {t}: JSON time {rec['time']} / size {rec['size_px']} vs PNG {size}")
        if rec["speed_range"] != [0.0, 2.5]:
            failures.append(f"t = {t}: speed scale {rec['speed_range']}, expected the largest fluid speed [0, 2.5]")
        for p in rec["panels"]:
            if p["method"] == "sph":
                got = (p["fluid_particles"], p["wall_markers"])
                if got != expected_sph[t]:
                    failures.append(f"t = {t}: SPH panel counts {got}, expected {expected_sph[t]}")
            else:
                water, nodes = expected_fem[t]
                got = (p["water_nodes"], p["nodes"], p["filled"], p["interface"])
                if got != (water, nodes, water > 0, water > 0):
                    failures.append(f"t = {t}: FEM panel {got}, expected {(water, nodes, water > 0, water > 0)}")
        wet = water_pixels(png)
        # water 0.8 x 0.5 of the 2 x 1 FEM panel: thousands of pixels; none without water
        if (t == "0.000" and wet < 2000) or (t != "0.000" and wet > 0):
            failures.append(f"t = {t}: {wet} pixels of the water colour")
        print(f"t = {t}: {size[0]} x {size[1]} px, panels {methods}, water pixels {wet}")
    if len(sizes) != 1:
        failures.append(f"the PNGs differ in size: {sizes}")
    r = run(run_dir, "--speed-max", "4", "--out", os.path.join(work, "fixed"))
    rec = json.load(open(os.path.join(work, "fixed", "snapshot_t0.500.json"))) if r.returncode == 0 else {}
    if rec.get("speed_range") != [0.0, 4.0]:
        failures.append(f"--speed-max 4: speed scale {rec.get('speed_range')} ({r.stderr})")
    with open(os.path.join(fem, "fem_t0.500.csv"), "w") as f:
        f.write("x,y,level\n0,0,1\n")
    r = run(run_dir)
    if r.returncode != 2 or "fem_t0.500.csv" not in r.stderr or "phi" not in r.stderr:
        failures.append(f"a FEM snapshot without phi must be an error naming it: {r.returncode} {r.stderr}")
    empty = os.path.join(work, "empty")
    os.makedirs(os.path.join(empty, "sph"))
    r = run(empty)
    if r.returncode != 0 or "nothing drawn" not in r.stdout or os.path.exists(os.path.join(empty, "plots")):
        failures.append(f"a run without snapshots must draw nothing: {r.returncode} {r.stdout} {r.stderr}")


def twinflow_run(work, twinflow, scene, failures):
    out = os.path.join(work, "run")
    env = dict(os.environ, TWINFLOW_PYTHON=sys.executable)
    r = subprocess.run([twinflow, scene, "-o", out, "--set", "Scene/Methods=sph", "--set", "Scene/End time=0.03",
                        "--set", "Scene/Snapshot times=0.02, 0"], capture_output=True, text=True, env=env)
    if r.returncode != 0:
        failures.append(f"twinflow run failed: {r.stdout[-2000:]} {r.stderr}")
        return
    for t in ("0.000", "0.020"):
        csv = os.path.join(out, "sph", "snapshots", f"sph_t{t}.csv")
        png = os.path.join(out, "plots", f"snapshot_t{t}.png")
        if not os.path.isfile(csv) or not os.path.isfile(png):
            failures.append(f"twinflow run: missing {csv} or {png}")
            continue
        rec = json.load(open(png[:-4] + ".json"))
        n_fluid = sum(1 for line in open(csv) if line.rstrip().endswith(",0"))
        if [p["method"] for p in rec["panels"]] != ["sph"] or rec["panels"][0]["fluid_particles"] != n_fluid:
            failures.append(f"twinflow run, t = {t}: JSON {rec['panels']}, {n_fluid} fluid rows in the CSV")
        print(f"twinflow run: t = {t}: {n_fluid} fluid particles drawn, {png_size(png)} px")


def main():
    work = sys.argv[1]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    failures = []
    synthetic(work, failures)
    if len(sys.argv) > 3:
        twinflow_run(work, sys.argv[2], sys.argv[3], failures)
    for f in failures:
        print("FAIL", f)
    print("plot_snapshots: ok" if not failures else f"plot_snapshots: {len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
