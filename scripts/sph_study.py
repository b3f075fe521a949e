#!/usr/bin/env python3
"""SPH study runner: sweeps the particle spacing and the operator kind (consistent /
standard) of one scene, runs each case with twinflow and writes the error of the scene's
first reference check against wall time.

usage: sph_study.py SCENE.prm OUT_DIR [--spacings a,b,...] [--operators consistent,standard]
                    [--twinflow PATH] [--set "Entry = value" ...]

Writes OUT_DIR/study.csv (twinflow monitor CSV), OUT_DIR/study.md (the table for doc/)
and OUT_DIR/study.png (relative error against wall time, one line per operator kind).
A case that diverges or fails is kept in the table with its status and the message.
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import time


def edit_scene(text, sph_entries, output_dir):
    """Returns the scene with the given SPH entries set (replaced or added) and no output interval."""
    lines, out, depth, in_sph, done = text.splitlines(), [], 0, False, set()
    for line in lines:
        stripped = line.strip()
        if re.match(r"subsection\s+SPH\s*$", stripped) and depth == 0:
            in_sph = True
        if stripped.startswith("subsection"):
            depth += 1
        elif stripped == "end":
            depth -= 1
            if in_sph and depth == 0:
                for key, value in sph_entries.items():
                    if key not in done:
                        out.append(f"  set {key} = {value}")
                in_sph = False
        m = re.match(r"\s*set\s+([^=]+?)\s*=", line)
        if in_sph and m and m.group(1) in sph_entries:
            key = m.group(1)
            line, _ = f"  set {key} = {sph_entries[key]}", done.add(key)
        if depth == 1 and re.match(r"\s*set\s+Output directory\s*=", line):
            line = f"  set Output directory = {output_dir}"
        out.append(line)
    if not any(re.match(r"subsection\s+SPH\s*$", l.strip()) for l in lines):
        out += ["subsection SPH"] + [f"  set {k} = {v}" for k, v in sph_entries.items()] + ["end"]
    return "\n".join(out) + "\n"


def run_case(args, scene_text, scene_dir, spacing, operators):
    name = f"{operators}_dx{spacing:g}"
    case_dir = os.path.join(args.out, name)
    os.makedirs(case_dir, exist_ok=True)
    entries = {"Particle spacing": repr(spacing), "Operators": operators}
    for item in args.set:
        key, value = (s.strip() for s in item.split("=", 1))
        entries[key] = value
    # the scene stays beside the original so that its relative reference paths resolve
    prm = os.path.join(scene_dir, f".sph_study_{os.getpid()}_{name}.prm")
    with open(prm, "w") as f:
        f.write(edit_scene(scene_text, entries, case_dir))
    t0 = time.time()
    try:
        proc = subprocess.run([args.twinflow, prm, "-o", case_dir], capture_output=True, text=True)
    finally:
        os.remove(prm)
    wall = time.time() - t0
    with open(os.path.join(case_dir, "log.txt"), "w") as f:
        f.write(proc.stdout + proc.stderr)
    row = {"operators": operators, "spacing": spacing, "particles": math.nan, "steps": math.nan,
           "wall time": wall, "error": math.nan, "status": "ok", "message": ""}
    summary = os.path.join(case_dir, "sph", "summary.json")
    if proc.returncode != 0 or not os.path.exists(summary):
        row["status"] = "diverged" if "diverged" in proc.stderr else f"failed ({proc.returncode})"
        row["message"] = (proc.stderr.strip().splitlines() or [""])[-1][:200]
        return row
    s = json.load(open(summary))
    row["particles"] = s["size"]["particles"]
    row["steps"] = s["time_stepping"]["steps"]
    row["wall time"] = s["cost"]["wall_time_s"]
    if s.get("errors"):
        row["error"] = s["errors"][0]["relative_error"]
        row["quantity"] = s["errors"][0].get("quantity", "")
    return row


def write_outputs(out, rows, scene):
    with open(os.path.join(out, "study.csv"), "w") as f:
        f.write(f"# twinflow monitor: sph study of {scene} (operators: 0 consistent, 1 standard; "
                "status: 0 ok, 1 diverged/failed)\n")
        f.write("operators [-],spacing [m],particles [-],steps [-],wall time [s],relative error [-],status [-]\n")
        for r in rows:
            f.write(",".join(f"{v:.10g}" for v in (0 if r["operators"] == "consistent" else 1, r["spacing"],
                                                  r["particles"], r["steps"], r["wall time"], r["error"],
                                                  0 if r["status"] == "ok" else 1)) + "\n")
    quantity = next((r.get("quantity") for r in rows if r.get("quantity")), "error")
    with open(os.path.join(out, "study.md"), "w") as f:
        f.write(f"Scene `{scene}`; error: {quantity} (relative, against the scene's reference).\n\n")
        f.write("| operators | spacing [m] | particles | steps | wall time [s] | rel. error | status |\n")
        f.write("|---|---|---|---|---|---|---|\n")
        for r in rows:
            err = "—" if math.isnan(r["error"]) else f"{100 * r['error']:.2f} %"
            parts = "—" if math.isnan(r["particles"]) else f"{int(r['particles'])}"
            steps = "—" if math.isnan(r["steps"]) else f"{int(r['steps'])}"
            status = r["status"] + (f": {r['message']}" if r["message"] else "")
            f.write(f"| {r['operators']} | {r['spacing']:g} | {parts} | {steps} | {r['wall time']:.1f} | {err} | "
                    f"{status} |\n")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("sph_study: matplotlib not available, no plot")
        return
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for ops, marker in (("consistent", "o-"), ("standard", "s--")):
        pts = [(r["wall time"], r["error"], r["spacing"]) for r in rows
               if r["operators"] == ops and r["status"] == "ok" and r["error"] > 0]
        if pts:
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker, label=f"{ops} operators")
            for t, e, dx in pts:
                ax.annotate(f"Δx={dx:g}", (t, e), textcoords="offset points", xytext=(4, 4), fontsize=7)
        bad = [r for r in rows if r["operators"] == ops and r["status"] != "ok"]
        for r in bad:
            ax.axvline(r["wall time"], ls=":", color="grey")
            ax.annotate(f"{ops} Δx={r['spacing']:g}: {r['status']}", (r["wall time"], 0.5),
                        xycoords=("data", "axes fraction"), rotation=90, fontsize=7, color="grey")
    ax.set_xlabel("wall time [s]")
    ax.set_ylabel(f"relative error ({quantity})")
    ax.set_title(f"SPH study: {scene}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "study.png"), dpi=120)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene")
    parser.add_argument("out")
    parser.add_argument("--spacings", required=True, help="comma-separated particle spacings [m]")
    parser.add_argument("--operators", default="consistent,standard")
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser.add_argument("--twinflow", default=os.path.join(root, "build", "twinflow"))
    parser.add_argument("--set", action="append", default=[], help="extra 'SPH entry = value'")
    args = parser.parse_args()
    args.out = os.path.abspath(args.out)
    os.makedirs(args.out, exist_ok=True)
    with open(args.scene) as f:
        scene_text = f.read()
    scene_dir = os.path.dirname(os.path.abspath(args.scene))
    spacings = sorted((float(s) for s in args.spacings.split(",")), reverse=True)
    operators = [o.strip() for o in args.operators.split(",")]
    for o in operators:
        if o not in ("consistent", "standard"):
            sys.exit(f"sph_study: unknown operator kind '{o}'; allowed: consistent, standard")
    rows, total, t_start = [], len(spacings) * len(operators), time.time()
    for k, (ops, dx) in enumerate((o, d) for o in operators for d in spacings):
        r = run_case(args, scene_text, scene_dir, dx, ops)
        rows.append(r)
        err = "—" if math.isnan(r["error"]) else f"{100 * r['error']:.2f} %"
        print(f"[{k + 1}/{total}] {ops:10s} dx {dx:<10g} {r['status']:8s} error {err:>9s}  wall {r['wall time']:.1f} s"
              f"  (elapsed {time.time() - t_start:.0f} s)", flush=True)
    write_outputs(args.out, rows, os.path.basename(args.scene))
    print(f"sph_study: wrote study.csv, study.md, study.png to {args.out}")


if __name__ == "__main__":
    main()
