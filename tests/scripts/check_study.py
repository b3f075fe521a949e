#!/usr/bin/env python3
"""Checks a study CSV.

usage: check_study.py refinement_study.csv
         DFG 2D-1 refinement study (FEM): the drag error decreases from level to level and the
         finest level meets C_d 0.5 %, C_l 5 %, dp 1 %.
       check_study.py study.csv CHECK [CHECK ...]
         SPH spacing x operator study (scripts/sph_study.py): every case must have run (status
         ok), and each CHECK must hold:
           OPS<=TOL         the error of every OPS case (consistent|standard) is <= TOL
           OPS1<OPS2        at every spacing run with both, OPS1's error is below OPS2's
           decreasing=OPS   OPS's error decreases as the spacing decreases
"""
import sys

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from compare_csv import read  # noqa: E402


OPERATORS = {0: "consistent", 1: "standard"}


def check_sph(header, rows, checks):
    col = {h.split(" [")[0]: i for i, h in enumerate(header)}
    cases = {}
    ok = True
    for r in rows:
        ops, dx = OPERATORS[int(r[col["operators"]])], r[col["spacing"]]
        status = "ok" if r[col["status"]] == 0 else "DIVERGED/FAILED"
        ok = ok and status == "ok"
        cases.setdefault(ops, {})[dx] = r[col["relative error"]]
        print("%-10s dx %-9g particles %6d steps %5d wall %7.1f s  error %.3e  %s" % (
            ops, dx, r[col["particles"]] if r[col["particles"]] == r[col["particles"]] else -1,
            r[col["steps"]] if r[col["steps"]] == r[col["steps"]] else -1, r[col["wall time"]],
            r[col["relative error"]], status))
    for check in checks:
        if check.startswith("decreasing="):
            ops = check.split("=", 1)[1]
            errs = [cases.get(ops, {})[dx] for dx in sorted(cases.get(ops, {}), reverse=True)]
            good = len(errs) >= 2 and all(b < a for a, b in zip(errs, errs[1:]))
        elif "<=" in check:
            ops, tol = check.split("<=")
            good = bool(cases.get(ops)) and all(e <= float(tol) for e in cases[ops].values())
        elif "<" in check:
            a, b = check.split("<")
            common = set(cases.get(a, {})) & set(cases.get(b, {}))
            good = bool(common) and all(cases[a][dx] < cases[b][dx] for dx in common)
        else:
            print(f"unknown check '{check}'; allowed: OPS<=TOL, OPS1<OPS2, decreasing=OPS")
            return 2
        print(f"{'ok' if good else 'FAIL':5s} {check}")
        ok = ok and good
    print("OK" if ok else "FAIL")
    return 0 if ok else 1


def main():
    header, rows = read(sys.argv[1])
    if any(h.startswith("operators") for h in header):
        return check_sph(header, rows, sys.argv[2:])
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
