#!/usr/bin/env python3
"""The plot step of a run: references in the plots, snapshots, report.md (issue 15).

usage: test_run_report.py TWINFLOW WORKDIR MM_SCENE DFG_SCENE

1. The coarse Martin & Moyce dam break with both methods, shortened to 0.09 s, snapshots at
   0, 0.045 and 0.09 s:
   - plots/front.json: the x_front panel holds the FEM and SPH curves, each labelled with its
     raw and fitted error, and the reference table with all of its rows as points;
   - plots/front_Z_vs_T.png + .json: the front in the reference's own axes (Z against T) with
     the reference points and both methods' curves;
   - every PNG in plots/ has its JSON;
   - one snapshot PNG per requested time, all of one pixel size, each with the FEM panel
     (water region and its mesh cells) and the SPH panel;
   - report.md: every link names an existing file; it shows every PNG of plots/, the active
     physics of both methods, the cost rows (per 1000 steps, per simulated second) and the
     front errors of both methods.
2. DFG 2D-1 (FEM), 4 steps: plots/forces.json carries the reference C_d = References/Drag
   coefficient as a reference value, and the FEM curve's label its measured error.
3. plot_monitors.py with a reference table whose row has a wrong number of fields: exit
   status != 0 and a message naming the file and the line.
"""
import json
import math
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
from testlib import broken_links, check, failures, links, png_size  # noqa: E402

def run(cmd):
    proc = subprocess.run(cmd, capture_output=True, text=True)
    tail = (proc.stdout + proc.stderr).splitlines()[-12:]
    print("$ " + " ".join(cmd) + f"\n  exit {proc.returncode}\n" + "".join("  | " + l + "\n" for l in tail))
    return proc


def load(path):
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def panel(description, column):
    for p in description["panels"]:
        if p["y"].split(" [")[0] == column:
            return p
    return None


def table_rows(path):
    with open(path) as f:
        return sum(1 for l in f if l.strip() and not l.startswith("#")) - 1


def reference_file(scene):
    with open(scene) as f:
        for line in f:
            if line.strip().startswith("set Front position file"):
                return os.path.normpath(os.path.join(os.path.dirname(scene), line.split("=", 1)[1].strip()))
    return None


def dam_break(twinflow, work, scene):
    out = os.path.join(work, "dam_break")
    shutil.rmtree(out, ignore_errors=True)
    proc = run([twinflow, scene, "-o", out, "--set", "Scene/End time=0.09",
                "--set", "Scene/Snapshot times=0, 0.045, 0.09"])
    if not check(proc.returncode == 0, "the shortened Martin & Moyce run (FEM + SPH) succeeds"):
        return
    plots = os.path.join(out, "plots")
    n_reference = table_rows(reference_file(scene))

    # front.png: both runs with their errors, the reference table
    front = load(os.path.join(plots, "front.json"))
    p = panel(front, "x_front")
    if check(p is not None, "front.json has the x_front panel"):
        results = {s["source"]: s["label"] for s in p["series"] if s["kind"] == "result"}
        refs = [s for s in p["series"] if s["kind"] == "reference table"]
        check(set(results) == {"FEM", "SPH"}, f"x_front: FEM and SPH curves ({sorted(results)})")
        check(all("raw" in l and "time origin fitted" in l and "%" in l for l in results.values()),
              f"x_front: each curve's label carries its raw and fitted error ({list(results.values())})")
        check(len(refs) == 1 and refs[0]["points"] == n_reference and "Martin & Moyce" in refs[0]["label"],
              f"x_front: the Martin & Moyce table with its {n_reference} points ({refs})")

    # the reference's own axes: Z against T
    zt = os.path.join(plots, "front_Z_vs_T")
    if check(os.path.isfile(zt + ".png") and os.path.isfile(zt + ".json"), "front_Z_vs_T.png and .json"):
        d = load(zt + ".json")["panels"][0]
        check(d["x"].startswith("T") and d["y"].startswith("Z"), f"axes T and Z ({d['x']}, {d['y']})")
        check(any(s["kind"] == "reference table" and s["points"] == n_reference for s in d["series"]),
              "front_Z_vs_T: the reference points")
        check({s["source"] for s in d["series"] if s["kind"] == "result"} == {"FEM", "SPH"},
              "front_Z_vs_T: both methods")

    for png in sorted(f for f in os.listdir(plots) if f.endswith(".png")):
        check(os.path.isfile(os.path.join(plots, png[:-4] + ".json")), f"{png} has its JSON")

    # snapshots at the requested times, one pixel size, FEM with its mesh
    sizes = []
    for t in ("0.000", "0.045", "0.090"):
        png = os.path.join(plots, f"snapshot_t{t}.png")
        if check(os.path.isfile(png), f"snapshot at t = {t} s"):
            sizes.append(png_size(png))
            d = load(png[:-4] + ".json")
            methods = {e["method"]: e for e in d["panels"]}
            check(set(methods) == {"fem", "sph"}, f"t = {t}: FEM and SPH panels")
            fem = methods.get("fem", {})
            check(fem.get("filled") and fem.get("cells", 0) >= 1536,
                  f"t = {t}: FEM water region and its {fem.get('cells')} mesh cells drawn")
    check(len(set(sizes)) == 1 and sizes[0] is not None, f"every snapshot has one pixel size ({sizes})")

    # report.md
    report = os.path.join(out, "report.md")
    if not check(os.path.isfile(report), "report.md written"):
        return
    targets = links(report)
    check(not broken_links(report), f"report.md: every link names a file "
          f"(broken: {broken_links(report)})")
    pngs = sorted("plots/" + f for f in os.listdir(plots) if f.endswith(".png"))
    check(all(p in targets for p in pngs), f"report.md shows every PNG ({pngs})")
    with open(report, encoding="utf-8") as f:
        text = f.read()
    for method in ("fem", "sph"):
        physics = load(os.path.join(out, method, "summary.json"))["extra"]["active physics"]
        check(physics and physics in text, f"report.md: {method} active physics")
    check(text.count("| FEM | front position x_f(t)") == 2 and text.count("| SPH | front position x_f(t)") == 2,
          "report.md: raw and fitted front errors of both methods")
    check("per 1000 steps" in text and "per simulated second" in text, "report.md: the cost columns")


def dfg(twinflow, work, scene):
    out = os.path.join(work, "dfg")
    shutil.rmtree(out, ignore_errors=True)
    proc = run([twinflow, scene, "-o", out, "--set", "Scene/End time=0.2", "--set", "FEM/Time step=0.05",
                "--set", "FEM/Global refinements=0"])
    if not check(proc.returncode == 0, "the shortened DFG 2D-1 run succeeds"):
        return
    with open(scene) as f:
        cd = [float(l.split("=")[1]) for l in f if l.strip().startswith("set Drag coefficient")][0]
    p = panel(load(os.path.join(out, "plots", "forces.json")), "C_d")
    if check(p is not None, "forces.json has the C_d panel"):
        values = [s for s in p["series"] if s["kind"] == "reference value"]
        check(len(values) == 1 and math.isclose(values[0]["value"], cd, rel_tol=1e-9),
              f"C_d: the reference value {cd} ({values})")
        results = [s["label"] for s in p["series"] if s["kind"] == "result"]
        check(len(results) == 1 and "error" in results[0] and "%" in results[0],
              f"C_d: the FEM curve's label carries its error ({results})")


def bad_reference(work):
    bad = os.path.join(work, "bad_reference.csv")
    with open(bad, "w") as f:
        f.write("T,Z\n0.4,1.1\n0.8,1.2,7\n")
    empty = os.path.join(work, "empty_run")
    os.makedirs(empty, exist_ok=True)
    proc = run(["/usr/bin/python3", os.path.join(ROOT, "scripts", "plot_monitors.py"), empty,
                "--reference", bad, "--ref-x", "T", "--ref-y", "Z", "--monitor", "front", "--column", "x_front"])
    check(proc.returncode != 0 and "bad_reference.csv" in proc.stderr and "line 3 has 3 fields" in proc.stderr,
          "a reference row with a wrong field count: an error naming the file and the line")


def main():
    twinflow, work, mm_scene, dfg_scene = sys.argv[1:5]
    os.makedirs(work, exist_ok=True)
    dam_break(twinflow, work, mm_scene)
    dfg(twinflow, work, dfg_scene)
    bad_reference(work)
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
