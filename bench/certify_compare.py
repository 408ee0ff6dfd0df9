#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Whole-process time of `graphslam certify` (solve + verify, reading included) on SE-Sync's
nine public files, and of SE-Sync's own binary side by side when one is given.

usage: bench/certify_compare.py [--graphslam BIN] [--data DIR] [--files a,b] [--repeats R]
                                [--sesync PATH]

PATH is SE-Sync's example program built elsewhere from its public repository (nothing here
builds or ships it); it is run as `PATH FILE` (its command line takes the .g2o file). Runs
alternate (graphslam, then SE-Sync) per repeat; medians of --repeats. graphslam's figures
(F, dual bound, relative suboptimality bound, lambda_min, rank, its own solve + verify time)
come from its report. cubicle is read with --information isotropic (some of its information
blocks are not positive definite). Prints a markdown table.
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import time

FILES = ["manhattan_sesync", "city10000", "csail_sesync", "intel", "ais2klinik", "sphere2500",
         "torus3d", "garage", "cubicle"]
F_STAR = {"manhattan_sesync": 6.432e3, "city10000": 6.386e2, "csail_sesync": 3.170e1,
          "intel": 5.235e1, "ais2klinik": 1.885e2, "sphere2500": 1.687e3, "torus3d": 2.423e4,
          "garage": 1.263e0, "cubicle": 7.171e2}


def timed(cmd):
    """Runs cmd; returns (wall seconds, exit code, stdout + stderr)."""
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    return time.perf_counter() - start, proc.returncode, proc.stdout + proc.stderr


def number(pattern, text):
    m = re.search(pattern, text)
    return m.group(1) if m else "?"


def ours(binary, path, name):
    cmd = [binary, "certify", path]
    if name == "cubicle":
        cmd += ["--information", "isotropic"]
    wall, rc, out = timed(cmd)
    return wall, {
        "certified": rc == 0 and "certified globally optimal" in out,
        "F": number(r"F\(x\) ([0-9.e+-]+)", out),
        "dual": number(r"dual bound ([0-9.e+-]+)", out),
        "subopt": number(r"suboptimality bound ([0-9.e+-]+)", out),
        "lambda": number(r"lambda_min\(S\) ([0-9.e+-]+)", out),
        "rank": number(r"\n  rank ([0-9]+);", out),
        "time": number(r"; time ([0-9.]+) s", out),
    }


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--graphslam", default=os.path.join(here, "..", "build", "apps", "graphslam"))
    ap.add_argument("--data", default=os.environ.get("GRAPHSLAM_DATA", os.path.join(here, "..", "..", "shared", "datasets")))
    ap.add_argument("--files", default=",".join(FILES))
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--sesync", default="")
    a = ap.parse_args()
    rows = []
    for name in a.files.split(","):
        path = os.path.join(a.data, name + ".g2o")
        if not os.path.exists(path):
            print("skipping %s: %s not found" % (name, path), file=sys.stderr)
            continue
        walls, times, sesync_walls, info = [], [], [], None
        for _ in range(a.repeats):
            wall, info = ours(a.graphslam, path, name)
            walls.append(wall)
            times.append(float(info["time"]) if info["time"] != "?" else float("nan"))
            if a.sesync:
                s_wall, s_rc, _ = timed([a.sesync, path])
                sesync_walls.append(s_wall if s_rc == 0 else float("nan"))
        info["time"] = "%.3f" % statistics.median(times)
        rows.append((name, info, statistics.median(walls),
                     statistics.median(sesync_walls) if sesync_walls else None))
    print("| file | certified | F(x) | SE-Sync's f* | dual bound | rel. suboptimality | "
          "lambda_min(S) | rank | certify (solve + verify) s | whole process s | SE-Sync s |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, i, wall, s in rows:
        print("| %s | %s | %s | %.4g | %s | %s | %s | %s | %s | %.3f | %s |" % (
            name, "yes" if i["certified"] else "**no**", i["F"], F_STAR.get(name, float("nan")),
            i["dual"], i["subopt"], i["lambda"], i["rank"], i["time"], wall,
            "%.3f" % s if s is not None else "-"))


if __name__ == "__main__":
    main()
