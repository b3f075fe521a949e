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

(the options may be repeated for several overlays). With ``--time-shift
front:x_front=KEY`` the figure in the reference axes also shows each run delayed by the
time its summary.json gives as monitor KEY (a fitted time origin).

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
gives a warning.

Every overlay of a tabulated reference also gets a figure in the reference's own axes,
``<monitor>_<ref-y>_vs_<ref-x>.png`` (e.g. ``front_Z_vs_T.png``: the runs' x_front / a
against t sqrt(2 g / a) beside the Martin & Moyce points).

The measured errors go into the legend with ``--error-label MONITOR:COLUMN=QUANTITY``
(repeatable): on that subplot each run's label is followed by the relative errors of the
``errors`` entries of its ``summary.json`` whose quantity contains QUANTITY, e.g.
``SPH: raw 10.6 %, time origin fitted 1.8 %``.

Beside each PNG, a JSON file of the same name lists what was drawn on each panel (label,
kind -- result, reference table or reference value --, source, number of points), so that a
test can check that a reference is in a plot without reading pixels. Uses matplotlib with
the Agg backend, so no display is needed. Run with Debian's /usr/bin/python3.
"""

import argparse
import json
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


def read_csv(path, strict=False):
    """Read a CSV with '#' comment lines and a header row.

    Returns (monitor name or None, headers, columns). Rows that do not parse
    (e.g. a line being written by a running simulation) are skipped, unless
    @p strict (a reference table): then such a row raises ValueError naming its line.
    """
    name, headers, columns = None, None, None
    with open(path, encoding="utf-8", errors="replace") as f:
        for line_no, line in enumerate(f, start=1):
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
                if strict:
                    raise ValueError(f"line {line_no} has {len(fields)} fields, the header "
                                     f"({', '.join(headers)}) has {len(headers)}")
                continue
            try:
                values = [float(x) for x in fields]
            except ValueError:
                if strict:
                    raise ValueError(f"line {line_no}: {s!r} is not a row of numbers") from None
                continue
            for c, v in enumerate(values):
                columns[c].append(v)
    if strict and (not headers or len(columns[0]) < 2):
        raise ValueError("expected a header line and at least two rows of numbers")
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
    ref.add_argument("--ref-x-label", action="append", default=[],
                     help="axis label of the reference's abscissa in its own axes (default: its column)")
    ref.add_argument("--ref-y-label", action="append", default=[],
                     help="axis label of the reference's ordinate in its own axes (default: its column)")
    p.add_argument("--error-label", action="append", default=[], metavar="MONITOR:COLUMN=QUANTITY",
                   help="on that subplot, follow each run's label by the relative errors of its "
                   "summary.json whose quantity contains QUANTITY; repeatable")
    p.add_argument("--time-shift", action="append", default=[], metavar="MONITOR:COLUMN=KEY",
                   help="in the reference-axes figure of that overlay, also draw each run's curve "
                   "delayed by the time its summary.json gives as monitor KEY [s] (dashed); "
                   "repeatable")
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

    def targets(option, specs, value_name, example):
        """[(monitor, column, value)] of MONITOR:COLUMN=VALUE options."""
        parsed = []
        for spec in specs:
            target, equals, value = spec.partition("=")
            monitor, colon, column = target.partition(":")
            if not (equals and colon and monitor.strip() and column.strip() and value.strip()):
                p.error(f"{option} {spec!r}: expected MONITOR:COLUMN={value_name}, e.g. {option} '{example}'")
            parsed.append((monitor.strip(), column.strip(), value.strip()))
        return parsed

    args.error_labels = targets("--error-label", args.error_label, "QUANTITY",
                                "front:x_front=front position x_f(t)")
    args.time_shifts = targets("--time-shift", args.time_shift, "KEY",
                               "front:x_front=front fitted time origin delay [s]")

    n = len(args.reference)
    for option in ("ref_x", "ref_y", "monitor", "column"):
        if len(getattr(args, option)) != n:
            p.error("--reference, --ref-x, --ref-y, --monitor and --column must be given "
                    "the same number of times")
    for option in ("ref_x_scale", "ref_y_scale", "ref_label", "ref_x_label", "ref_y_label"):
        if len(getattr(args, option)) > n:
            p.error(f"--{option.replace('_', '-')} given more often than --reference")
    return args


def load_references(args):
    """[Reference] of the --reference overlays; exits with a message naming the file and
    what is wrong when a table cannot be read."""
    references = []
    for i, path in enumerate(args.reference):
        try:
            _, headers, columns = read_csv(path, strict=True)
        except (OSError, ValueError) as error:
            sys.exit(f"plot_monitors: reference {path}: {error}")
        ix, iy = column_index(headers, args.ref_x[i]), column_index(headers, args.ref_y[i])
        if ix is None or iy is None:
            sys.exit(f"plot_monitors: {path} has no column {args.ref_x[i]!r} or "
                     f"{args.ref_y[i]!r} (columns: {', '.join(headers)})")
        def option(name, default):
            values = getattr(args, name)
            return values[i] if i < len(values) else default
        references.append(Reference(
            monitor=args.monitor[i], column=args.column[i], path=path,
            label=option("ref_label", table_title(path)),
            x_name=headers[ix], y_name=headers[iy],
            x_label=option("ref_x_label", headers[ix]), y_label=option("ref_y_label", headers[iy]),
            x_scale=option("ref_x_scale", 1.0), y_scale=option("ref_y_scale", 1.0),
            x_own=columns[ix], y_own=columns[iy]))
    return references


def table_title(path):
    """A reference table's name for a legend: its first comment line up to the first ','
    ('Martin & Moyce (1952)'), else the file's name without extension."""
    with open(path, encoding="utf-8", errors="replace") as f:
        first = f.readline().strip()
    if first.startswith("#") and first.lstrip("# ").strip():
        return first.lstrip("# ").split(",")[0].strip()
    return os.path.splitext(os.path.basename(path))[0]


class Reference:
    """A tabulated reference overlaid on MONITOR's COLUMN: its points in the file's own axes
    (x_own, y_own) and in the monitor's (x = x_scale x_own, y = y_scale y_own)."""

    def __init__(self, **fields):
        self.__dict__.update(fields)
        self.x = [self.x_scale * v for v in self.x_own]
        self.y = [self.y_scale * v for v in self.y_own]


def read_summary(directory):
    """directory/summary.json as a dict, {} if there is none."""
    try:
        with open(os.path.join(directory, "summary.json"), encoding="utf-8") as f:
            return json.load(f)
    except (OSError, ValueError):
        return {}


def error_text(errors, quantity):
    """'raw 10.6 %, time origin fitted 1.8 %' for the errors whose quantity contains QUANTITY
    (one alone: 'error 3.2 %'); '' if none. The shortest matching quantity is the raw one,
    the others are named by what they add to it."""
    matches = [e for e in errors if quantity in e.get("quantity", "")
               and isinstance(e.get("relative_error"), (int, float))]
    if not matches:
        return ""
    matches.sort(key=lambda e: len(e["quantity"]))
    base = matches[0]["quantity"]
    parts = []
    for k, e in enumerate(matches):
        name = ("raw" if len(matches) > 1 else "error") if k == 0 else \
            (e["quantity"][len(base):] if e["quantity"].startswith(base) else e["quantity"]).strip(" ,:")
        parts.append(f"{name} {100 * e['relative_error']:.3g} %")
    return ", ".join(parts)


def hline_matches(hline_column, column, header):
    """--hline's COLUMN names the column as its name (C_d) or its header (C_d [-])."""
    return hline_column in (column, header)


def safe_name(name):
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in name)


def write_description(png, description):
    """The JSON beside @p png: what each panel shows."""
    with open(os.path.splitext(png)[0] + ".json", "w", encoding="utf-8") as f:
        json.dump(description, f, indent=1)
        f.write("\n")


def run_label(label, summary, name, column, error_labels):
    """The legend label of one run on MONITOR name's COLUMN, with the measured errors of its
    summary."""
    errors = summary.get("errors", [])
    texts = [error_text(errors, q) for m, c, q in error_labels if m == name and c == column]
    texts = [t for t in texts if t]
    return label + (": " + "; ".join(texts) if texts else "")


def plot_monitor(name, entries, references, hlines, error_labels, output_dir, dpi):
    """entries: [(label, headers, columns, summary)] of one monitor; hlines: [(monitor, column,
    value, label)]. Returns the PNG path."""
    names, headers_of = [], {}
    for _, headers, _, _ in entries:
        for h in headers[1:]:
            n = split_name_unit(h)[0]
            if n not in headers_of:
                names.append(n)
                headers_of[n] = h
    time_header = entries[0][1][0]
    fig, axes = plt.subplots(len(names), 1, sharex=True, squeeze=False,
                             figsize=(8.0, min(2.6 * len(names) + 0.8, 40.0)))
    panels = []
    for ax, column in zip(axes[:, 0], names):
        series = []
        for k, (label, headers, columns, summary) in enumerate(entries):
            i = column_index(headers, column)
            if i is not None:
                text = run_label(label, summary, name, column, error_labels)
                # the first source on top (FEM before a noisier SPH), the others a little lighter
                ax.plot(columns[0], columns[i], "-", lw=1.4 if k == 0 else 1.0, alpha=1.0 if k == 0 else 0.75,
                        zorder=2 + len(entries) - k, label=text)
                series.append({"label": text, "kind": "result", "source": label,
                               "points": len(columns[i])})
        for r in references:
            if r.monitor == name and r.column == column:
                ax.plot(r.x, r.y, "o", ms=4.5, mfc="none", mec="k", label=r.label)
                series.append({"label": r.label, "kind": "reference table", "file": r.path,
                               "points": len(r.x)})
        for monitor, line_column, value, label in hlines:
            if monitor == name and hline_matches(line_column, column, headers_of[column]):
                ax.axhline(value, ls="--", lw=1.2, color="k", alpha=0.75, label=label)
                series.append({"label": label, "kind": "reference value", "value": value})
        ax.set_ylabel(headers_of[column])
        ax.grid(True, alpha=0.3)
        if len(ax.get_legend_handles_labels()[0]) > 1 or any(s["label"] != s.get("source") for s in series):
            ax.legend(fontsize="small")
        panels.append({"x": time_header, "y": headers_of[column], "series": series})
    axes[-1, 0].set_xlabel(time_header)
    axes[0, 0].set_title(name)
    fig.tight_layout()
    path = os.path.join(output_dir, safe_name(name) + ".png")
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    write_description(path, {"figure": os.path.basename(path), "monitor": name, "panels": panels})
    return path


def plot_in_reference_axes(r, entries, error_labels, time_shifts, output_dir, dpi):
    """The runs' COLUMN of r's monitor mapped into the reference's own axes (time / x_scale
    and value / y_scale: Z against T for the dam-break front) beside the reference points.
    Returns the PNG path, or None if no run wrote that column."""
    fig, ax = plt.subplots(figsize=(7.0, 4.6))
    series = []
    for k, (label, headers, columns, summary) in enumerate(entries):
        i = column_index(headers, r.column)
        if i is None:
            continue
        text = run_label(label, summary, r.monitor, r.column, error_labels)
        line, = ax.plot([t / r.x_scale for t in columns[0]], [v / r.y_scale for v in columns[i]],
                        "-", lw=1.4 if k == 0 else 1.0, label=text)
        series.append({"label": text, "kind": "result", "source": label, "points": len(columns[i])})
        for monitor, column, key in time_shifts:
            tau = summary.get("monitors", {}).get(key)
            if monitor == r.monitor and column == r.column and isinstance(tau, (int, float)) and tau:
                shifted = f"{label}, delayed by {tau:.3g} s ({key})"
                ax.plot([(t + tau) / r.x_scale for t in columns[0]],
                        [v / r.y_scale for v in columns[i]], "--", lw=1.0,
                        color=line.get_color(), label=shifted)
                series.append({"label": shifted, "kind": "result, time-shifted", "source": label,
                               "shift": tau, "points": len(columns[i])})
    if not series:
        plt.close(fig)
        return None
    ax.plot(r.x_own, r.y_own, "o", ms=5, mfc="none", mec="k", label=r.label)
    series.append({"label": r.label, "kind": "reference table", "file": r.path,
                   "points": len(r.x_own)})
    # the window of the reference, with a margin: the comparison's range
    xs = [v for v in r.x_own]
    ax.set_xlim(0.0 if min(xs) >= 0 else min(xs), 1.1 * max(xs))
    ax.set_xlabel(r.x_label)
    ax.set_ylabel(r.y_label)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize="small")
    ax.set_title(f"{r.monitor}: {split_name_unit(r.column)[0]} in the axes of {r.label}")
    fig.tight_layout()
    path = os.path.join(output_dir, safe_name(f"{r.monitor}_{split_name_unit(r.y_name)[0]}_vs_"
                                              f"{split_name_unit(r.x_name)[0]}") + ".png")
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    write_description(path, {"figure": os.path.basename(path), "monitor": r.monitor, "panels": [
        {"x": r.x_label, "y": r.y_label, "series": series}]})
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
    for label, directory, monitors in sources:
        summary = read_summary(directory)
        for name, (headers, columns) in monitors.items():
            by_monitor.setdefault(name, []).append((label, headers, columns, summary))
    for r in references:
        if r.monitor not in by_monitor:
            print(f"plot_monitors: warning: no monitor {r.monitor!r} for the reference overlay",
                  file=sys.stderr)
    for monitor, column, _, _ in args.hlines:
        if monitor not in by_monitor:
            print(f"plot_monitors: warning: no monitor {monitor!r} for --hline "
                  f"{monitor}:{column}", file=sys.stderr)
            continue
        headers = list(dict.fromkeys(h for _, hs, _, _ in by_monitor[monitor] for h in hs[1:]))
        if not any(hline_matches(column, split_name_unit(h)[0], h) for h in headers):
            print(f"plot_monitors: warning: monitor {monitor!r} has no column {column!r} for "
                  f"--hline (columns: {', '.join(headers)})", file=sys.stderr)

    os.makedirs(output_dir, exist_ok=True)
    written = [plot_monitor(name, by_monitor[name], references, args.hlines, args.error_labels,
                            output_dir, args.dpi)
               for name in sorted(by_monitor)]
    for r in references:
        if r.monitor in by_monitor:
            path = plot_in_reference_axes(r, by_monitor[r.monitor], args.error_labels,
                                          args.time_shifts, output_dir, args.dpi)
            if path:
                written.append(path)
    print(f"plot_monitors: wrote {len(written)} plot(s) to {output_dir}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
