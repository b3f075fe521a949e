"""Links of a markdown report (report.md of a run or a study), for the tests.

links(path)        every target of [text](target) and ![alt](target), in order
broken_links(path) the targets that name no existing file, relative to the report's folder
"""
import os
import re

LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")


def links(path):
    with open(path, encoding="utf-8") as f:
        return LINK.findall(f.read())


def broken_links(path):
    base = os.path.dirname(os.path.abspath(path))
    return [t for t in links(path)
            if not t.startswith(("http://", "https://", "#")) and not os.path.isfile(os.path.join(base, t))]
