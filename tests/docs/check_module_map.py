#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Checks that docs/ARCHITECTURE.md's module map and the build agree.

The build's module folders are the folders the top-level CMakeLists.txt adds with
add_subdirectory: literal names, and ${var} inside a foreach over a list set() in the same
file (GRAPHSLAM_MODULES). Each must hold a CMakeLists.txt. The map is the table of the
"## Module map" section: one row per folder, its first cell the folder in backticks
(`core/`). Fails, naming them, when a folder is missing from the map, when the map names a
folder the build does not add, or when a row is listed twice.

Usage: check_module_map.py SOURCE_DIR [--remove-row NAME] [--add-row NAME]
The two options edit the map in memory before the check, so a test can show that the check
fails when the map and the build disagree.
"""
import argparse
import os
import re
import sys


def strip_comments(text):
    return "\n".join(line.split("#", 1)[0] for line in text.splitlines())


def cmake_module_dirs(source_dir):
    path = os.path.join(source_dir, "CMakeLists.txt")
    with open(path, encoding="utf-8") as f:
        text = strip_comments(f.read())
    lists = {m.group(1): m.group(2).split()
             for m in re.finditer(r"\bset\(\s*(\w+)\s+([^)]*)\)", text)}
    loops = {m.group(1): m.group(2)
             for m in re.finditer(r"\bforeach\(\s*(\w+)\s+IN\s+LISTS\s+(\w+)\s*\)", text)}
    dirs = []
    for m in re.finditer(r"\badd_subdirectory\(\s*([^)\s]+)", text):
        arg = m.group(1)
        var = re.fullmatch(r"\$\{(\w+)\}", arg)
        if var:
            loop_list = loops.get(var.group(1))
            if loop_list is None or loop_list not in lists:
                sys.exit(f"{path}: cannot resolve add_subdirectory({arg})")
            dirs.extend(lists[loop_list])
        else:
            dirs.append(arg)
    for d in dirs:
        if not os.path.isfile(os.path.join(source_dir, d, "CMakeLists.txt")):
            sys.exit(f"{path}: add_subdirectory({d}) has no {d}/CMakeLists.txt")
    return dirs


def map_rows(doc_text, path):
    section = re.search(r"^## Module map\n(.*?)(?=^## |\Z)", doc_text, re.M | re.S)
    if not section:
        sys.exit(f"{path}: no '## Module map' section")
    rows = []
    for line in section.group(1).splitlines():
        m = re.match(r"\|\s*`([^`]+)`\s*\|", line)
        if m:
            rows.append(m.group(1).rstrip("/"))
    if not rows:
        sys.exit(f"{path}: the '## Module map' section has no table rows")
    return rows


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("source_dir")
    parser.add_argument("--remove-row", action="append", default=[])
    parser.add_argument("--add-row", action="append", default=[])
    args = parser.parse_args()

    doc = os.path.join(args.source_dir, "docs", "ARCHITECTURE.md")
    with open(doc, encoding="utf-8") as f:
        rows = map_rows(f.read(), doc)
    for name in args.remove_row:
        if name not in rows:
            sys.exit(f"--remove-row {name}: no such row in {doc}")
        rows = [r for r in rows if r != name]
    rows += args.add_row

    dirs = cmake_module_dirs(args.source_dir)
    errors = []
    for d in dirs:
        if d not in rows:
            errors.append(f"{d}/ is added by CMakeLists.txt but missing from the module map")
    for r in rows:
        if r not in dirs:
            errors.append(f"{r}/ is in the module map but CMakeLists.txt adds no such folder")
    for r in sorted({r for r in rows if rows.count(r) > 1}):
        errors.append(f"{r}/ is listed {rows.count(r)} times in the module map")
    if errors:
        for e in errors:
            print(f"{doc}: {e}", file=sys.stderr)
        return 1
    print(f"module map and CMakeLists.txt agree: {len(dirs)} folders ({' '.join(dirs)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
