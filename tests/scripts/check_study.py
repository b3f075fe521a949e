#!/usr/bin/env python3
"""Checks a DFG 2D-1 refinement study: the drag error decreases from level to level and
the finest level meets C_d 0.5 %, C_l 5 %, dp 1 %. usage: check_study.py refinement_study.csv"""
import sys

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from compare_csv import read  # noqa: E402


def main():
    header, rows = read(sys.argv[1])
    col = {h.split(" [")[0]: i for i, h in enumerate(header)}
    for r in rows:
        print("level %d: cells %d dofs %d wall %.1f s  err C_d %.2e C_l %.2e dp %.2e" % (
            r[col["level"]], r[col["cells"]], r[col["dofs"]], r[col["wall time"]],
            r[col["error C_d"]], r[col["error C_l"]], r[col["error dp"]]))
    drag = [r[col["error C_d"]] for r in rows]
    ok = all(b < a for a, b in zip(drag, drag[1:]))
    last = rows[-1]
    ok = ok and last[col["error C_d"]] < 0.005 and last[col["error C_l"]] < 0.05 and last[col["error dp"]] < 0.01
    print("OK" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
