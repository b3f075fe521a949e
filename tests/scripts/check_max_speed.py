#!/usr/bin/env python3
"""Largest value of a monitor column against a bound (issue 14, item 4: no fluid particle of a
dam break faster than 4 sqrt(g H); the energy bounds a dam break's speeds near 2 sqrt(g H)).

usage: check_max_speed.py CSV BOUND [--column 'max speed [m/s]']
Fails if any row is not finite or the largest value exceeds BOUND; prints the largest value,
when it occurred and how many rows exceed the bound.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
import twinflow_csv  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("bound", type=float)
    ap.add_argument("--column", default="max speed [m/s]")
    a = ap.parse_args()
    header, rows = twinflow_csv.read(a.csv)
    if a.column not in header:
        sys.exit(f"check_max_speed: no column '{a.column}' in {a.csv}; columns: {', '.join(header)}")
    i = header.index(a.column)
    values = [r[i] for r in rows]
    if not values:
        sys.exit(f"check_max_speed: {a.csv} has no rows")
    finite = all(math.isfinite(v) for v in values)
    k = max(range(len(values)), key=lambda j: values[j] if math.isfinite(values[j]) else math.inf)
    above = sum(1 for v in values if not v <= a.bound)
    ok = finite and above == 0
    print(f"{a.column}: largest {values[k]:.4g} at t = {rows[k][0]:.4g} s, bound {a.bound:.4g}; "
          f"{above} of {len(values)} rows above; finite: {finite}")
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
