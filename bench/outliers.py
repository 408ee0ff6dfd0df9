#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Outlier rejection benchmark (issue 35): random wrong loop closures added to public 2D
pose graphs, then `graphslam optimize --reject-outliers`, compared with the outlier-free
optimum (`graphslam optimize` on the clean file).

usage: bench/outliers.py GRAPHSLAM [--data DIR] [--work DIR] [--files a,b] [--fractions 0.1,0.2]
                         [--seed S] [--repeats N] [--extra='OPTIONS']

Per file and fraction: RMS APE (translation, SE(2)/SE(3) Umeyama-aligned, `graphslam eval
ape -a`) of the result against the clean optimum, wrong closures rejected / added, right
edges kept / candidates, and the wall time of the whole command (load, initialisation,
GNC, re-optimisation, write) against that of the clean solve (medians of --repeats runs).
Generated files go to --work (default /tmp/graphslam_outliers_bench), never the repo.
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import time

FILES = {  # name -> (file, ground truth or None)
    "m3500": ("m3500.g2o", None),
    "intel": ("intel.g2o", None),
    "city10000": ("city10000.g2o", "city10000_groundtruth.g2o"),
    "ring": ("ring.g2o", "ring_groundtruth.g2o"),
    "ringcity": ("ringcity.g2o", "ringcity_groundtruth.g2o"),
}


def run(cmd):
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    dt = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit("failed (%d): %s\n%s%s" % (p.returncode, " ".join(cmd), p.stdout, p.stderr))
    return p.stdout, dt


def timed(cmd, repeats):
    times, out = [], ""
    for _ in range(repeats):
        out, dt = run(cmd)
        times.append(dt)
    return out, statistics.median(times)


def ape(gs, ref, est):
    out, _ = run([gs, "eval", "ape", ref, est, "-a"])
    return float(re.search(r"rmse\s+([0-9.eE+-]+)", out).group(1))


def pairs(path):
    """Vertex-id pairs of a --list or --outliers file (line, id, id, ...)."""
    out = set()
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        f = line.split()
        out.add(tuple(sorted((int(f[1]), int(f[2])))))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("graphslam")
    ap.add_argument("--data", default=os.environ.get("GRAPHSLAM_DATA", os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "datasets")))
    ap.add_argument("--work", default="/tmp/graphslam_outliers_bench")
    ap.add_argument("--files", default=",".join(FILES))
    ap.add_argument("--fractions", default="0.1,0.2")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--extra", default="", help="options added to optimize --reject-outliers "
                    "(one string, e.g. --extra='--gnc-mu-step 2')")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    gs = a.graphslam
    print("| file | wrong closures | APE RMS vs clean optimum (m) | wrong rejected | right kept "
          "| time clean (s) | time --reject-outliers (s) | ratio |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for name in a.files.split(","):
        fname, gt = FILES[name]
        src = os.path.join(a.data, fname)
        clean = os.path.join(a.work, name + "_clean.g2o")
        _, t_clean = timed([gs, "optimize", src, "-o", clean, "--quiet"], a.repeats)
        if gt:
            print("| %s | (clean optimum vs ground truth: APE RMS %.4f m) | | | | | | |"
                  % (name, ape(gs, os.path.join(a.data, gt), clean)), flush=True)
        for frac in [float(f) for f in a.fractions.split(",")]:
            tag = "%s_%d" % (name, round(100 * frac))
            bad = os.path.join(a.work, tag + ".g2o")
            lst = os.path.join(a.work, tag + ".list")
            out = os.path.join(a.work, tag + "_opt.g2o")
            rej = os.path.join(a.work, tag + ".outliers")
            info, _ = run([gs, "add-outliers", src, "-o", bad, "--fraction", str(frac),
                           "--seed", str(a.seed), "--list", lst])
            m = re.search(r"(\d+) wrong loop closures added to (\d+) loop closures", info)
            n_wrong, n_right = int(m.group(1)), int(m.group(2))
            log, t_rej = timed([gs, "optimize", bad, "--reject-outliers", "--outliers", rej,
                                "-o", out, "--quiet"] + a.extra.split(), a.repeats)
            m = re.search(r"(\d+) of (\d+) candidate edges rejected", log)
            candidates = int(m.group(2))
            wrong, rejected = pairs(lst), pairs(rej)
            right_rejected = len(rejected - wrong)
            right = candidates - n_wrong
            print("| %s | %d %% (%d) | %.4f | %d / %d | %d / %d (%.2f %%) | %.3f | %.3f | %.2f |"
                  % (name, round(100 * frac), n_wrong, ape(gs, clean, out),
                     len(wrong & rejected), n_wrong, right - right_rejected, right,
                     100.0 * (right - right_rejected) / max(right, 1), t_clean, t_rej,
                     t_rej / t_clean), flush=True)


if __name__ == "__main__":
    main()
