#!/usr/bin/env python3
"""Test of scripts/study_series.py: two series selected from a study.csv by '=' and '!='
filters end up in the table with the right cases, the PNG is written, and a bad filter (an
unknown column, a condition without '=') is an error naming it.

usage: test_study_series.py WORKDIR
"""
import csv
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(ROOT, "scripts", "study_series.py")


def run(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


def main():
    work = sys.argv[1]
    os.makedirs(work, exist_ok=True)
    study = os.path.join(work, "study.csv")
    cols = ["case", "folder", "FEM/Mesh adaptation/Maximum level", "method", "cells", "dofs", "steps",
            "wall time [s]", "error drag coefficient C_d", "status"]
    rows = [[1, "a", 4, "fem", 460, 4571, 671, 9.1, 0.0488, "ok"],
            [2, "b", 5, "fem", 868, 8495, 700, 20.2, 0.0215, "ok"],
            [3, "c", 0, "fem", 2560, 23603, 672, 48.6, 0.0497, "ok"],
            [4, "d", 0, "fem", 10240, 93283, 702, 258, 0.0223, "ok"],
            [5, "e", 6, "fem", 0, 0, 0, 0, "", "diverged"]]
    with open(study, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        w.writerows(rows)
    prefix = os.path.join(work, "series")
    r = run(study, "--series", "band:FEM/Mesh adaptation/Maximum level!=0",
            "--series", "uniform:FEM/Mesh adaptation/Maximum level=0", "--out", prefix)
    failures = []
    if r.returncode != 0:
        failures.append(f"good call failed: {r.stderr}")
    else:
        table = open(prefix + ".md").read().splitlines()[2:]
        band = [l.split("|")[2].strip() for l in table if l.startswith("| band")]
        uniform = [l.split("|")[2].strip() for l in table if l.startswith("| uniform")]
        if band != ["1", "2"]:
            failures.append(f"band series holds cases {band}, expected 1, 2 (5 diverged: left out)")
        if uniform != ["3", "4"]:
            failures.append(f"uniform series holds cases {uniform}, expected 3, 4")
        if not os.path.getsize(prefix + ".png") > 1000:
            failures.append("no PNG")
    # an SPH study: no cells, the size is the particle count (table column and x axis)
    sph = os.path.join(work, "study_sph.csv")
    with open(sph, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["case", "folder", "SPH/Energy-conserving pair", "method", "cells", "dofs", "particles", "steps",
                    "wall time [s]", "error energy rise", "status"])
        w.writerows([[1, "a", "false", "sph", "", "", 2156, 720, 4.3, 0.0214, "ok"],
                     [2, "b", "false", "sph", "", "", 896, 360, 1.0, 0.0475, "ok"],
                     [3, "c", "true", "sph", "", "", 896, 360, 4.8, 0.0061, "ok"]])
    r = run(sph, "--series", "default:SPH/Energy-conserving pair=false", "--series",
            "pair:SPH/Energy-conserving pair=true", "--quantity", "energy rise", "--out", prefix + "_sph")
    if r.returncode != 0:
        failures.append(f"SPH study failed: {r.stderr}")
    else:
        lines = open(prefix + "_sph.md").read().splitlines()
        if "| particles |" not in lines[0]:
            failures.append(f"SPH table's size column is not 'particles': {lines[0]}")
        default = [(l.split("|")[2].strip(), l.split("|")[3].strip()) for l in lines[2:] if l.startswith("| default")]
        if default != [("2", "896"), ("1", "2,156")]:
            failures.append(f"SPH default series {default}, expected cases 2 then 1 by particle count")
    r = run(study, "--series", "x:No such column=1", "--out", prefix)
    if r.returncode == 0 or "No such column" not in (r.stderr + r.stdout):
        failures.append(f"an unknown column must be an error naming it: {r.returncode} {r.stderr}")
    r = run(study, "--series", "x:FEM/Mesh adaptation/Maximum level", "--out", prefix)
    if r.returncode == 0 or "has no '=' or '!='" not in (r.stderr + r.stdout):
        failures.append(f"a condition without '=' must be an error: {r.returncode} {r.stderr}")
    for f in failures:
        print("FAIL", f)
    print("study_series: ok" if not failures else f"study_series: {len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
