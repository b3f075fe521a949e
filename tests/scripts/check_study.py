#!/usr/bin/env python3
"""Checks the table of a study (scripts/study.py: DIR/study.csv).

usage: check_study.py study.csv [CHECK ...]

Every case must have run (status ok) and every row must have its error; then each CHECK
must hold. A CHECK is [QUANTITY:]RULE, QUANTITY an error quantity of the study or the
unique beginning of one ('drag' for 'drag coefficient C_d'; default: the first error column).
RULE is one of
  SEL<=TOL          the error of every SEL row is <= TOL
  SEL1<SEL2         SEL1's error is below SEL2's wherever both ran with the same other
                    entries (e.g. consistent<standard at every spacing)
  decreasing=SEL    the error of the SEL rows decreases as the size (DoFs, particles or
                    cells) grows, for each method and each value of the other entries
SEL is a value of a varied entry (e.g. consistent), a method (fem, sph), 'all', or 'finest'
(the largest case of each method).
Examples: check_study.py study.csv "consistent<=0.01" "consistent<standard"
          check_study.py study.csv "drag:decreasing=all" "drag:finest<=0.005"
"""
import csv
import sys


def number(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return None


def main(argv):
    if not argv:
        print(__doc__)
        return 2
    with open(argv[0], newline="") as f:
        reader = csv.DictReader(f)
        header, rows = reader.fieldnames, list(reader)
    varied = header[header.index("folder") + 1:header.index("method")]
    errors = [h[len("error "):] for h in header if h.startswith("error ")]
    if not errors:
        print("FAIL: the study has no error column (does the scene have references?)")
        return 1

    def size(r):
        for key in ("dofs", "particles", "cells"):
            if number(r.get(key)) is not None:
                return number(r[key])
        return 0.0

    finest = {}
    for r in rows:
        if size(r) >= finest.get(r["method"], -1):
            finest[r["method"]] = size(r)

    def selected(r, sel):
        if not r["method"]:
            return False  # a case without a summary: reported above
        return (sel == "all" or r["method"] == sel or any(r[e] == sel for e in varied) or
                (sel == "finest" and size(r) == finest.get(r["method"])))

    ok = True
    for r in rows:
        good = r["status"] == "ok" and all(number(r["error " + q]) is not None for q in errors[:1])
        ok = ok and good
        print(f"{'ok  ' if good else 'FAIL'} case {r['case']:>3} {r['method'] or '—':4s} " +
              " ".join(f"{e.split('/')[-1]}={r[e]}" for e in varied) +
              f"  size {size(r):g}  wall {r['wall time [s]'] or r['case wall time [s]']} s  " +
              "  ".join(f"{q} {r['error ' + q] or '—'}" for q in errors) +
              ("" if r["status"] == "ok" else f"  [{r['status']}: {r['message']}]"))

    for check in argv[1:]:
        quantity, rule = errors[0], check
        if ":" in check:
            name, rest = check.rsplit(":", 1)
            match = [q for q in errors if q == name] or [q for q in errors if q.startswith(name)]
            if len(match) != 1:
                print(f"FAIL {check}: '{name}' names {'no' if not match else 'more than one'} error quantity "
                      f"of the study; allowed: {', '.join(errors)} (or a unique beginning)")
                return 2
            quantity, rule = match[0], rest
        col = "error " + quantity

        def err(r):
            return number(r[col])
        if rule.startswith("decreasing="):
            sel = rule.split("=", 1)[1]
            groups = {}
            for r in rows:
                if selected(r, sel) and err(r) is not None:
                    groups.setdefault((r["method"],) + tuple(r[e] for e in varied[1:]), []).append(r)
            good = bool(groups) and all(len(g) >= 2 for g in groups.values())
            for g in groups.values():
                errs = [err(r) for r in sorted(g, key=size)]
                good = good and all(b < a for a, b in zip(errs, errs[1:]))
        elif "<=" in rule:
            sel, tol = rule.split("<=", 1)
            picked = [r for r in rows if selected(r, sel)]
            good = bool(picked) and all(err(r) is not None and err(r) <= float(tol) for r in picked)
        elif "<" in rule:
            a, b = rule.split("<", 1)
            column = next((e for e in varied if any(r[e] == a for r in rows)), "method")
            others = [e for e in varied if e != column] + (["method"] if column != "method" else [])
            index = {tuple(r[e] for e in others): r for r in rows if r[column] == b}
            pairs = [(r, index.get(tuple(r[e] for e in others))) for r in rows if r[column] == a]
            pairs = [(x, y) for x, y in pairs if y is not None and err(x) is not None and err(y) is not None]
            good = bool(pairs) and all(err(x) < err(y) for x, y in pairs)
        else:
            print(f"unknown check '{check}'; allowed: [QUANTITY:]SEL<=TOL, SEL1<SEL2, decreasing=SEL")
            return 2
        print(f"{'ok  ' if good else 'FAIL'} {quantity}: {rule}")
        ok = ok and good
    print("OK" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
