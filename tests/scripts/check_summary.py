#!/usr/bin/env python3
"""Checks the accuracy section of a twinflow summary.json against tolerances.

usage: check_summary.py SUMMARY.json QUANTITY=MAX_RELATIVE_ERROR [...]
QUANTITY is matched against the error entry's name: an exact match first, else the first entry
whose name starts with it (e.g. 'drag', 'lift', 'pressure difference'). Exits 1 (with a table) if an entry is missing or above tolerance.
"""
import json
import sys


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    with open(sys.argv[1]) as f:
        summary = json.load(f)
    errors = summary.get("errors", [])
    ok = True
    for spec in sys.argv[2:]:
        name, tol = spec.split("=")
        tol = float(tol)
        entry = next((e for e in errors if e.get("quantity", "") == name),
                     next((e for e in errors if e.get("quantity", "").startswith(name)), None))
        if entry is None:
            print(f"MISSING  {name}: no such error entry in {sys.argv[1]}")
            ok = False
            continue
        rel = entry.get("relative_error")
        status = "ok" if rel is not None and rel <= tol else "FAIL"
        ok = ok and status == "ok"
        print(f"{status:7s} {entry['quantity']}: measured {entry.get('measured')} reference "
              f"{entry.get('reference')} relative error {rel:.3e} (tolerance {tol:.3e})")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
