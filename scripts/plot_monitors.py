#!/usr/bin/env python3
"""Plot the monitor CSV files of twinflow runs (one PNG per monitor).

A monitor file is a CSV written by twinflow::io::CsvMonitor::

    # twinflow monitor: forces
    time [s],drag [N],lift [N]
    0.000000000000e+00,1.2e+00,-4.0e-03

Every directory given on the command line is searched for monitor files,
and so are its immediate subdirectories (a run directory with ``fem/`` and
``sph/`` subfolders). Monitors of the same name from several directories are
drawn on the same axes, labelled by directory ("FEM", "SPH"). Each PNG has one
subplot per column, plotted against the first column (the time).

A reference data set can be overlaid on one column of one monitor, e.g. the
Martin & Moyce surge front (nondimensional T, Z) on the dam-break front::

    plot_monitors.py run/ --reference martin_moyce_1952_front_n2.csv \
        --ref-x T --ref-y Z --monitor front --column x_front \
        --ref-x-scale 0.0539 --ref-y-scale 0.05715

(the options may be repeated for several overlays).

A constant reference value is drawn as a horizontal dashed line on one column's
subplot with ``--hline MONITOR:COLUMN=VALUE[:LABEL]`` (repeatable), e.g. the
body-fitted drag coefficient on the C_d(t) curves of an immersed-boundary run::

    plot_monitors.py run/ --hline "forces:C_d=5.5795:body-fitted reference" \
        --hline forces:C_l=0.0106

COLUMN is the column's name with or without its unit (``C_d`` or ``C_d [-]``);
LABEL (may contain ':') is the legend entry, by default ``COLUMN = VALUE``.
twinflow passes ``--hline forces:C_d=...:reference`` (and C_l) itself when the
scene sets References/Drag coefficient (Lift coefficient). A malformed --hline
is an error (exit status 2); one naming a monitor or column that no run wrote
gives a warning. Uses matplotlib with the Agg backend, so no display is needed.
Run with Debian's /usr/bin/python3.
"""

import argparse
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MONITOR_TAG = "# twinflow monitor:"
KNOWN_LABELS = {"fem": "FEM", "sph": "SPH"}


def split_name_unit(field):
    """'time [s]' -> ('time', 's'); 'T' -> ('T', '')."""
    field = field.strip()
    if field.endswith("]") and "[" in field:
        i = field.rindex("[")
        return field[:i].strip(), field[i + 1:-1].strip()
    return field, ""


def read_csv(path):
    """Read a CSV with '#' comment lines and a header row.

    Returns (monitor name or None, headers, columns). Rows that do not parse
    (e.g. a line being written by a running simulation) are skipped.
    """
    name, headers, columns = None, None, None
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            s = line.strip()
            if not s:
                continue
            if s.startswith("#"):
                if headers is None and name is None and s.startswith(MONITOR_TAG):
                    name = s[len(MONITOR_TAG):].strip()
                continue
            fields = [x.strip() for x in s.split(",")]
            if headers is None:
                headers = fields
                columns = [[] for _ in headers]
                continue
            if len(fields) != len(headers):
                continue
            try:
                values = [float(x) for x in fields]
            except ValueError:
                continue
            for c, v in enumerate(values):
                columns[c].append(v)
    return name, headers or [], columns or []


def find_monitors(directory):
    """{monitor name: (headers, columns)} for the monitor files directly in directory."""
    monitors = {}
    for entry in sorted(os.listdir(directory)):
        path = os.path.join(directory, entry)
        if not (entry.endswith(".csv") and os.path.isfile(path)):
            continue
        try:
            name, headers, columns = read_csv(path)
        except OSError as error:
            print(f"plot_monitors: cannot read {path}: {error}", file=sys.stderr)
            continue
        if name is None or len(headers) < 2:
            continue  # not a monitor file (e.g. a copied reference table)
        monitors[name or os.path.splitext(entry)[0]] = (headers, columns)
    return monitors


def find_sources(directories, output_dir):
    """[(label, directory, monitors)] for the directories and their subdirectories."""
    sources = []
    for d in directories:
        candidates = [d] + [
            os.path.join(d, e) for e in sorted(os.listdir(d))
            if os.path.isdir(os.path.join(d, e))
            and os.path.abspath(os.path.join(d, e)) != os.path.abspath(output_dir)
        ]
        for c in candidates:
            monitors = find_monitors(c)
            if monitors:
                base = os.path.basename(os.path.normpath(os.path.abspath(c)))
                sources.append((KNOWN_LABELS.get(base.lower(), base), c, monitors))
    return sources


def column_index(headers, column):
    for i, h in enumerate(headers):
        if h == column or split_name_unit(h)[0] == column:
            return i
    return None


HLINE_FORM = "MONITOR:COLUMN=VALUE[:LABEL]"


def parse_hline(spec):
    """'forces:C_d=5.58:body-fitted reference' -> ('forces', 'C_d', 5.58, label).

    Raises ValueError with a message saying what is wrong.
    """
    monitor, colon, rest = spec.partition(":")
    if not colon or not monitor.strip():
        raise ValueError("no 'MONITOR:' before the column")
    column, equals, rest = rest.partition("=")
    if not equals or not column.strip():
        raise ValueError("no 'COLUMN=' after the monitor")
    value_text, _, label = rest.partition(":")
    try:
        value = float(value_text)
    except ValueError:
        raise ValueError(f"the value {value_text.strip()!r} is not a number") from None
    if not math.isfinite(value):
        raise ValueError(f"the value {value_text.strip()!r} is not finite")
    column = column.strip()
    label = label.strip() or f"{column} = {value:g}"
    return monitor.strip(), column, value, label


def parse_arguments(argv):
    p = argparse.ArgumentParser(
        description="Plot twinflow monitor CSV files, one PNG per monitor.")
    p.add_argument("directories", nargs="+", help="output directories of runs")
    p.add_argument("--output-dir", help="where the PNGs go (default: DIR/plots for one "
                   "directory, else <common parent>/plots)")
    p.add_argument("--labels", nargs="+", help="legend labels of the sources, in order found")
    p.add_argument("--dpi", type=int, default=120)
    ref = p.add_argument_group("reference overlay (each option repeatable, one per overlay)")
    ref.add_argument("--reference", action="append", default=[], help="reference CSV file")
    ref.add_argument("--ref-x", action="append", default=[], help="abscissa column of it")
    ref.add_argument("--ref-y", action="append", default=[], help="ordinate column of it")
    ref.add_argument("--monitor", action="append", default=[], help="monitor to overlay on")
    ref.add_argument("--column", action="append", default=[], help="column of that monitor")
    ref.add_argument("--ref-x-scale", action="append", type=float, default=[],
                     help="x = scale * x_file (default 1)")
    ref.add_argument("--ref-y-scale", action="append", type=float, default=[],
                     help="y = scale * y_file (default 1)")
    ref.add_argument("--ref-label", action="append", default=[], help="legend label")
    p.add_argument("--hline", action="append", default=[], metavar=HLINE_FORM,
                   help="horizontal dashed line at VALUE on that column's subplot, in the "
                   "legend as LABEL (default 'COLUMN = VALUE'); repeatable")
    args = p.parse_args(argv)

    args.hlines = []
    for spec in args.hline:
        try:
            args.hlines.append(parse_hline(spec))
        except ValueError as error:
            p.error(f"--hline {spec!r}: {error}; expected {HLINE_FORM}, "
                    "e.g. --hline 'forces:C_d=5.58:body-fitted reference'")

    n = len(args.reference)
    for option in ("ref_x", "ref_y", "monitor", "column"):
        if len(getattr(args, option)) != n:
            p.error("--reference, --ref-x, --ref-y, --monitor and --column must be given "
                    "the same number of times")
    for option in ("ref_x_scale", "ref_y_scale", "ref_label"):
        if len(getattr(args, option)) > n:
            p.error(f"--{option.replace('_', '-')} given more often than --reference")
    return args


def load_references(args):
    """[(monitor, column, label, x, y)]"""
    references = []
    for i, path in enumerate(args.reference):
        _, headers, columns = read_csv(path)
        ix, iy = column_index(headers, args.ref_x[i]), column_index(headers, args.ref_y[i])
        if ix is None or iy is None:
            sys.exit(f"plot_monitors: {path} has no column {args.ref_x[i]!r} or "
                     f"{args.ref_y[i]!r} (columns: {', '.join(headers)})")
        sx = args.ref_x_scale[i] if i < len(args.ref_x_scale) else 1.0
        sy = args.ref_y_scale[i] if i < len(args.ref_y_scale) else 1.0
        label = args.ref_label[i] if i < len(args.ref_label) else \
            os.path.splitext(os.path.basename(path))[0]
        references.append((args.monitor[i], args.column[i], label,
                           [sx * v for v in columns[ix]], [sy * v for v in columns[iy]]))
    return references


def hline_matches(hline_column, column, header):
    """--hline's COLUMN names the column as its name (C_d) or its header (C_d [-])."""
    return hline_column in (column, header)


def plot_monitor(name, entries, references, hlines, output_dir, dpi):
    """entries: [(label, headers, columns)] of one monitor; hlines: [(monitor, column,
    value, label)]. Returns the PNG path."""
    names, headers_of = [], {}
    for _, headers, _ in entries:
        for h in headers[1:]:
            n = split_name_unit(h)[0]
            if n not in headers_of:
                names.append(n)
                headers_of[n] = h
    time_header = entries[0][1][0]
    fig, axes = plt.subplots(len(names), 1, sharex=True, squeeze=False,
                             figsize=(8.0, min(2.6 * len(names) + 0.8, 40.0)))
    for ax, column in zip(axes[:, 0], names):
        for k, (label, headers, columns) in enumerate(entries):
            i = column_index(headers, column)
            if i is not None:
                # the first source on top (FEM before a noisier SPH), the others a little lighter
                ax.plot(columns[0], columns[i], "-", lw=1.4 if k == 0 else 1.0, alpha=1.0 if k == 0 else 0.75,
                        zorder=2 + len(entries) - k, label=label)
        for monitor, ref_column, label, x, y in references:
            if monitor == name and ref_column == column:
                ax.plot(x, y, "o", ms=4.5, mfc="none", mec="k", label=label)
        for monitor, line_column, value, label in hlines:
            if monitor == name and hline_matches(line_column, column, headers_of[column]):
                ax.axhline(value, ls="--", lw=1.2, color="k", alpha=0.75, label=label)
        ax.set_ylabel(headers_of[column])
        ax.grid(True, alpha=0.3)
        if len(ax.get_legend_handles_labels()[0]) > 1:
            ax.legend(fontsize="small")
    axes[-1, 0].set_xlabel(time_header)
    axes[0, 0].set_title(name)
    fig.tight_layout()
    safe = "".join(c if c.isalnum() or c in "-_." else "_" for c in name)
    path = os.path.join(output_dir, safe + ".png")
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path


def main(argv=None):
    args = parse_arguments(sys.argv[1:] if argv is None else argv)
    if args.output_dir:
        output_dir = args.output_dir
    elif len(args.directories) == 1:
        output_dir = os.path.join(args.directories[0], "plots")
    else:
        common = os.path.commonpath([os.path.abspath(d) for d in args.directories])
        output_dir = os.path.join(common, "plots")

    missing = [d for d in args.directories if not os.path.isdir(d)]
    if missing:
        print("plot_monitors: not a directory: " + ", ".join(missing), file=sys.stderr)
        return 1
    sources = find_sources(args.directories, output_dir)
    if args.labels:
        sources = [(args.labels[i] if i < len(args.labels) else label, d, m)
                   for i, (label, d, m) in enumerate(sources)]
    references = load_references(args)
    if not sources:
        print("plot_monitors: no monitor files found in " + ", ".join(args.directories))
        return 0

    by_monitor = {}
    for label, _, monitors in sources:
        for name, (headers, columns) in monitors.items():
            by_monitor.setdefault(name, []).append((label, headers, columns))
    for monitor, *_ in references:
        if monitor not in by_monitor:
            print(f"plot_monitors: warning: no monitor {monitor!r} for the reference overlay",
                  file=sys.stderr)
    for monitor, column, _, _ in args.hlines:
        if monitor not in by_monitor:
            print(f"plot_monitors: warning: no monitor {monitor!r} for --hline "
                  f"{monitor}:{column}", file=sys.stderr)
            continue
        headers = list(dict.fromkeys(h for _, hs, _ in by_monitor[monitor] for h in hs[1:]))
        if not any(hline_matches(column, split_name_unit(h)[0], h) for h in headers):
            print(f"plot_monitors: warning: monitor {monitor!r} has no column {column!r} for "
                  f"--hline (columns: {', '.join(headers)})", file=sys.stderr)

    os.makedirs(output_dir, exist_ok=True)
    written = [plot_monitor(name, by_monitor[name], references, args.hlines, output_dir,
                            args.dpi)
               for name in sorted(by_monitor)]
    print(f"plot_monitors: wrote {len(written)} plot(s) to {output_dir}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
