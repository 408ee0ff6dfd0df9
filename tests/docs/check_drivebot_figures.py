#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""docs/DRIVEBOT.md's figures against the commands printed under them. A figure drawn by
`graphslam drivebot ... --plot` (tools/plot/plot_drivebot.py) carries the per-step optimizer
of its run as a PNG text entry, `graphslam-optimizer`. The command under the figure, run here
for two steps, prints the optimizer it uses; the two must agree, and a run figure without the
entry fails (it was drawn before the entry existed: regenerate it with its command).

usage: check_drivebot_figures.py GRAPHSLAM DOC [--add-option FIGURE=OPTIONS] [--regenerate WORK]
  --add-option appends OPTIONS to the command of FIGURE (a file name) before running it: the
  test that this check fails when a command and its figure disagree.
  --regenerate runs every figure's command in full (outputs under WORK, run from the repository
  root) and copies the figure it names into the document's img/drivebot/ folder."""
import argparse
import os
import re
import shlex
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

# The files plot_drivebot.py writes for one run; other figures (factor graphs, comparisons of
# several runs, the pruning study) are not checked here.
RUN_FIGURES = ("errors", "covariance", "chi2", "optimization_time", "map", "loop_closure",
               "loop_closure_vehicle")


def png_text(path):
    """The tEXt/zTXt entries of a PNG file."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG file")
    entries, at = {}, 8
    while at + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + length]
        if kind == b"tEXt":
            key, _, value = body.partition(b"\0")
            entries[key.decode("latin-1")] = value.decode("latin-1")
        elif kind == b"zTXt":
            key, _, rest = body.partition(b"\0")
            entries[key.decode("latin-1")] = zlib.decompress(rest[1:]).decode("latin-1")
        at += 12 + length
    return entries


def figures(doc):
    """(figure path, the drivebot command of its caption) for every run figure of `doc`: a
    caption is the paragraph after one or more image lines, in *italics*."""
    found, images, caption = [], [], None
    for line in open(doc, encoding="utf-8").read().split("\n") + [""]:
        m = re.match(r"!\[[^\]]*\]\((img/drivebot/[^)]+\.png)\)", line)
        if m and caption is None:
            images.append(m.group(1))
        elif images and caption is None and line.startswith("*"):
            caption = line
        elif caption is not None and line.strip():
            caption += " " + line
        else:
            commands = re.findall(r"`(graphslam drivebot [^`]*)`", caption or "")
            for path in images:
                stem = os.path.basename(path)[:-4]
                if commands and any(stem.endswith("_" + kind) for kind in RUN_FIGURES):
                    found.append((path, re.split(r"\s*(?:&&|;)\s*", commands[0])[0]))
            images, caption = [], None
    return found


def command_optimizer(tool, command, root, work):
    """The per-step optimizer the documented command uses: run for two steps into `work`."""
    words = shlex.split(command)[2:]  # after "graphslam drivebot"
    args = []
    skip = False
    for w in words:
        if skip:
            skip = False
            continue
        if w in ("--out", "--max-steps"):
            skip = True
            continue
        if w in ("--plot", "-q"):
            continue
        args.append(w)
    p = subprocess.run([tool, "drivebot", *args, "--max-steps", "2", "--out", work], cwd=root,
                       capture_output=True, text=True)
    m = re.search(r"optimizer: (\w+)", p.stdout)
    if p.returncode != 0 or not m:
        return None, (p.stderr.strip() or p.stdout.strip())
    return m.group(1), ""


def regenerate(tool, doc, work):
    """Runs each distinct command of the document's run figures once and copies its figures."""
    root = os.path.dirname(os.path.dirname(os.path.abspath(doc)))
    done = {}
    for path, command in figures(doc):
        words = shlex.split(command)
        out = words[words.index("--out") + 1]
        if command not in done:
            print(f"== {command}", flush=True)
            args = [tool] + words[1:]
            args[args.index("--out") + 1] = os.path.join(work, out)
            subprocess.run(args, cwd=root, check=True)
            done[command] = os.path.join(work, out)
        stem = os.path.basename(path)[:-4]
        kind = next(k for k in sorted(RUN_FIGURES, key=len, reverse=True) if stem.endswith("_" + k))
        shutil.copyfile(os.path.join(done[command], kind + ".png"), os.path.join(os.path.dirname(doc), path))
        print(f"   {kind}.png -> {path}")
    return 0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("tool")
    ap.add_argument("doc")
    ap.add_argument("--add-option", action="append", default=[])
    ap.add_argument("--regenerate", metavar="WORK")
    a = ap.parse_args()
    if a.regenerate:
        return regenerate(os.path.abspath(a.tool), a.doc, os.path.abspath(a.regenerate))
    extra = dict(x.split("=", 1) for x in a.add_option)
    root = os.path.dirname(os.path.dirname(os.path.abspath(a.doc)))
    checked, problems, skipped = 0, [], []
    with tempfile.TemporaryDirectory() as work:
        for path, command in figures(a.doc):
            name = os.path.basename(path)
            command = command + (" " + extra[name] if name in extra else "")
            drawn = png_text(os.path.join(os.path.dirname(a.doc), path)).get("graphslam-optimizer")
            if not drawn:
                problems.append(f"{path}: no graphslam-optimizer entry: regenerate it with `{command}`")
                continue
            runs, why = command_optimizer(a.tool, command, root, os.path.join(work, str(checked)))
            if runs is None:
                if "data" in why and "folder" in why or "not found" in why:
                    skipped.append(f"{path}: skipped, its command needs what is absent here: {why}")
                    continue
                problems.append(f"{path}: `{command}` failed: {why}")
                continue
            checked += 1
            if runs != drawn:
                problems.append(f"{path} was drawn from a run with the {drawn} optimizer, but the command "
                                f"under it, `{command}`, runs the {runs} one")
    for s in skipped:
        print(s)
    if problems:
        print("\n".join(problems), file=sys.stderr)
        return 1
    if checked == 0:
        print("no figure checked: the document has no drivebot run figure", file=sys.stderr)
        return 1
    print(f"{checked} DriveBot figures match the optimizer of the command under them")
    return 0


if __name__ == "__main__":
    sys.exit(main())
