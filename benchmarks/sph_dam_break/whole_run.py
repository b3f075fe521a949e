#!/usr/bin/env python3
"""Whole-run SPH benchmark (issue 14, item 4): what a user pays for a whole dam break.

Runs the committed free-surface scenes with SPH only, each from its start to its end time, one
case at a time, and prints per case: particles, steps, wall time of the whole job (set-up,
output, monitors included), wall time per simulated second and per 1000 steps, the split per
phase (from summary.json), the mean and largest pressure iterations (solver.csv), the largest
fluid speed of the run against sqrt(g H) (front.csv), the energy gain over the initial value
(energy.csv) and, for Martin & Moyce, the front error raw / time-origin fitted. The peer
column is the weakly compressible code of the issue (SPHinXsys, measured on these 2 cores).

usage:
  benchmarks/sph_dam_break/whole_run.py [--cases mm40,mm80,db40,db80] [--threads 2]
        [--set 'SPH/CFL number=1'] [--out output/sph_whole_run] [--twinflow build/twinflow]
  cases: mm40, mm80 (Martin & Moyce a/40, a/80), db40, db80 (paper dam break dx = H/40, H/80),
         paper (the paper's 52.5k-marker dam break, dx = 1/150 m; ~15-60 min)
Writes OUT/whole_run.md (the table) and OUT/whole_run.json.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import twinflow_csv  # noqa: E402

G = 9.81
# name: (scene, spacing, water height H for sqrt(gH), peer wall time [s] or None)
CASES = {
    "mm40": ("parameters/dam_break_martin_moyce.prm", 0.05715 / 40, 2 * 0.05715, 2.4),
    "mm80": ("parameters/dam_break_martin_moyce.prm", 0.05715 / 80, 2 * 0.05715, 22.6),
    "db40": ("parameters/dam_break.prm", 1.0 / 40, 1.0, 6.1),
    "db80": ("parameters/dam_break.prm", 1.0 / 80, 1.0, 63.0),
    "paper": ("parameters/dam_break.prm", 1.0 / 150, 1.0, None),
}


def column(path, name):
    header, rows = twinflow_csv.read(path)
    i = header.index(name)
    return [r[i] for r in rows]


def run_case(name, args):
    scene, dx, height, peer = CASES[name]
    out = os.path.join(args.out, name)
    cmd = [args.twinflow, os.path.join(ROOT, scene), "--set", "Scene/Methods=sph",
           "--set", f"SPH/Particle spacing={dx!r}", "-o", out]
    for s in args.set:
        cmd += ["--set", s]
    env = dict(os.environ, OMP_NUM_THREADS=str(args.threads))
    os.makedirs(out, exist_ok=True)
    start = time.time()
    with open(os.path.join(out, "log.txt"), "w") as log:
        rc = subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT, env=env)
    elapsed = time.time() - start
    if rc != 0:
        return {"case": name, "status": f"failed (exit {rc}, see {out}/log.txt)", "job_s": elapsed}
    s = json.load(open(os.path.join(out, "sph", "summary.json")))
    steps = s["time_stepping"]["steps"]
    t_end = s["time_stepping"]["final_time_s"]
    wall = s["cost"]["wall_time_s"]
    iters = column(os.path.join(out, "sph", "solver.csv"), "pressure iterations [-]")
    speed = max(column(os.path.join(out, "sph", "front.csv"), "max speed [m/s]"))
    energy = column(os.path.join(out, "sph", "energy.csv"), "total energy [J]")
    m = s["monitors"]
    row = {
        "case": name, "status": "ok", "particles": s["size"]["particles"],
        "fluid_particles": s.get("extra", {}).get("fluid particles"), "steps": steps,
        "final_time_s": t_end, "wall_s": wall, "job_s": elapsed, "peer_s": peer,
        "per_simulated_second_s": wall / t_end, "per_1000_steps_s": 1000 * wall / steps,
        "split_ms_per_step": {k: 1e3 * v["wall_time_s"] / steps for k, v in s["cost"]["sections"].items()},
        "pressure_iterations_mean": sum(iters) / len(iters), "pressure_iterations_max": max(iters),
        "max_speed": speed, "max_speed_over_sqrt_gH": speed / math.sqrt(G * height),
        "energy_gain": max(energy) / energy[0] - 1,
        "front_raw": m.get("front rms relative error"),
        "front_fitted": m.get("front rms relative error, time origin fitted"),
    }
    return row


def pct(v):
    return "—" if v is None else f"{100 * v:.1f} %"


def table(rows):
    lines = ["| case | particles | steps | wall time (peer) | per simulated second | per 1000 steps | "
             "pressure its mean / max | max speed / √(gH) | energy gain | front raw / fitted |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["status"] != "ok":
            lines.append(f"| {r['case']} | {r['status']} |||||||||")
            continue
        peer = f" ({r['peer_s']} s)" if r["peer_s"] else ""
        lines.append(
            f"| {r['case']} | {r['particles']} | {r['steps']} | {r['wall_s']:.1f} s{peer} | "
            f"{r['per_simulated_second_s']:.1f} s | {r['per_1000_steps_s']:.1f} s | "
            f"{r['pressure_iterations_mean']:.1f} / {r['pressure_iterations_max']:.0f} | "
            f"{r['max_speed']:.2f} m/s = {r['max_speed_over_sqrt_gH']:.2f} | {pct(r['energy_gain'])} | "
            f"{pct(r['front_raw'])} / {pct(r['front_fitted'])} |")
    lines += ["", "Split per phase [ms/step]:", ""]
    phases = sorted({k for r in rows if r["status"] == "ok" for k in r["split_ms_per_step"]})
    lines.append("| case | " + " | ".join(phases) + " |")
    lines.append("|---|" + "---|" * len(phases))
    for r in rows:
        if r["status"] == "ok":
            lines.append(f"| {r['case']} | " + " | ".join(f"{r['split_ms_per_step'].get(p, 0):.2f}" for p in phases) + " |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", default="mm40,mm80,db40,db80")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--out", default=os.path.join(ROOT, "output", "sph_whole_run"))
    ap.add_argument("--twinflow", default=os.path.join(ROOT, "build", "twinflow"))
    args = ap.parse_args()
    names = [c.strip() for c in args.cases.split(",") if c.strip()]
    for n in names:
        if n not in CASES:
            sys.exit(f"whole_run.py: unknown case '{n}'; allowed: {', '.join(CASES)}")
    rows = []
    for n in names:
        print(f"[{n}] running ...", flush=True)
        rows.append(run_case(n, args))
        r = rows[-1]
        print(f"[{n}] {r['status']}, whole job {r['job_s']:.1f} s", flush=True)
    md = table(rows)
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "whole_run.md"), "w") as f:
        f.write(f"Overrides: {args.set or 'none'}; OpenMP threads: {args.threads}\n\n{md}\n")
    json.dump(rows, open(os.path.join(args.out, "whole_run.json"), "w"), indent=1)
    print(md)
    return 0 if all(r["status"] == "ok" for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
