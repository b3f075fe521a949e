#!/usr/bin/env python3
"""Draw the snapshots of a twinflow run (Scene/Snapshot times): one PNG per time.

A run directory holds ``fem/`` and/or ``sph/``; each method writes, at the first step at or
after every snapshot time, ``<method>/snapshots/<method>_t<time with 3 decimals>.csv``:

* SPH (``sph_t0.500.csv``): one row per particle, columns ``x, y[, z], speed, pressure, kind``
  (kind 0 = fluid, 1 = wall marker, 2 = solid marker; units in brackets are allowed);
* FEM (``fem_t0.500.csv``): the level set's nodal values, columns ``x, y, phi``; water where
  phi < 0; in 2D beside it ``fem_t0.500_cells.csv``, the active cells (columns ``x0, y0, ...,
  x3, y3``, corners in order around the cell), drawn as thin edges so that the refinement
  bands can be seen.

For every time found, ``<out>/snapshot_t<time>.png`` (default ``<run>/plots``) shows the FEM
water region (filled contour of phi < 0 over the scattered nodes, interface phi = 0 drawn) on
top and the SPH particles (fluid coloured by speed, markers grey) below, like the paper's
Figs 7-8; a method without a file at that time gets no panel. Every PNG of a run has the same
pixel size, the same axes limits and the same speed colour scale (0 to the largest fluid speed
over all snapshots, or ``--speed-max``), so a series can be compared frame by frame. Beside it,
``snapshot_t<time>.json`` lists what was drawn. 3D SPH snapshots are drawn in the x-z plane
through the particles within one spacing of the middle y plane.

usage: plot_snapshots.py RUN_DIR [--out DIR] [--speed-max V] [--size W H] [--dpi D]

Exit status 0 also when there is no snapshot (nothing drawn, a note on stdout); 2 for bad
arguments or an unreadable snapshot file. Uses matplotlib (Agg backend) and numpy; run with
Debian's /usr/bin/python3.
"""

import argparse
import glob
import json
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
import numpy as np  # noqa: E402

KIND_NAMES = {0: "fluid", 1: "wall", 2: "solid"}
FILE_PATTERN = re.compile(r"^(fem|sph)_t(\d+\.\d{3})\.csv$")
WATER_COLOUR = "#3b7dd8"
INTERFACE_COLOUR = "#0b2a66"
MARKER_COLOUR = "0.55"


class SnapshotError(Exception):
    """A snapshot file that cannot be read."""


def read_table(path):
    """Columns of a CSV with '#' comments and a header (units in brackets dropped)."""
    header, rows = None, []
    with open(path, encoding="utf-8") as f:
        for line in f:
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            fields = [x.strip() for x in s.split(",")]
            if header is None:
                header = [re.sub(r"\s*\[.*\]$", "", x) for x in fields]
                continue
            if len(fields) != len(header):
                raise SnapshotError(f"{path}: a row has {len(fields)} fields, the header {len(header)}")
            try:
                rows.append([float(x) for x in fields])
            except ValueError as e:
                raise SnapshotError(f"{path}: {e}") from None
    if header is None:
        raise SnapshotError(f"{path}: no header row")
    data = np.array(rows, dtype=float).reshape(len(rows), len(header))
    return {name: data[:, k] for k, name in enumerate(header)}


def require_columns(path, table, names):
    missing = [n for n in names if n not in table]
    if missing:
        raise SnapshotError(f"{path}: missing column(s) {', '.join(missing)} (has {', '.join(table)})")


def lattice_spacing(x):
    """Smallest gap between distinct coordinates (the particle spacing on a lattice)."""
    u = np.unique(np.round(x, 9))
    gaps = np.diff(u)
    gaps = gaps[gaps > 0]
    return float(gaps.min()) if gaps.size else 0.0


def read_sph(path):
    t = read_table(path)
    require_columns(path, t, ["x", "y", "speed", "kind"])
    kind = t["kind"].astype(int)
    x, y = t["x"], t["y"]
    note = ""
    if "z" in t:  # 3D: the x-z plane through the middle of y, one spacing either side
        dx = lattice_spacing(x[kind != 0]) if np.any(kind != 0) else lattice_spacing(x)
        mid = 0.5 * (y.min() + y.max())
        keep = np.abs(y - mid) <= max(dx, 1e-12)
        x, y, kind = x[keep], t["z"][keep], kind[keep]
        t = {k: v[keep] for k, v in t.items()}
        note = f"3D: x-z plane, |y - {mid:g}| <= {dx:g}"
    markers = kind != 0
    spacing = lattice_spacing(x[markers]) if np.any(markers) else lattice_spacing(x)
    return {"x": x, "y": y, "speed": t["speed"], "kind": kind, "spacing": spacing, "note": note}


def read_fem(path):
    t = read_table(path)
    require_columns(path, t, ["x", "y", "phi"])
    # nodes shared by cells may be listed once per cell: one value per point
    xy = np.round(np.column_stack([t["x"], t["y"]]), 12)
    _, first = np.unique(xy, axis=0, return_index=True)
    first.sort()
    fem = {"x": t["x"][first], "y": t["y"][first], "phi": t["phi"][first], "cells": None}
    cells_path = path[:-4] + "_cells.csv"
    if os.path.isfile(cells_path):
        c = read_table(cells_path)
        corners = [f"{a}{k}" for k in range(4) for a in "xy"]
        require_columns(cells_path, c, corners)
        fem["cells"] = np.stack([np.column_stack([c[f"x{k}"], c[f"y{k}"]]) for k in range(4)], axis=1)
        fem["cells_path"] = cells_path
    return fem


def find_snapshots(run):
    """{time label: {method: path}} for every snapshot file of the run."""
    found = {}
    for method in ("fem", "sph"):
        for path in glob.glob(os.path.join(run, method, "snapshots", f"{method}_t*.csv")):
            m = FILE_PATTERN.match(os.path.basename(path))
            if m and m.group(1) == method:
                found.setdefault(m.group(2), {})[method] = path
    return dict(sorted(found.items(), key=lambda kv: float(kv[0])))


def common_limits(data):
    """Axes limits covering every point of every snapshot (the same in every PNG)."""
    xs = [d["x"] for snap in data.values() for d in snap.values() if len(d["x"])]
    ys = [d["y"] for snap in data.values() for d in snap.values() if len(d["y"])]
    if not xs:
        return (0.0, 1.0), (0.0, 1.0)
    x0, x1 = min(a.min() for a in xs), max(a.max() for a in xs)
    y0, y1 = min(a.min() for a in ys), max(a.max() for a in ys)
    pad = 0.02 * max(x1 - x0, y1 - y0, 1e-12)
    return (x0 - pad, x1 + pad), (y0 - pad, y1 + pad)


def draw_fem(ax, fem):
    """Water (phi < 0) filled, interface phi = 0 drawn; returns the JSON entry."""
    entry = {"method": "fem", "nodes": int(len(fem["phi"])), "water_nodes": int(np.sum(fem["phi"] < 0)),
             "filled": False, "interface": False, "cells": 0}
    if fem.get("cells") is not None and len(fem["cells"]):
        # the mesh under the water: thin edges, so that the refinement bands show
        ax.add_collection(PolyCollection(fem["cells"], facecolors="none", edgecolors="0.6",
                                         linewidths=0.25, zorder=3))
        entry["cells"] = int(len(fem["cells"]))
        entry["cells_file"] = fem["cells_path"]
    if len(fem["phi"]) >= 3:
        tri = mtri.Triangulation(fem["x"], fem["y"])
        lo, hi = float(fem["phi"].min()), float(fem["phi"].max())
        if lo < 0:
            ax.tricontourf(tri, fem["phi"], levels=[lo - 1.0, 0.0], colors=[WATER_COLOUR])
            entry["filled"] = True
        if lo < 0 < hi:
            ax.tricontour(tri, fem["phi"], levels=[0.0], colors=[INTERFACE_COLOUR], linewidths=1.5)
            entry["interface"] = True
    mesh = f", {entry['cells']} cells drawn" if entry["cells"] else ""
    ax.set_title(f"FEM: level set, water where phi < 0 ({entry['nodes']} nodes{mesh})", fontsize=10)
    return entry


def draw_sph(ax, sph, vmax):
    """Fluid particles coloured by speed on [0, vmax], markers grey; returns (entry, artist)."""
    fluid, markers = sph["kind"] == 0, sph["kind"] != 0
    ax.scatter(sph["x"][markers], sph["y"][markers], s=1, c=MARKER_COLOUR, marker="s", linewidths=0)
    art = ax.scatter(sph["x"][fluid], sph["y"][fluid], s=1, c=sph["speed"][fluid], cmap="viridis", vmin=0.0,
                     vmax=vmax, linewidths=0)
    entry = {"method": "sph", "fluid_particles": int(fluid.sum()),
             "wall_markers": int(np.sum(sph["kind"] == 1)), "solid_markers": int(np.sum(sph["kind"] == 2)),
             "max_speed": float(sph["speed"][fluid].max()) if fluid.any() else 0.0, "spacing": sph["spacing"]}
    if sph["note"]:
        entry["note"] = sph["note"]
    ax.set_title(f"SPH: {entry['fluid_particles']} fluid particles coloured by speed, markers grey", fontsize=10)
    return entry, art


def size_markers(fig, ax, spacing, xlim):
    """Marker area [pt^2] so that a particle covers about its spacing on screen."""
    if spacing <= 0:
        return
    fig.canvas.draw()
    width_px = ax.get_window_extent().width
    diameter_pt = spacing * width_px / (xlim[1] - xlim[0]) * 72.0 / fig.dpi
    for c in ax.collections:
        c.set_sizes([max(diameter_pt, 0.5) ** 2])


def plot_time(label, snap, out, limits, vmax, size, dpi):
    panels = [m for m in ("fem", "sph") if m in snap]
    fig, axes = plt.subplots(len(panels), 1, figsize=size, dpi=dpi, squeeze=False, sharex=True, sharey=True)
    fig.subplots_adjust(left=0.11, right=0.87, bottom=0.07, top=0.9, hspace=0.3)
    fig.suptitle(f"t = {label} s")
    record = {"time": float(label), "label": label, "panels": [], "speed_range": [0.0, vmax]}
    for ax, method in zip(axes[:, 0], panels):
        ax.set_xlim(*limits[0])
        ax.set_ylim(*limits[1])
        ax.set_aspect("equal", adjustable="box")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("z [m]" if snap[method].get("note") else "y [m]")
        if method == "fem":
            entry = draw_fem(ax, snap["fem"])
        else:
            entry, art = draw_sph(ax, snap["sph"], vmax)
        ax.set_xlim(*limits[0])  # again: contouring may rescale
        ax.set_ylim(*limits[1])
        ax.tick_params(labelbottom=True)
        if method == "sph":
            size_markers(fig, ax, snap["sph"]["spacing"], limits[0])
            box = ax.get_position()
            cax = fig.add_axes([0.89, box.y0, 0.02, box.height])
            fig.colorbar(art, cax=cax, label="speed [m/s]")
        entry["file"] = snap[method]["path"]
        record["panels"].append(entry)
    png = os.path.join(out, f"snapshot_t{label}.png")
    fig.savefig(png, dpi=dpi)  # no tight bounding box: every PNG has the same pixel size
    plt.close(fig)
    record["png"] = png
    record["size_px"] = [int(round(size[0] * dpi)), int(round(size[1] * dpi))]
    with open(os.path.join(out, f"snapshot_t{label}.json"), "w") as f:
        json.dump(record, f, indent=2)
    return png


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("run", help="run output directory (holds fem/ and/or sph/)")
    p.add_argument("--out", help="where the PNG and JSON go (default RUN/plots)")
    p.add_argument("--speed-max", type=float, help="top of the speed colour scale [m/s] (default: largest speed)")
    p.add_argument("--size", type=float, nargs=2, default=[8.0, 8.0], metavar=("W", "H"),
                   help="figure size in inches (default 8 8)")
    p.add_argument("--dpi", type=int, default=100, help="pixels per inch (default 100)")
    a = p.parse_args(argv)
    if not os.path.isdir(a.run):
        p.error(f"run directory '{a.run}' does not exist")
    if a.speed_max is not None and not a.speed_max > 0:
        p.error(f"--speed-max {a.speed_max}: must be > 0")
    found = find_snapshots(a.run)
    if not found:
        print(f"plot_snapshots: no snapshot in {a.run}/fem/snapshots or {a.run}/sph/snapshots: nothing drawn")
        return 0
    try:
        data = {}
        for label, files in found.items():
            data[label] = {}
            for method, path in files.items():
                d = read_fem(path) if method == "fem" else read_sph(path)
                d["path"] = path
                data[label][method] = d
    except (OSError, SnapshotError) as e:
        print(f"plot_snapshots: error: {e}", file=sys.stderr)
        return 2
    vmax = a.speed_max
    if vmax is None:
        speeds = [s["sph"]["speed"][s["sph"]["kind"] == 0] for s in data.values() if "sph" in s]
        vmax = max([float(v.max()) for v in speeds if v.size] + [0.0])
        vmax = vmax if vmax > 0 and math.isfinite(vmax) else 1.0
    out = a.out or os.path.join(a.run, "plots")
    os.makedirs(out, exist_ok=True)
    limits = common_limits(data)
    for label, snap in data.items():
        print("plot_snapshots: wrote", plot_time(label, snap, out, limits, vmax, tuple(a.size), a.dpi))
    return 0


if __name__ == "__main__":
    sys.exit(main())
