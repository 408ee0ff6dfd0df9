#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Checks that the command reference of docs/TOOL.md is what the tool prints.

The reference is the text between the lines <!-- help --> and <!-- /help --> of TOOL.md:
`graphslam --help`, then `graphslam COMMAND --help` for every command that --help lists,
each under a heading and in a fenced block. Fails with a diff when it differs from what
GRAPHSLAM prints (a command added, removed or changed without its reference).

Usage: check_tool_reference.py GRAPHSLAM [--doc docs/TOOL.md] [--write]
                                         [--remove-command NAME]
--write rewrites the reference from the tool. --remove-command drops a command's block from
the documented text in memory before comparing, so a test can show that the check fails.
"""
import argparse
import difflib
import os
import re
import subprocess
import sys

BEGIN, END = "<!-- help -->", "<!-- /help -->"


def run_help(tool, *args):
    proc = subprocess.run([tool, *args, "--help"], capture_output=True, text=True, timeout=60)
    if proc.returncode != 0:
        sys.exit(f"{tool} {' '.join(args)} --help: exit {proc.returncode}\n{proc.stderr}")
    if "```" in proc.stdout:
        sys.exit(f"{tool} {' '.join(args)} --help prints ``` (it would break the page)")
    return proc.stdout.rstrip("\n")


def commands_of(main_help):
    section = main_help.split("commands:", 1)
    if len(section) != 2:
        sys.exit("graphslam --help has no 'commands:' section")
    names = re.findall(r"^  ([a-z][a-z0-9-]*)\s", section[1], re.M)
    if not names:
        sys.exit("graphslam --help lists no command")
    return names


def block(title, text):
    return f"### `{title}`\n\n```\n{text}\n```\n"


def reference(tool):
    main_help = run_help(tool)
    blocks = [block("graphslam --help", main_help)]
    for name in commands_of(main_help):
        blocks.append(block(f"graphslam {name} --help", run_help(tool, name)))
    return "\n".join(blocks)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser()
    parser.add_argument("tool")
    parser.add_argument("--doc", default=os.path.join(here, "..", "..", "docs", "TOOL.md"))
    parser.add_argument("--write", action="store_true")
    parser.add_argument("--remove-command", default=None)
    args = parser.parse_args()

    with open(args.doc, encoding="utf-8") as f:
        page = f.read()
    if page.count(BEGIN) != 1 or page.count(END) != 1 or page.index(BEGIN) > page.index(END):
        sys.exit(f"{args.doc}: needs one '{BEGIN}' line followed by one '{END}' line")
    head, rest = page.split(BEGIN, 1)
    documented, tail = rest.split(END, 1)
    expected = reference(args.tool)

    if args.write:
        with open(args.doc, "w", encoding="utf-8") as f:
            f.write(f"{head}{BEGIN}\n{expected}{END}{tail}")
        print(f"{args.doc}: command reference rewritten")
        return 0

    documented = documented.strip("\n") + "\n"
    if args.remove_command:
        pattern = rf"### `graphslam {re.escape(args.remove_command)} --help`\n\n```\n.*?\n```\n\n?"
        documented, n = re.subn(pattern, "", documented, flags=re.S)
        if n != 1:
            sys.exit(f"--remove-command {args.remove_command}: no such block in {args.doc}")
    if documented == expected:
        print(f"{args.doc}: the command reference matches {args.tool} --help")
        return 0
    print(f"{args.doc}: the command reference differs from what the tool prints "
          f"(rewrite it: {sys.argv[0]} {args.tool} --write):", file=sys.stderr)
    sys.stderr.writelines(difflib.unified_diff(
        documented.splitlines(True), expected.splitlines(True), "docs/TOOL.md", "--help"))
    return 1


if __name__ == "__main__":
    sys.exit(main())
