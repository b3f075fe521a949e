#!/usr/bin/env python3
"""Plots a twinflow refinement study: relative error against wall time and against DoFs.

usage: plot_study.py refinement_study.csv   (writes refinement_study.png beside it)
"""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from twinflow_csv import read  # noqa: E402


def main():
    path = sys.argv[1]
    header, rows = read(path)
    header = [h.split(" [")[0] for h in header]
    col = {name: i for i, name in enumerate(header)}
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for name in header:
        if not name.startswith("error "):
            continue
        pts = [(r[col["wall time"]], r[col["dofs"]], r[col[name]]) for r in rows
               if not math.isnan(r[col[name]]) and r[col[name]] > 0]
        if not pts:
            continue
        label = name.replace("error ", "")
        axes[0].loglog([p[0] for p in pts], [p[2] for p in pts], "o-", label=label)
        axes[1].loglog([p[1] for p in pts], [p[2] for p in pts], "o-", label=label)
    axes[0].set_xlabel("wall time [s]")
    axes[1].set_xlabel("DoFs")
    for ax in axes:
        ax.set_ylabel("relative error")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.suptitle("Refinement study: what accuracy costs")
    fig.tight_layout()
    out = os.path.splitext(path)[0] + ".png"
    fig.savefig(out, dpi=120)
    print(f"plot_study: wrote {out}")


if __name__ == "__main__":
    sys.exit(main())
