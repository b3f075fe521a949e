#!/usr/bin/env python3
"""Overlay series of one study (scripts/study.py's study.csv) selected by filters: e.g. band AMR
against uniform refinement in one error-vs-cost plot.

usage:
  scripts/study_series.py STUDY.csv --series 'LABEL:COLUMN=VALUE' --series 'LABEL:COLUMN!=VALUE'
                          [--quantity 'drag coefficient C_d'] [--out PREFIX] [--title TEXT]

A series holds the rows (status ok) whose COLUMN equals (=) or differs from (!=) VALUE; several
conditions are joined with '&'. Writes PREFIX.png (relative error against wall time and against
the size: cells for the FEM, particles for SPH; log-log, one line per series, each point labelled
with its case number) and PREFIX.md (the rows of each series: size, DoFs, steps, wall time,
error). Run with /usr/bin/python3.
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def parse_series(spec):
    if ":" not in spec:
        raise SystemExit(f"study_series: --series '{spec}': expected LABEL:COLUMN=VALUE[&COLUMN!=VALUE...]")
    label, conditions = spec.split(":", 1)
    parsed = []
    for cond in conditions.split("&"):
        op = "!=" if "!=" in cond else "="
        if op not in cond:
            raise SystemExit(f"study_series: --series '{spec}': condition '{cond}' has no '=' or '!='")
        column, value = (s.strip() for s in cond.split(op, 1))
        parsed.append((column, op, value))
    return label.strip(), parsed


def select(rows, conditions):
    out = []
    for r in rows:
        if r.get("status") != "ok":
            continue
        ok = True
        for column, op, value in conditions:
            if column not in r:
                raise SystemExit(f"study_series: no column '{column}' in the study (columns: {', '.join(r)})")
            ok = ok and ((r[column] == value) if op == "=" else (r[column] != value))
        if ok:
            out.append(r)
    return sorted(out, key=size)


def size(row):
    """The row's problem size: its cells (FEM), else its particles (SPH)."""
    return float(row.get("cells") or row.get("particles") or 0)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("study")
    p.add_argument("--series", action="append", required=True)
    p.add_argument("--quantity", default="drag coefficient C_d")
    p.add_argument("--out", default=None)
    p.add_argument("--title", default=None)
    a = p.parse_args(argv)
    with open(a.study) as f:
        rows = list(csv.DictReader(f))
    column = "error " + a.quantity
    if rows and column not in rows[0]:
        raise SystemExit(f"study_series: no error column '{column}' (have: "
                         f"{', '.join(c[6:] for c in rows[0] if c.startswith('error '))})")
    prefix = a.out or a.study.rsplit(".", 1)[0] + "_series"
    fig, (ax_t, ax_n) = plt.subplots(1, 2, figsize=(12, 4.8))
    unit = "cells" if any(r.get("cells") for r in rows) else "particles"
    lines = [f"| series | case | {unit} | DoFs | steps | wall time [s] | error {a.quantity} |", "|---|---|---|---|---|---|---|"]
    for spec in a.series:
        label, conditions = parse_series(spec)
        chosen = select(rows, conditions)
        if not chosen:
            print(f"study_series: warning: series '{label}' selects no case", file=sys.stderr)
            continue
        err = [float(r[column]) for r in chosen]
        wall = [float(r["wall time [s]"]) for r in chosen]
        sizes = [size(r) for r in chosen]
        for ax, x in ((ax_t, wall), (ax_n, sizes)):
            ax.loglog(x, err, "o-", label=label)
            for r, xi, yi in zip(chosen, x, err):
                ax.annotate(r["case"], (xi, yi), textcoords="offset points", xytext=(4, 4), fontsize=8)
        for r in chosen:
            dofs = f"{int(float(r['dofs'])):,}" if r.get("dofs") else "—"
            lines.append(f"| {label} | {r['case']} | {int(size(r)):,} | {dofs} | {r['steps']} "
                         f"| {float(r['wall time [s]']):.1f} | {100 * float(r[column]):.3g} % |")
    for ax, xlabel in ((ax_t, "wall time [s]"), (ax_n, unit)):
        ax.set_xlabel(xlabel)
        ax.set_ylabel(f"relative error: {a.quantity}")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.suptitle(a.title or f"{a.quantity}: error against cost")
    fig.tight_layout()
    fig.savefig(prefix + ".png", dpi=110)
    with open(prefix + ".md", "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"study_series: wrote {prefix}.png and {prefix}.md")
    return 0


if __name__ == "__main__":
    sys.exit(main())
