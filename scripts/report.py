#!/usr/bin/env python3
"""Write report.md, the page a user opens first, for a twinflow run.

    report.py RUN_DIR [--scene FILE] [--command 'twinflow ...']

RUN_DIR is a run's output directory (Scene/Output directory): one subfolder per method
(fem/, sph/) with its summary.json, and plots/ with the PNGs of the plot step. The report
holds, in this order:

  - the scene: name, scene file, the command that ran it, dimension, methods;
  - the active physics of each method (what the scene built; nothing else ran);
  - cost: size (cells and DoFs, or particles), steps, simulated time, wall time, and the
    wall time per 1000 steps and per simulated second;
  - accuracy against references: every error of every summary.json, with its tolerance and
    status, the raw error beside a fitted one where the run reports both;
  - wall time per section (solver phase) of each method;
  - the plots (plots/<monitor>.png, and figures in a reference's own axes) and the
    snapshots (plots/snapshot_t<time>.png) inline, each with what its JSON says it shows;
  - the final monitor values and the files of the run, linked.

A run that stopped with an error (--stopped MESSAGE) gets the message first and what it wrote
up to the stop. Every link is relative to RUN_DIR and names a file that exists when the report
is written. Needs only the Python standard library. Exit status 1 when RUN_DIR has no
summary.json and the run did not stop (nothing to report).
"""
import argparse
import datetime
import json
import os
import sys

METHOD_ORDER = ["fem", "sph"]
METHOD_NAMES = {"fem": "FEM", "sph": "SPH"}


def load_summaries(run_dir):
    """[(method folder, summary)] of the method subfolders that hold a summary.json."""
    found = []
    folders = [d for d in sorted(os.listdir(run_dir)) if os.path.isdir(os.path.join(run_dir, d))]
    folders.sort(key=lambda d: METHOD_ORDER.index(d) if d in METHOD_ORDER else len(METHOD_ORDER))
    for d in folders:
        path = os.path.join(run_dir, d, "summary.json")
        if os.path.isfile(path):
            with open(path, encoding="utf-8") as f:
                found.append((d, json.load(f)))
    return found


def number(v, digits=4):
    if v is None:
        return "—"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, int):
        return f"{v:,}"
    if isinstance(v, float):
        if v == 0:
            return "0"
        if 1e3 <= abs(v) < 1e9:
            return f"{v:,.0f}"
        return f"{v:.{digits}g}"
    return str(v)


def cell(text):
    """Markdown table cell: no '|' or line breaks."""
    return str(text).replace("|", "\\|").replace("\n", " ")


def table(head, rows):
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(cell(c) for c in r) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def size_text(s):
    size = s.get("size", {})
    parts = []
    if size.get("cells"):
        parts.append(f"{size['cells']:,} cells")
    if size.get("dofs_total"):
        parts.append(f"{size['dofs_total']:,} DoFs")
    if size.get("particles"):
        parts.append(f"{size['particles']:,} particles")
    extra = s.get("extra", {})
    if "fluid particles" in extra and "BCE markers" in extra:
        parts.append(f"({int(extra['fluid particles']):,} fluid + {int(extra['BCE markers']):,} BCE markers)")
    return " ".join(parts) or "—"


def cost_rows(summaries):
    rows = []
    for method, s in summaries:
        steps = s.get("time_stepping", {}).get("steps")
        t_end = s.get("time_stepping", {}).get("final_time_s")
        wall = s.get("cost", {}).get("wall_time_s")
        per_1000 = 1000 * wall / steps if wall is not None and steps else None
        per_second = wall / t_end if wall is not None and t_end else None
        rows.append([METHOD_NAMES.get(method, method), size_text(s), number(s.get("mpi_ranks")),
                     number(steps), number(t_end), number(wall, 3), number(per_1000, 3),
                     number(per_second, 3)])
    return rows


def accuracy_rows(summaries):
    rows = []
    for method, s in summaries:
        for e in s.get("errors", []):
            rel = e.get("relative_error")
            tol = e.get("tolerance")
            status = "info" if tol is None else ("ok" if e.get("passed") else "**FAILED**")
            series = e.get("series")
            measured = f"RMS {number(e.get('measured'))} over {series['n_samples']} points" \
                if series else number(e.get("measured"))
            rows.append([METHOD_NAMES.get(method, method), e.get("quantity", ""), measured,
                         number(e.get("reference")),
                         "—" if rel is None else f"{100 * rel:.3g} %",
                         "—" if tol is None else f"{100 * tol:.3g} %", status, e.get("note", "")])
    return rows


def section_tables(summaries):
    out = []
    for method, s in summaries:
        sections = s.get("cost", {}).get("sections", {})
        if not sections:
            continue
        ordered = sorted(sections.items(), key=lambda kv: -kv[1].get("wall_time_s", 0))
        out.append(f"**{METHOD_NAMES.get(method, method)}**\n\n" + table(
            ["section", "calls", "wall time [s]", "share"],
            [[name, number(v.get("calls")), number(v.get("wall_time_s"), 3),
              f"{100 * v.get('fraction', 0):.1f} %"] for name, v in ordered]))
    return out


def figure_caption(png_path):
    """What the JSON beside a PNG says was drawn: 'x_front [m]: SPH, Martin & Moyce (1952)
    (reference table, 15 points)'."""
    description = os.path.splitext(png_path)[0] + ".json"
    try:
        with open(description, encoding="utf-8") as f:
            d = json.load(f)
    except (OSError, ValueError):
        return ""
    panels = []
    for p in d.get("panels", []):
        if not isinstance(p, dict) or "series" not in p:
            continue
        refs = [s for s in p["series"] if s.get("kind", "").startswith("reference")]
        if not refs:
            continue
        texts = []
        for r in refs:
            if r["kind"] == "reference value":
                texts.append(f"{r['label']} = {number(r.get('value'))}")
            else:
                texts.append(f"{r['label']} ({r.get('points', '?')} points)")
        panels.append(f"{p.get('y', '')}: against " + ", ".join(texts))
    return "; ".join(panels)


def plot_section(run_dir):
    plots = os.path.join(run_dir, "plots")
    if not os.path.isdir(plots):
        return [], []
    pngs = sorted(f for f in os.listdir(plots) if f.endswith(".png"))
    snapshots = [f for f in pngs if f.startswith("snapshot_t")]
    monitors = [f for f in pngs if f not in snapshots]
    return monitors, snapshots


def files_section(run_dir):
    rows = []
    for method in METHOD_ORDER:
        folder = os.path.join(run_dir, method)
        if not os.path.isdir(folder):
            continue
        for f in sorted(os.listdir(folder)):
            path = os.path.join(folder, f)
            if not os.path.isfile(path):
                continue
            if f.endswith((".csv", ".json", ".pvd")) or f.startswith("checkpoint"):
                rows.append(f"[`{method}/{f}`]({method}/{f})")
    return rows


def write_report(run_dir, scene, command, stopped=""):
    summaries = load_summaries(run_dir)
    if not summaries and not stopped:
        raise FileNotFoundError(f"no <method>/summary.json in {run_dir}")
    first = summaries[0][1] if summaries else {}
    name = first.get("scene", os.path.basename(os.path.normpath(run_dir)))
    lines = [f"# {name}: twinflow run report", ""]
    if stopped:
        lines += ["> **The run stopped with an error:** " + " ".join(stopped.split()), ">",
                  "> Below is what it wrote up to the stop: the monitors' plots and the summaries of "
                  "the methods that finished.", ""]
    facts = [f"- **Methods:** {', '.join(METHOD_NAMES.get(m, m) for m, _ in summaries) or 'none finished'}"]
    if "dimension" in first:
        facts.append(f"- **Dimension:** {first['dimension']}D")
    if scene:
        facts.insert(0, f"- **Scene file:** `{scene}`")
    if command:
        facts.insert(1 if scene else 0, f"- **Command:** `{command}`")
    facts.append("- **Written:** " + datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"))
    all_ok = not stopped and all(s.get("all_within_tolerance", True) for _, s in summaries)
    facts.append("- **Every checked error within its tolerance:** " + ("yes" if all_ok else "**no**"))
    lines += facts + [""]

    lines += ["## Active physics", "",
              "What the scene built; no other module was constructed or run.", ""]
    for method, s in summaries:
        physics = s.get("extra", {}).get("active physics", "—")
        lines.append(f"- **{METHOD_NAMES.get(method, method)}:** {physics}")
    lines.append("")

    lines += ["## Cost", "", "The whole run of each method (start-up, time loop, output).", "",
              table(["method", "size", "MPI ranks", "steps", "simulated time [s]", "wall time [s]",
                     "per 1000 steps [s]", "per simulated second [s]"], cost_rows(summaries))]

    accuracy = accuracy_rows(summaries)
    lines += ["## Accuracy against references", ""]
    if accuracy:
        lines += ["Relative errors; *info* rows are reported without a tolerance of their own "
                  "(e.g. the raw error beside a fitted one).", "",
                  table(["method", "quantity", "measured", "reference", "rel. error", "tolerance",
                         "status", "note"], accuracy)]
    else:
        lines += ["The scene sets no reference (References subsection).", ""]

    sections = section_tables(summaries)
    if sections:
        lines += ["## Wall time per section", ""] + sections

    monitors, snapshots = plot_section(run_dir)
    if monitors:
        lines += ["## Plots", "", "Figures with a reference first."]
        captions = {f: figure_caption(os.path.join(run_dir, "plots", f)) for f in monitors}
        monitors.sort(key=lambda f: (not captions[f], f))
        lines.append("")
        for f in monitors:
            caption = captions[f]
            lines += [f"### {os.path.splitext(f)[0]}", ""]
            if caption:
                lines += [caption, ""]
            lines += [f"![{os.path.splitext(f)[0]}](plots/{f})", ""]
    if snapshots:
        lines += ["## Snapshots", ""]
        for f in snapshots:
            t = os.path.splitext(f)[0][len("snapshot_t"):]
            lines += [f"### t = {t} s", "", f"![snapshot at t = {t} s](plots/{f})", ""]

    lines += ["## Final monitor values", ""]
    for method, s in summaries:
        values = s.get("monitors", {})
        if values:
            lines += [f"**{METHOD_NAMES.get(method, method)}**", "",
                      table(["monitor", "value"], [[k, number(v, 6)] for k, v in sorted(values.items())])]

    files = files_section(run_dir)
    if files:
        lines += ["## Files", "", "ParaView: open the `.pvd` files. Monitors: the CSV files (one row per "
                  "step). Everything above comes from the `summary.json` files.", ""]
        lines += ["- " + f for f in files] + [""]

    path = os.path.join(run_dir, "report.md")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(lines).rstrip() + "\n")
    return path


def main(argv=None):
    p = argparse.ArgumentParser(description="Write RUN_DIR/report.md for a twinflow run.")
    p.add_argument("run_dir", help="the run's output directory (Scene/Output directory)")
    p.add_argument("--scene", default="", help="the scene file that was run")
    p.add_argument("--command", default="", help="the command line that ran it")
    p.add_argument("--stopped", default="", help="the error message of a run that stopped")
    args = p.parse_args(argv)
    if not os.path.isdir(args.run_dir):
        print(f"report: not a directory: {args.run_dir}", file=sys.stderr)
        return 1
    try:
        path = write_report(args.run_dir, args.scene, args.command, args.stopped)
    except FileNotFoundError as error:
        print(f"report: {error}", file=sys.stderr)
        return 1
    print(f"report: wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
