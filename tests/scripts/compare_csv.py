#!/usr/bin/env python3
"""Compares two twinflow monitor CSVs column by column.

usage: compare_csv.py A.csv B.csv RTOL
Every value must agree to RTOL relative to the column's largest magnitude
(absolute floor: RTOL times that scale). Prints the worst deviation per column.
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
from twinflow_csv import read  # noqa: E402,F401  (re-exported for the other checks)


def main():
    a_path, b_path, rtol = sys.argv[1], sys.argv[2], float(sys.argv[3])
    ha, ra = read(a_path)
    hb, rb = read(b_path)
    if ha != hb or len(ra) != len(rb) or not ra:
        print(f"FAIL: different shapes: {ha} x {len(ra)} vs {hb} x {len(rb)}")
        return 1
    ok = True
    for c, name in enumerate(ha):
        scale = max(max(abs(r[c]) for r in ra), 1e-300)
        worst = max(abs(x[c] - y[c]) for x, y in zip(ra, rb)) / scale
        status = "ok" if worst <= rtol else "FAIL"
        ok = ok and status == "ok"
        print(f"{status:5s} {name:20s} max relative deviation {worst:.3e} (tolerance {rtol:.1e})")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
