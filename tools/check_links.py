#!/usr/bin/env python3
"""Checks the relative links of README.md and docs/*.md: every linked file exists and every #anchor into a
Markdown file names one of its headings (as GitHub spells a heading's anchor). Prints each broken link and
exits 1 when there is one.

  python3 tools/check_links.py [ROOT]     ROOT: the repository (default: this script's parent folder)
"""
import glob
import os
import re
import sys


def anchor(heading):
    """The anchor GitHub gives a heading: lower case, punctuation dropped, spaces as hyphens."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def anchors_of(path, cache={}):
    if path not in cache:
        with open(path, encoding="utf-8") as f:
            text = re.sub(r"```.*?```", "", f.read(), flags=re.S)
        cache[path] = {anchor(m.group(1)) for m in re.finditer(r"^#+\s+(.*)$", text, flags=re.M)}
    return cache[path]


def broken_links(path):
    with open(path, encoding="utf-8") as f:
        text = re.sub(r"```.*?```", "", f.read(), flags=re.S)  # code blocks hold no links
    for m in re.finditer(r"\]\(([^)\s]+)\)", text):
        target = m.group(1)
        if re.match(r"[a-z]+:", target):  # https:, mailto:
            continue
        file, _, fragment = target.partition("#")
        full = os.path.normpath(os.path.join(os.path.dirname(path), file)) if file else path
        if not os.path.exists(full):
            yield f"{path}: {target}: no such file"
        elif fragment and full.endswith(".md") and fragment not in anchors_of(full):
            yield f"{path}: {target}: no heading with that anchor"


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    files = [os.path.join(root, "README.md")] + sorted(glob.glob(os.path.join(root, "docs", "*.md")))
    broken = [b for f in files for b in broken_links(f)]
    for b in broken:
        print(b)
    print(f"{len(files)} files, {len(broken)} broken links")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
