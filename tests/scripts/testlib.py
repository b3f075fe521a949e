"""Helpers shared by the Python test scripts of tests/scripts.

check(condition, what)  print 'ok'/'FAIL' and the check; failures collects the failed ones
png_size(path)          (width, height) of a PNG file, None if it is not one
links(path)             every target of [text](target) and ![alt](target) in a markdown file
broken_links(path)      the targets that name no existing file, relative to the file's folder
"""
import os
import re
import struct

LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")

failures = []


def check(condition, what):
    print(f"{'ok  ' if condition else 'FAIL'} {what}")
    if not condition:
        failures.append(what)
    return condition


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    if head[:8] != b"\x89PNG\r\n\x1a\n":
        return None
    return struct.unpack(">II", head[16:24])


def links(path):
    with open(path, encoding="utf-8") as f:
        return LINK.findall(f.read())


def broken_links(path):
    base = os.path.dirname(os.path.abspath(path))
    return [t for t in links(path)
            if not t.startswith(("http://", "https://", "#")) and not os.path.isfile(os.path.join(base, t))]
