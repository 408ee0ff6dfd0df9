#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Outlier rejection benchmark (issue 35): random wrong loop closures added to public 2D
pose graphs, then `graphslam optimize --reject-outliers`, compared with the outlier-free
optimum (`graphslam optimize` on the clean file).

usage: bench/outliers.py GRAPHSLAM [--data DIR] [--work DIR] [--files a,b] [--fractions 0.1,0.2]
                         [--seed S] [--repeats N] [--extra='OPTIONS']
                         [--kernels all|NAME,NAME] [--kernel-edges loop-closures|all|E,E]
                         [--kernel-repeats N] [--kernel-timeout S]

Per file and fraction: RMS APE (translation, SE(2)/SE(3) Umeyama-aligned, `graphslam eval
ape -a`) of the result against the clean optimum, wrong closures rejected / added, right
edges kept / candidates, and the wall time of the whole command (load, initialisation,
GNC, re-optimisation, write) against that of the clean solve (medians of --repeats runs).
Generated files go to --work (default /tmp/graphslam_outliers_bench), never the repo.

With --kernels, the same corrupted files are also optimised with each robust kernel alone
(`graphslam optimize CORRUPTED --robust-kernel K --robust-edges E`, the kernel's default
width, the tool's default initialisation), and a second table per --kernel-edges value is
printed at the end: one row per file and fraction, one column for --reject-outliers and
one per kernel, each cell "APE RMS vs clean optimum in m (time / clean time)". A kernel run
that fails (non-zero exit, or no APE) is the cell "failed"; one stopped by --kernel-timeout
is "timeout (> N x)".
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


def run_ok(cmd, timeout=None):
    """run(), but None instead of exiting when the command fails, "timeout" when it takes
    longer than timeout seconds."""
    t0 = time.perf_counter()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        print("timeout (%g s): %s" % (timeout, " ".join(cmd)), file=sys.stderr, flush=True)
        return "timeout"
    dt = time.perf_counter() - t0
    if p.returncode != 0:
        print("failed (%d): %s\n%s%s" % (p.returncode, " ".join(cmd), p.stdout[-2000:],
                                         p.stderr[-2000:]), file=sys.stderr, flush=True)
        return None
    return p.stdout, dt


def timed_ok(cmd, repeats, timeout=None):
    """timed(), but None when any run fails, "timeout" when one times out."""
    times = []
    for _ in range(repeats):
        r = run_ok(cmd, timeout)
        if r is None or r == "timeout":
            return r
        times.append(r[1])
    return statistics.median(times)


def ape_ok(gs, ref, est):
    r = run_ok([gs, "eval", "ape", ref, est, "-a"])
    m = r and re.search(r"rmse\s+(\S+)", r[0])
    return float(m.group(1)) if m else None


def cell(e, ratio):
    return "%s (%.1fx)" % ("%.4f" % e if e < 100 else "%.0f" % e, ratio)


def kernel_names(gs):
    out, _ = run([gs, "list-kernels"])
    return [line.split()[0] for line in out.splitlines() if line.strip()]


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
    ap.add_argument("--kernels", default="", help="also run each robust kernel alone: all "
                    "(every kernel of graphslam list-kernels) or a comma-separated list")
    ap.add_argument("--kernel-edges", default="loop-closures", help="--robust-edges for the "
                    "kernel runs; a comma-separated list gives one table each")
    ap.add_argument("--kernel-repeats", type=int, default=None,
                    help="repeats of each kernel run (default: --repeats)")
    ap.add_argument("--kernel-timeout", type=float, default=None,
                    help="stop a kernel run after this many seconds (cell: timeout)")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    gs = a.graphslam
    kernels = kernel_names(gs) if a.kernels == "all" else [k for k in a.kernels.split(",") if k]
    kernel_edges = a.kernel_edges.split(",")
    k_repeats = a.kernel_repeats or a.repeats
    rows = []  # (file, fraction, reject cell, {(edges, kernel): cell})
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
            e_rej = ape(gs, clean, out)
            print("| %s | %d %% (%d) | %.4f | %d / %d | %d / %d (%.2f %%) | %.3f | %.3f | %.2f |"
                  % (name, round(100 * frac), n_wrong, e_rej,
                     len(wrong & rejected), n_wrong, right - right_rejected, right,
                     100.0 * (right - right_rejected) / max(right, 1), t_clean, t_rej,
                     t_rej / t_clean), flush=True)
            cells = {}
            for edges in kernel_edges:
                for k in kernels:
                    kout = os.path.join(a.work, "%s_%s_%s_opt.g2o" % (tag, k, edges))
                    if os.path.exists(kout):
                        os.remove(kout)
                    t_k = timed_ok([gs, "optimize", bad, "--robust-kernel", k, "--robust-edges",
                                    edges, "-o", kout, "--quiet"], k_repeats, a.kernel_timeout)
                    if t_k == "timeout":
                        cells[(edges, k)] = "timeout (> %.0fx)" % (a.kernel_timeout / t_clean)
                    else:
                        e = ape_ok(gs, clean, kout) if t_k is not None else None
                        cells[(edges, k)] = "failed" if e is None else cell(e, t_k / t_clean)
                    print("  %s %s %s: %s" % (tag, edges, k, cells[(edges, k)]),
                          file=sys.stderr, flush=True)
            rows.append((name, frac, cell(e_rej, t_rej / t_clean), cells))
    for edges in kernel_edges if kernels else []:
        print("\nKernels alone (`--robust-kernel K --robust-edges %s`, default widths); "
              "cell: APE RMS vs clean optimum in m (time / clean time)\n" % edges)
        print("| file | wrong closures | --reject-outliers | " + " | ".join(kernels) + " |")
        print("|---|---:|" + "---:|" * (len(kernels) + 1))
        for name, frac, rej_cell, cells in rows:
            print("| %s | %d %% | %s | %s |" % (name, round(100 * frac), rej_cell, " | ".join(
                cells[(edges, k)] for k in kernels)), flush=True)


if __name__ == "__main__":
    main()
