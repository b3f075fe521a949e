#!/usr/bin/env python3
"""Twinflow study runner: what accuracy costs in time.

Sweeps one or more entries of a scene, runs one twinflow case per combination (each in its
own folder), collects every <case>/<method>/summary.json into one table and plots the error
of each reference quantity against wall time and against the problem size.

usage:
  scripts/study.py SCENE.prm --vary 'FEM/Global refinements=0,1,2,3' [--vary ...] [--zip]
                   [--set 'Subsection/Entry=value' ...] [--out DIR] [--twinflow PATH]
                   [--mpi N] [--timeout S]
  scripts/study.py --plot-only DIR        re-collect DIR's cases, rewrite the table and plots

--vary 'PATH=v1,v2,...'  an entry to sweep, PATH as for `twinflow --set` (subsections and the
                         entry separated by '/'). Values are separated by ','; a value that
                         itself contains commas (a point, a list) needs '|' as the separator:
                         --vary 'Scene/Methods=fem|sph|fem, sph' (a single such value
                         ends with '|': --vary 'Domain/Upper corner=2, 1|').
                         Several --vary give the full cartesian product (the first --vary is
                         the outer loop); with --zip they are paired (equal lengths).
--set 'PATH=value'       a fixed override passed to every case.
--out DIR                study folder (default: output/study_<scene name>).
--twinflow PATH          the executable (default: build/twinflow of this source tree).
--mpi N                  run each case with `mpirun -np N` (the FEM is distributed).
--timeout S              stop a case after S seconds (status 'timeout').

Every case runs `twinflow SCENE --set ... -o DIR/case_<k>_<short name>` and keeps its output
and log.txt there. Before the first case, every case's input is checked (`twinflow --check`),
so a typo stops the study at once. A case that fails (input error, divergence, crash,
timeout) stays in the table with its status and message.

Writes into DIR:
  study.json        the study (scene, entries, cases with status), read by --plot-only
  study.csv         one row per case and method: case, folder, the varied entries, method,
                    mpi ranks, cells, dofs, particles, steps, final time [s], wall time [s],
                    time per step [s], case wall time [s], 'monitor <name>' per monitor,
                    'error <quantity>' (relative) per reference quantity, within tolerance,
                    status, message
  study.md          the same as a markdown table (for doc/)
  report.md         the study's page: that table, the plots inline, links to each case's report.md
  study_<quantity>.png  per error quantity: error against wall time and against size
                    (DoFs for FEM, particles for SPH), log-log, one line per method and per
                    value of the other varied entries, the tolerance as a dashed line
Exit status: 0 when at least one case ran, 1 on bad arguments or input, 3 when no case ran.
"""
import argparse
import csv
import itertools
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
METHOD_ORDER = {"fem": 0, "sph": 1}


class StudyError(Exception):
    """A usage or input error: printed as 'study: error: ...', exit status 1."""


# --------------------------------------------------------------------------- set-up

def split_assignment(text, option):
    """'A / B = v' -> ('A/B', 'v') with the parts trimmed."""
    if "=" not in text:
        raise StudyError(f"{option} '{text}': expected 'Subsection/.../Entry=value' (no '=' found)")
    key, value = text.split("=", 1)
    parts = [p.strip() for p in key.split("/")]
    if any(not p for p in parts):
        raise StudyError(f"{option} '{text}': empty subsection or entry name in '{key.strip()}'")
    return "/".join(parts), value.strip()


def parse_vary(text):
    entry, rhs = split_assignment(text, "--vary")
    values = [v.strip() for v in rhs.split("|" if "|" in rhs else ",")]
    if "|" in rhs and len(values) > 1 and values[-1] == "":
        values.pop()  # 'v1, v2|': a single value that contains commas
    if not rhs.strip() or any(v == "" for v in values):
        raise StudyError(f"--vary '{text}': expected one or more values separated by ',' (or '|'), "
                         "with none empty")
    return entry, values


def is_number(s):
    try:
        float(s)
        return True
    except ValueError:
        return False


def short_name(values):
    """'FEM/Global refinements'='2', 'SPH/Operators'='standard' -> 'refinements2_standard'."""
    parts = []
    for entry, value in values.items():
        word = entry.split("/")[-1].split()[-1].lower()
        simple_word = re.fullmatch(r"[A-Za-z][A-Za-z0-9_-]*", value) is not None
        parts.append(value if simple_word else word + value)
    name = "_".join(re.sub(r"[^A-Za-z0-9.+-]+", "-", p).strip("-") for p in parts)
    return name[:60].strip("_-") or "case"


def make_cases(vary, zipped):
    entries = [e for e, _ in vary]
    if zipped:
        lengths = {len(v) for _, v in vary}
        if len(lengths) > 1:
            raise StudyError("--zip needs the same number of values in every --vary (got " +
                             ", ".join(f"{e}: {len(v)}" for e, v in vary) + ")")
        combos = list(zip(*[v for _, v in vary]))
    else:
        combos = list(itertools.product(*[v for _, v in vary]))
    width = len(str(len(combos)))
    cases = []
    for k, combo in enumerate(combos, start=1):
        values = dict(zip(entries, combo))
        cases.append({"k": k, "folder": f"case_{k:0{width}d}_{short_name(values)}", "values": values,
                      "status": "pending", "message": "", "wall_time_s": None, "returncode": None})
    return cases


def twinflow_args(study, case):
    args = [study["twinflow"], study["scene"]]
    for s in study["set"]:
        args += ["--set", s]
    for entry, value in case["values"].items():
        args += ["--set", f"{entry}={value}"]
    return args


def child_env(study):
    env = dict(os.environ)
    if study.get("mpi") and os.geteuid() == 0:
        env.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
        env.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    return env


def last_line(text):
    lines = [l.strip() for l in text.strip().splitlines() if l.strip()]
    return lines[-1][:300] if lines else ""


def error_message(stderr):
    """The error line of twinflow's stderr (its first line starting with 'twinflow: '), else the last line."""
    lines = stderr.strip().splitlines()
    for i, line in enumerate(lines):
        if line.startswith("twinflow: "):
            return " ".join(l.strip() for l in lines[i:i + 3] if not l.startswith("(twinflow --print"))[:300]
    return last_line(stderr)


def check_inputs(study):
    """Runs `twinflow ... --check` for every case: a typo or a bad value stops the study before any run."""
    for case in study["cases"]:
        proc = subprocess.run(twinflow_args(study, case) + ["--check"], capture_output=True, text=True,
                              env=child_env(study))
        if proc.returncode != 0:
            raise StudyError(f"case {case['k']} ({case['folder']}) does not pass twinflow's input check, "
                             f"nothing was run:\n{proc.stderr.strip() or proc.stdout.strip()}")


def run_case(study, case, out):
    folder = os.path.join(out, case["folder"])
    if os.path.isdir(folder):
        shutil.rmtree(folder)  # results of an earlier study in the same folder
    os.makedirs(folder)
    cmd = twinflow_args(study, case) + ["-o", folder]
    if study.get("mpi"):
        cmd = ["mpirun", "-np", str(study["mpi"])] + cmd
    t0 = time.time()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=child_env(study), start_new_session=True)
    timed_out = False
    try:
        stdout, stderr = proc.communicate(timeout=study.get("timeout"))
    except subprocess.TimeoutExpired:
        timed_out = True
        os.killpg(proc.pid, signal.SIGKILL)
        stdout, stderr = proc.communicate()
    except KeyboardInterrupt:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        case.update(status="interrupted", message="stopped by the user", wall_time_s=time.time() - t0)
        raise
    case["wall_time_s"] = time.time() - t0
    case["returncode"] = proc.returncode
    with open(os.path.join(folder, "log.txt"), "w") as f:
        f.write("$ " + " ".join(shell_quote(c) for c in cmd) + "\n" + stdout + stderr)
    if timed_out:
        case.update(status="timeout", message=f"stopped after {study['timeout']:g} s (--timeout)")
    elif proc.returncode == 0:
        case.update(status="ok", message="")
        if not summaries_of(folder):
            case.update(status="no summary", message="twinflow exited with 0 but wrote no summary.json")
    elif "diverged" in stderr:
        case.update(status="diverged", message=error_message(stderr))
    elif proc.returncode == 1:
        case.update(status="input error", message=error_message(stderr))
    else:
        case.update(status=f"failed (exit {proc.returncode})", message=error_message(stderr))


def shell_quote(s):
    return s if re.fullmatch(r"[A-Za-z0-9_./=:,+-]+", s) else "'" + s.replace("'", "'\\''") + "'"


# --------------------------------------------------------------------------- collecting

def summaries_of(folder):
    """[(method, summary dict)] of a case folder, FEM first."""
    found = []
    if not os.path.isdir(folder):
        return found
    for method in sorted(os.listdir(folder), key=lambda m: (METHOD_ORDER.get(m, 9), m)):
        path = os.path.join(folder, method, "summary.json")
        if os.path.isfile(path):
            try:
                with open(path) as f:
                    found.append((method, json.load(f)))
            except (OSError, ValueError) as e:
                print(f"study: warning: cannot read {path}: {e}", file=sys.stderr)
    return found


def collect(study, out):
    """Rows (one per case and method), the monitor names and error quantities in first-seen order, and the
    tolerances given per quantity."""
    rows, monitors, quantities, tolerances = [], [], [], {}
    for case in study["cases"]:
        base = {"case": case["k"], "folder": case["folder"], **case["values"],
                "case wall time [s]": case["wall_time_s"], "status": case["status"], "message": case["message"]}
        found = summaries_of(os.path.join(out, case["folder"])) if case["status"] != "pending" else []
        if not found:
            rows.append(dict(base, method=""))
            continue
        for method, s in found:
            size, steps, cost = s.get("size", {}), s.get("time_stepping", {}), s.get("cost", {})
            row = dict(base, method=method)
            row.update({"mpi ranks": s.get("mpi_ranks"), "cells": size.get("cells"), "dofs": size.get("dofs_total"),
                        "particles": size.get("particles"), "steps": steps.get("steps"),
                        "final time [s]": steps.get("final_time_s"), "wall time [s]": cost.get("wall_time_s"),
                        "time per step [s]": cost.get("wall_time_per_step_s"),
                        "within tolerance": s.get("all_within_tolerance")})
            for name, value in s.get("monitors", {}).items():
                if name not in monitors:
                    monitors.append(name)
                row["monitor " + name] = value
            for e in s.get("errors", []):
                q = e.get("quantity", "")
                if q not in quantities:
                    quantities.append(q)
                row["error " + q] = e.get("relative_error")
                if e.get("tolerance") is not None:
                    tolerances.setdefault(q, set()).add(e["tolerance"])
            rows.append(row)
    return rows, monitors, quantities, tolerances


def columns(study, monitors, quantities):
    return (["case", "folder"] + [e for e, _ in study["vary"]] +
            ["method", "mpi ranks", "cells", "dofs", "particles", "steps", "final time [s]", "wall time [s]",
             "time per step [s]", "case wall time [s]"] +
            ["monitor " + m for m in monitors] + ["error " + q for q in quantities] +
            ["within tolerance", "status", "message"])


def fmt(v):
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return "" if math.isnan(v) else f"{v:.10g}"
    return str(v)


def write_csv(path, cols, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for r in rows:
            w.writerow([fmt(r.get(c)) for c in cols])


def scene_name(study):
    """The scene path relative to the source tree when it lies inside it, else absolute."""
    rel = os.path.relpath(study["scene"], ROOT)
    return study["scene"] if rel.startswith("..") else rel


def command_line(study):
    def quoted(s):
        return "'" + s.replace("'", "'\\''") + "'"
    parts = ["scripts/study.py", shell_quote(scene_name(study))]
    for e, values in study["vary"]:
        sep = "|" if any("," in v for v in values) else ","
        parts += ["--vary", quoted(f"{e}={sep.join(values)}" + ("|" if sep == "|" and len(values) == 1 else ""))]
    if study.get("zip"):
        parts.append("--zip")
    for s in study["set"]:
        parts += ["--set", quoted(s)]
    if study.get("mpi"):
        parts += ["--mpi", str(study["mpi"])]
    return " ".join(parts)


def size_text(r):
    if r.get("dofs") is not None:
        return f"{r['cells']:,} cells / {r['dofs']:,} DoFs" if r.get("cells") is not None else f"{r['dofs']:,} DoFs"
    if r.get("particles") is not None:
        return f"{r['particles']:,} particles"
    if r.get("cells") is not None:
        return f"{r['cells']:,} cells"
    return "—"


def write_markdown(path, study, rows, quantities):
    entries = [e for e, _ in study["vary"]]
    with open(path, "w") as f:
        f.write(f"Study of `{scene_name(study)}`: `{command_line(study)}`. "
                "Errors are relative, against the scene's references.\n\n")
        head = (["case"] + [f"`{e}`" for e in entries] + ["method", "size", "steps", "wall time [s]",
                                                          "time/step [ms]"] + [f"{q}" for q in quantities] + ["status"])
        f.write("| " + " | ".join(head) + " |\n|" + "---|" * len(head) + "\n")
        for r in rows:
            def num(key, scale=1.0, form="{:.1f}"):
                v = r.get(key)
                return "—" if v is None or (isinstance(v, float) and math.isnan(v)) else form.format(scale * v)
            errs = [num("error " + q, 100, "{:.3g} %") for q in quantities]
            status = r["status"] + (f": {r['message']}" if r.get("message") else "")
            wall = r.get("wall time [s]") if r.get("wall time [s]") is not None else r.get("case wall time [s]")
            cells = ([str(r["case"])] + [str(r.get(e, "")) for e in entries] +
                     [r.get("method") or "—", size_text(r), num("steps", form="{:.0f}"),
                      "—" if wall is None else f"{wall:.3g}", num("time per step [s]", 1000, "{:.3g}")] + errs +
                     [status.replace("|", "/")])
            f.write("| " + " | ".join(cells) + " |\n")


def slug(text):
    return re.sub(r"[^A-Za-z0-9]+", "_", text).strip("_").lower() or "error"


def plot(study, rows, quantities, tolerances, out):
    """One PNG per error quantity: error against wall time and against size, log-log."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("study: warning: matplotlib is not available (python3-matplotlib), no plots", file=sys.stderr)
        return []
    entries = [e for e, _ in study["vary"]]
    sweep = entries if study.get("zip") else entries[:1]
    others = [e for e in entries if e not in sweep]
    written = []
    for q in quantities:
        col = "error " + q
        groups = {}
        for r in rows:
            if r["status"] == "ok" and isinstance(r.get(col), (int, float)) and r[col] > 0:
                key = (r["method"],) + tuple(r.get(e) for e in others)
                groups.setdefault(key, []).append(r)
        if not groups:
            continue
        fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
        methods = sorted({k[0] for k in groups}, key=lambda m: METHOD_ORDER.get(m, 9))
        for i, (key, pts) in enumerate(sorted(groups.items(), key=lambda kv: (METHOD_ORDER.get(kv[0][0], 9), kv[0]))):
            label = ", ".join([key[0].upper()] + [f"{e.split('/')[-1]} = {v}" for e, v in zip(others, key[1:])])
            style = "os^vDP*X"[i % 8] + ("-" if key[0] != "sph" else "--")
            pts = sorted(pts, key=lambda r: (size_of(r) or 0, r["wall time [s]"] or 0))
            for ax, xkey in ((axes[0], "wall time [s]"), (axes[1], None)):
                xy = [((r[xkey] if xkey else size_of(r)), r[col], r) for r in pts]
                xy = [(x, y, r) for x, y, r in xy if x is not None and x > 0]
                if not xy:
                    continue
                line, = ax.loglog([p[0] for p in xy], [p[1] for p in xy], style, label=label)
                for x, y, r in xy:
                    ax.annotate(", ".join(str(r.get(e)) for e in sweep), (x, y), textcoords="offset points",
                                xytext=(4, 4), fontsize=7, color=line.get_color())
        for tol in sorted(tolerances.get(q, ())):
            for ax in axes:
                ax.axhline(tol, ls="--", color="grey", lw=1)
                ax.annotate(f"tolerance {100 * tol:.3g} %", (0.01, tol), xycoords=("axes fraction", "data"),
                            textcoords="offset points", xytext=(0, 3), fontsize=7, color="grey")
        failed = {r["case"]: r for r in rows if r["status"] not in ("ok", "pending")}
        for r in failed.values():
            t = r.get("case wall time [s]")
            if t and t > 0:
                axes[0].axvline(t, ls=":", color="grey")
                axes[0].annotate(f"case {r['case']}: {r['status']}", (t, 0.5), xycoords=("data", "axes fraction"),
                                 rotation=90, fontsize=7, color="grey")
        axes[0].set_xlabel("wall time [s]")
        size_label = " / ".join({"fem": "DoFs (FEM)", "sph": "particles (SPH)"}.get(m, m) for m in methods)
        axes[1].set_xlabel(f"size: {size_label}")
        for ax in axes:
            ax.set_ylabel(f"relative error: {q}")
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=8, title="points: " + ", ".join(e.split("/")[-1] for e in sweep),
                      title_fontsize=8)
        fig.suptitle(f"{os.path.basename(study['scene'])}: {q} — what accuracy costs")
        fig.tight_layout()
        path = os.path.join(out, f"study_{slug(q)}.png")
        fig.savefig(path, dpi=110)
        plt.close(fig)
        written.append(path)
    return written


def size_of(r):
    for key in ("dofs", "particles", "cells"):
        if isinstance(r.get(key), (int, float)):
            return r[key]
    return None


def write_report(out, study, pngs):
    """DIR/report.md: the study table (study.md), its error-against-time plots inline, and a
    link to each case's own report. Every link is relative to DIR and names an existing file."""
    with open(os.path.join(out, "study.md"), encoding="utf-8") as f:
        table = f.read()
    lines = [f"# Study of {os.path.basename(study['scene'])}: what accuracy costs in time", "",
             "Written " + time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()) + ". The table is also in "
             "[study.md](study.md) and [study.csv](study.csv).", "", table.rstrip(), ""]
    if pngs:
        lines += ["## Error against wall time and size", ""]
        for p in pngs:
            name = os.path.basename(p)
            lines += [f"![{os.path.splitext(name)[0]}]({name})", ""]
    cases = []
    for case in study.get("cases", []):
        folder = case.get("folder") or ""
        if folder and os.path.isfile(os.path.join(out, folder, "report.md")):
            cases.append(f"- case {case.get('k', '')}: [{folder}/report.md]({folder}/report.md)")
    if cases:
        lines += ["## The cases' reports", ""] + cases + [""]
    with open(os.path.join(out, "report.md"), "w", encoding="utf-8") as f:
        f.write("\n".join(lines).rstrip() + "\n")


def write_results(study, out, with_plots):
    with open(os.path.join(out, "study.json"), "w") as f:
        json.dump(study, f, indent=1)
    rows, monitors, quantities, tolerances = collect(study, out)
    write_csv(os.path.join(out, "study.csv"), columns(study, monitors, quantities), rows)
    write_markdown(os.path.join(out, "study.md"), study, rows, quantities)
    pngs = plot(study, rows, quantities, tolerances, out) if with_plots else []
    write_report(out, study, pngs)
    return pngs, rows, quantities


# --------------------------------------------------------------------------- main

def progress_line(study, case, rows, quantities, t_start, done_times):
    n = len(study["cases"])
    mine = [r for r in rows if r["case"] == case["k"]]
    details = []
    for r in mine:
        if r.get("method"):
            errs = [f"{q} {100 * r['error ' + q]:.3g} %" for q in quantities
                    if isinstance(r.get("error " + q), (int, float))][:3]
            details.append(f"{r['method']}: {size_text(r)}" + (", " + ", ".join(errs) if errs else ""))
    remaining = n - case["k"]
    eta = sum(done_times) / len(done_times) * remaining if done_times else 0
    text = f"[{case['k']}/{n}] {case['folder']}: {case['status']}, {case['wall_time_s']:.1f} s"
    if details:
        text += " (" + "; ".join(details) + ")"
    if case["message"]:
        text += f" — {case['message']}"
    text += f" | elapsed {time.time() - t_start:.0f} s"
    if remaining:
        text += f", ETA ~{eta:.0f} s ({remaining} to go, at the mean case time so far)"
    return text


def main(argv):
    parser = argparse.ArgumentParser(prog="scripts/study.py", description=__doc__, usage=argparse.SUPPRESS,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene", nargs="?")
    parser.add_argument("--vary", action="append", default=[])
    parser.add_argument("--zip", action="store_true")
    parser.add_argument("--set", action="append", default=[])
    parser.add_argument("--out")
    parser.add_argument("--twinflow", default=os.path.join(ROOT, "build", "twinflow"))
    parser.add_argument("--mpi", type=int, default=0)
    parser.add_argument("--timeout", type=float)
    parser.add_argument("--plot-only", metavar="DIR")
    args = parser.parse_args(argv)

    if args.plot_only:
        out = os.path.abspath(args.plot_only)
        try:
            with open(os.path.join(out, "study.json")) as f:
                study = json.load(f)
        except (OSError, ValueError) as e:
            raise StudyError(f"--plot-only {args.plot_only}: cannot read its study.json ({e}); is it a study folder?")
        pngs, rows, _ = write_results(study, out, True)
        print(f"study: re-collected {len(study['cases'])} cases ({len(rows)} rows) into {out}/study.csv, study.md"
              + (", " + ", ".join(os.path.basename(p) for p in pngs) if pngs else ""))
        return 0

    if not args.scene:
        raise StudyError("a scene file is needed (or --plot-only DIR)")
    if not args.vary:
        raise StudyError("nothing to vary: give at least one --vary 'Subsection/Entry=v1,v2,...'")
    if not os.path.isfile(args.scene):
        raise StudyError(f"cannot open scene file '{args.scene}'")
    twinflow = shutil.which(args.twinflow) or (os.path.abspath(args.twinflow) if os.access(args.twinflow, os.X_OK)
                                               else None)
    if not twinflow:
        raise StudyError(f"twinflow executable '{args.twinflow}' not found; build it (cmake --build build) "
                         "or pass --twinflow PATH")
    if args.mpi < 0 or (args.timeout is not None and args.timeout <= 0):
        raise StudyError("--mpi must be >= 1 and --timeout > 0")
    vary = [parse_vary(v) for v in args.vary]
    names = [e for e, _ in vary]
    if len(set(names)) != len(names):
        raise StudyError("an entry is given to --vary twice: " + ", ".join(sorted({e for e in names if names.count(e) > 1})))
    fixed = []
    for s in args.set:
        entry, value = split_assignment(s, "--set")
        if entry in names:
            raise StudyError(f"--set '{s}': '{entry}' is also varied")
        fixed.append(f"{entry}={value}")
    stem = os.path.splitext(os.path.basename(args.scene))[0]
    out = os.path.abspath(args.out or os.path.join("output", f"study_{stem}"))
    study = {"schema": "twinflow.study", "schema_version": 1, "scene": os.path.abspath(args.scene),
             "vary": vary, "zip": args.zip, "set": fixed, "twinflow": twinflow, "mpi": args.mpi,
             "timeout": args.timeout, "cases": make_cases(vary, args.zip)}
    os.makedirs(out, exist_ok=True)
    n = len(study["cases"])
    print(f"study: {n} case{'s' if n > 1 else ''} of {args.scene} into {out}: " +
          ("; ".join(f"{e} = {', '.join(v)}" for e, v in vary)) + (" (zipped)" if args.zip else ""), flush=True)
    check_inputs(study)
    write_results(study, out, False)
    t_start, done_times = time.time(), []
    try:
        for case in study["cases"]:
            print(f"[{case['k']}/{n}] running {case['folder']}: " +
                  ", ".join(f"{e}={v}" for e, v in case["values"].items()), flush=True)
            run_case(study, case, out)
            done_times.append(case["wall_time_s"])
            _, rows, quantities = write_results(study, out, False)
            print(progress_line(study, case, rows, quantities, t_start, done_times), flush=True)
    except KeyboardInterrupt:
        print("study: interrupted; writing what has run so far", file=sys.stderr)
    pngs, rows, _ = write_results(study, out, True)
    ok = sum(c["status"] == "ok" for c in study["cases"])
    print(f"study: {ok} of {n} cases ok, {time.time() - t_start:.0f} s; wrote {out}/study.csv, study.md" +
          (", " + ", ".join(os.path.basename(p) for p in pngs) if pngs else "") +
          f" (re-plot: scripts/study.py --plot-only {os.path.relpath(out)})")
    return 0 if ok else 3


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except StudyError as e:
        print(f"study: error: {e}", file=sys.stderr)
        sys.exit(1)
