#!/usr/bin/env python3
"""Compares two twinflow monitor CSVs column by column.

usage: compare_csv.py A.csv B.csv RTOL
Every value must agree to RTOL relative to the column's largest magnitude
(absolute floor: RTOL times that scale). Prints the worst deviation per column.
"""
import sys


def read(path):
    header, rows = None, []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            if header is None:
                header = line.split(",")
                continue
            rows.append([float(v) for v in line.split(",")])
    return header, rows


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
