#!/usr/bin/env python3
"""Test of the study runner (scripts/study.py) on a tiny FEM scene.

usage: test_study.py TWINFLOW WORKDIR

1. DFG 2D-1 at 0 and 1 global refinements, 4 steps of 0.05 s: the study writes one folder
   per case, study.csv with one row per case (the varied entry, method, cells, DoFs growing
   with the level, steps, wall time, time per step, the monitors and one error column per
   reference quantity, status ok), study.md, one PNG per error quantity, progress lines with
   an ETA; check_study.py accepts the table.
2. --plot-only re-collects the same table and redraws the plots.
3. A case that fails at run time (a pressure probe inside the cylinder, outside the mesh)
   stays in the table with its status and message; no case ran: exit status 3.
4. A typo in a --vary entry stops the study before any case runs (twinflow --check), with
   twinflow's message.
"""
import csv
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from testlib import broken_links, check, failures, links  # noqa: E402
ROOT = os.path.dirname(os.path.dirname(HERE))
PY = sys.executable
STUDY = os.path.join(ROOT, "scripts", "study.py")
SCENE = os.path.join(ROOT, "parameters", "dfg_2d1.prm")
SHORT = ["--set", "Scene/End time=0.2", "--set", "FEM/Time step=0.05"]

def run(args):
    proc = subprocess.run([PY, STUDY] + args, capture_output=True, text=True)
    print(f"$ study.py {' '.join(args)}\n  exit {proc.returncode}\n" +
          "".join("  | " + l + "\n" for l in (proc.stdout + proc.stderr).splitlines()))
    return proc


def read_csv(path):
    with open(path, newline="") as f:
        r = csv.DictReader(f)
        return r.fieldnames, list(r)


def is_png(path):
    try:
        with open(path, "rb") as f:
            return f.read(8) == b"\x89PNG\r\n\x1a\n" and os.path.getsize(path) > 1000
    except OSError:
        return False


def main():
    twinflow, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)

    # 1. two refinement levels
    out = os.path.join(work, "levels")
    proc = run([SCENE, "--vary", "FEM/Global refinements=0,1", *SHORT, "--out", out, "--twinflow", twinflow])
    check(proc.returncode == 0, "study of levels 0, 1 exits with 0")
    check("[1/2]" in proc.stdout and "ETA" in proc.stdout and "[2/2]" in proc.stdout,
          "progress lines [k/n] with an ETA")
    header, rows = read_csv(os.path.join(out, "study.csv"))
    check(len(rows) == 2, f"study.csv has one row per case (2): {len(rows)}")
    for col in ("case", "folder", "FEM/Global refinements", "method", "cells", "dofs", "particles", "steps",
                "wall time [s]", "time per step [s]", "status", "message"):
        check(col in header, f"study.csv has the column '{col}'")
    errors = [h for h in header if h.startswith("error ")]
    check(len(errors) >= 1, f"study.csv has error columns: {errors}")
    check(any(h.startswith("monitor ") for h in header), "study.csv has monitor columns")
    if len(rows) == 2 and all(c in header for c in ("dofs", "wall time [s]", "status")):
        check([r["FEM/Global refinements"] for r in rows] == ["0", "1"], "the rows are the levels 0, 1")
        check(all(r["method"] == "fem" and r["status"] == "ok" for r in rows), "both cases: fem, status ok")
        check(all(float(r["wall time [s]"]) > 0 and float(r["time per step [s]"]) > 0 for r in rows),
              "wall time and time per step > 0")
        check(all(r["steps"] == "4" for r in rows), "4 steps per case (the --set end time and step)")
        check(0 < int(rows[0]["dofs"]) < int(rows[1]["dofs"]) and int(rows[0]["cells"]) < int(rows[1]["cells"]),
              f"DoFs grow with the level: {rows[0]['dofs']} < {rows[1]['dofs']}")
        for e in errors:
            check(all(float(r[e]) >= 0 for r in rows), f"'{e}' is a number in every row")
    for r in rows:
        folder = os.path.join(out, r["folder"])
        check(os.path.isfile(os.path.join(folder, "fem", "summary.json")) and
              os.path.isfile(os.path.join(folder, "log.txt")), f"{r['folder']}/ holds fem/summary.json and log.txt")
    check(sorted(os.listdir(out))[:2] == ["case_1_refinements0", "case_2_refinements1"],
          f"case folders case_<k>_<short name>: {sorted(os.listdir(out))}")
    pngs = sorted(f for f in os.listdir(out) if f.endswith(".png"))
    check(len(pngs) == len(errors) and all(is_png(os.path.join(out, p)) for p in pngs),
          f"one PNG per error quantity: {pngs}")
    with open(os.path.join(out, "study.md")) as f:
        md = f.read()
    check(md.count("\n| ") == 3 and "`FEM/Global refinements`" in md, "study.md: header + 2 rows")
    report = os.path.join(out, "report.md")
    if check(os.path.isfile(report), "report.md written"):
        targets = links(report)
        check(not broken_links(report), f"report.md: every link names a file ({targets})")
        check(all(p in targets for p in pngs) and "study.csv" in targets,
              "report.md shows every error-against-time plot and links study.csv")
        check(sum(t.endswith("/report.md") for t in targets) == 2, "report.md links the 2 cases' reports")
    proc = subprocess.run([PY, os.path.join(HERE, "check_study.py"), os.path.join(out, "study.csv")],
                          capture_output=True, text=True)
    check(proc.returncode == 0, "check_study.py accepts the table:\n" + proc.stdout)

    # 2. --plot-only
    with open(os.path.join(out, "study.csv")) as f:
        table = f.read()
    for p in pngs + ["study.csv", "study.md"]:
        os.remove(os.path.join(out, p))
    proc = run(["--plot-only", out])
    check(proc.returncode == 0, "--plot-only exits with 0")
    with open(os.path.join(out, "study.csv")) as f:
        check(f.read() == table, "--plot-only re-collects the same study.csv")
    check(all(is_png(os.path.join(out, p)) for p in pngs) and os.path.isfile(os.path.join(out, "study.md")),
          "--plot-only redraws the PNGs and study.md")

    # 3. a failing case is kept
    out = os.path.join(work, "failing")
    proc = run([SCENE, "--vary", "Monitors/Pressure probes=0.2, 0.2; 0.25, 0.2|", "--set", "FEM/Global refinements=0",
                *SHORT, "--out", out, "--twinflow", twinflow])
    check(proc.returncode == 3, f"no case ran: exit status 3 (got {proc.returncode})")
    header, rows = read_csv(os.path.join(out, "study.csv"))
    check(len(rows) == 1 and rows[0]["status"].startswith("failed") and "probe" in rows[0]["message"].lower(),
          f"the failed case is in the table with status and message: {rows}")

    # 4. a typo stops the study before it runs anything
    out = os.path.join(work, "typo")
    proc = run([SCENE, "--vary", "FEM/Global refinementz=0,1", "--out", out, "--twinflow", twinflow])
    check(proc.returncode == 1 and "no entry 'Global refinementz' in subsection 'FEM'" in proc.stderr,
          "an unknown --vary entry is an input error with twinflow's message")
    check(not any(f.startswith("case_") for f in os.listdir(out)) if os.path.isdir(out) else True,
          "nothing ran")

    print("FAIL: " + "; ".join(failures) if failures else "OK")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
