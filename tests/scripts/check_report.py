#!/usr/bin/env python3
"""Check a run's report.md (scripts/report.py).

usage: check_report.py RUN_DIR [--stopped REGEX]

report.md exists, every link in it names an existing file, and it shows every PNG of
RUN_DIR/plots. With --stopped: the report starts with the stop ("The run stopped with an
error:") and the message matches REGEX. Exit status 1 on any failure.
"""
import argparse
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from testlib import broken_links, check, failures, links  # noqa: E402


def main():
    p = argparse.ArgumentParser()
    p.add_argument("run_dir")
    p.add_argument("--stopped", help="regex the stop message must match")
    a = p.parse_args()
    report = os.path.join(a.run_dir, "report.md")
    if not check(os.path.isfile(report), f"{report} exists"):
        return 1
    check(not broken_links(report), f"every link names a file (broken: {broken_links(report)})")
    plots = os.path.join(a.run_dir, "plots")
    pngs = sorted("plots/" + f for f in os.listdir(plots) if f.endswith(".png")) if os.path.isdir(plots) else []
    targets = links(report)
    check(pngs and all(p in targets for p in pngs), f"the report shows every PNG ({pngs})")
    if a.stopped:
        with open(report, encoding="utf-8") as f:
            text = f.read()
        head = text.split("\n## ")[0]
        check("The run stopped with an error:" in head and re.search(a.stopped, head) is not None,
              f"the stop and its message /{a.stopped}/ head the report")
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
