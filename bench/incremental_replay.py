#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Incremental optimisation benchmark (issue 38): `graphslam incremental` replays each public
file pose by pose (the protocol of incremental/include/graphslam/incremental/replay.h: pose k
composed from the current estimate of pose k-1 and the odometry edge, every edge whose
largest pose endpoint is k, landmarks with their first observation, one timed update per
step) and compares its end with the batch optimum. Prints one markdown table.

usage: bench/incremental_replay.py GRAPHSLAM [--data DIR] [--files a,b] [--timeout S]
                                   [--relinearize-threshold X] [--relinearize-skip N]
                                   [--max-passes N] [--refine X] [--backsubstitution-fraction F]
                                   [--isam2 PATH [--isam2-arg A]...]

GRAPHSLAM is the graphslam binary; --data the datasets folder (default $GRAPHSLAM_DATA, else
../shared/datasets beside the repository). Columns: steps, total update time, per-step p50,
p99 and max, the final chi2 of the replay, the batch optimum (`optimize`'s defaults on the
whole file), their relative gap, and the batch optimizer's time, as `graphslam incremental`
prints them; then the gap after the optimizer's refine(X) that ends the run (--refine X,
passed on; default 1e-6, 0: none) and refine()'s time, which is not part of the total. A
file that is missing, fails or exceeds --timeout is a row saying so. Every program runs with
OPENBLAS_NUM_THREADS=1 and OMP_NUM_THREADS=1 (one thread each, as ISAM2 without TBB).

--isam2 PATH runs an external program (for example a replay written against a GTSAM build;
nothing here builds or ships one) the same way, as `PATH [ARG...] FILE.g2o`, and adds a
second table with its figures, the relative gap of its final chi2 to the batch optimum, and
the ratios graphslam / ISAM2 of the total and of p99. The
program must replay FILE with the protocol above and print, each on a line of its own
(other lines are ignored; a missing key is shown as "-"):

    steps: N                  number of steps (poses)
    total_s: SECONDS          sum of the update times
    p50_ms: MS                per-step update time percentiles (nearest rank) and maximum
    p90_ms: MS
    p99_ms: MS
    max_ms: MS
    final_chi2: VALUE         sum over the edges of e^T Omega e at its final estimate, with
                              g2o's error definitions (the chi2 graphslam reports)
"""
import argparse
import os
import re
import subprocess
import sys

FILES = ["city10000", "m3500", "intel", "victoria_park", "citytrees10000", "sphere2500", "garage"]

GRAPHSLAM_PATTERNS = {
    "steps": r"^replay: (\d+) steps",
    "total_s": r"^update time: ([0-9.e+-]+) s in all",
    "p50_ms": r"per step p50 ([0-9.e+-]+) ms",
    "p90_ms": r"p90 ([0-9.e+-]+) ms",
    "p99_ms": r"p99 ([0-9.e+-]+) ms",
    "max_ms": r"max ([0-9.e+-]+) ms",
    "final_chi2": r"^final chi2: ([0-9.e+-]+)",
    "batch_chi2": r"^batch optimum: chi2 ([0-9.e+-]+)",
    "batch_s": r"^batch optimum: chi2 [0-9.e+-]+ in ([0-9.e+-]+) s",
    "gap": r"^relative difference: ([0-9.e+-]+)",
    "refined_gap": r"^relative difference: .*; after refine ([0-9.e+-]+)",
    "refine_s": r"^after refine\([^)]*\): chi2 [0-9.e+-]+ in ([0-9.e+-]+) s",
}
ISAM2_KEYS = ["steps", "total_s", "p50_ms", "p90_ms", "p99_ms", "max_ms", "final_chi2"]


def default_data():
    env = os.environ.get("GRAPHSLAM_DATA")
    if env:
        return env
    here = os.path.dirname(os.path.abspath(__file__))
    return os.path.normpath(os.path.join(here, "..", "..", "shared", "datasets"))


# Both replays run on one thread: the BLAS that graphslam's large fronts call (OpenBLAS
# starts threads by OPENBLAS_NUM_THREADS, all cores when unset) and any OpenMP runtime.
ONE_THREAD = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}


def run(cmd, timeout):
    """(stdout, None) or (None, reason)."""
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout,
                           env=dict(os.environ, **ONE_THREAD))
    except subprocess.TimeoutExpired:
        return None, "timeout (> %g s)" % timeout
    except OSError as e:
        return None, "cannot run: %s" % e
    if p.returncode != 0:
        last = (p.stderr.strip().splitlines() or p.stdout.strip().splitlines() or [""])[-1]
        print("failed (%d): %s\n%s%s" % (p.returncode, " ".join(cmd), p.stdout[-2000:], p.stderr[-2000:]),
              file=sys.stderr, flush=True)
        if p.returncode < 0:
            return None, "killed by signal %d" % -p.returncode
        return None, "failed (exit %d): %s" % (p.returncode, last[:80])
    return p.stdout, None


def parse_graphslam(text):
    found = {}
    for key, pattern in GRAPHSLAM_PATTERNS.items():
        m = re.search(pattern, text, re.M)
        if m:
            found[key] = float(m.group(1))
    return found


def parse_isam2(text):
    found = {}
    for line in text.splitlines():
        key, sep, value = line.partition(":")
        if sep and key.strip() in ISAM2_KEYS:
            try:
                found[key.strip()] = float(value.split()[0])
            except (ValueError, IndexError):
                pass
    return found


def cell(row, key, fmt):
    return fmt % row[key] if key in row else "-"


def ratio(a, b, key):
    return "%.2f" % (a[key] / b[key]) if key in a and key in b and b[key] > 0 else "-"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("graphslam")
    ap.add_argument("--data", default=default_data())
    ap.add_argument("--files", default=",".join(FILES), help="comma-separated names without .g2o")
    ap.add_argument("--timeout", type=float, default=1800.0, help="seconds per run")
    ap.add_argument("--relinearize-threshold", type=float, default=None)
    ap.add_argument("--relinearize-skip", type=int, default=None)
    ap.add_argument("--max-passes", type=int, default=None)
    ap.add_argument("--backsubstitution-fraction", type=float, default=None)
    ap.add_argument("--refine", type=float, default=1e-6,
                    help="passed on to graphslam incremental (0: no refine)")
    ap.add_argument("--isam2", help="external replay program (see the header)")
    ap.add_argument("--isam2-arg", action="append", default=[], help="argument before FILE (repeatable)")
    args = ap.parse_args()

    ours, theirs = {}, {}
    names = [n for n in args.files.split(",") if n]
    for name in names:
        path = os.path.join(args.data, name + ".g2o")
        if not os.path.exists(path):
            ours[name] = "missing (%s)" % path
            continue
        cmd = [args.graphslam, "incremental", path]
        if args.relinearize_threshold is not None:
            cmd += ["--relinearize-threshold", repr(args.relinearize_threshold)]
        if args.relinearize_skip is not None:
            cmd += ["--relinearize-skip", str(args.relinearize_skip)]
        if args.max_passes is not None:
            cmd += ["--max-passes", str(args.max_passes)]
        if args.backsubstitution_fraction is not None:
            cmd += ["--backsubstitution-fraction", repr(args.backsubstitution_fraction)]
        if args.refine > 0:
            cmd += ["--refine", repr(args.refine)]
        print("running", " ".join(cmd), file=sys.stderr, flush=True)
        out, why = run(cmd, args.timeout)
        ours[name] = why or parse_graphslam(out)
        if args.isam2:
            out, why = run([args.isam2] + args.isam2_arg + [path], args.timeout)
            theirs[name] = why or parse_isam2(out)

    refined = args.refine > 0
    extra_head = " gap after refine | refine time |" if refined else ""
    print("| file | steps | total | p50 | p99 | max | final chi2 | batch optimum | relative gap | batch time |"
          + extra_head)
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|" + ("---:|---:|" if refined else ""))
    for name in names:
        r = ours[name]
        if isinstance(r, str):
            print("| %s | %s |  |  |  |  |  |  |  |  |%s" % (name, r, "  |  |" if refined else ""))
            continue
        extra = " %s | %s |" % (cell(r, "refined_gap", "%.2e"), cell(r, "refine_s", "%.3f s")) if refined else ""
        print("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |%s" % (
            name, cell(r, "steps", "%d"), cell(r, "total_s", "%.3f s"), cell(r, "p50_ms", "%.3f ms"),
            cell(r, "p99_ms", "%.3f ms"), cell(r, "max_ms", "%.3f ms"), cell(r, "final_chi2", "%.10g"),
            cell(r, "batch_chi2", "%.10g"), cell(r, "gap", "%.2e"), cell(r, "batch_s", "%.3f s"), extra))
    if not args.isam2:
        return
    print()
    print("| file | ISAM2 total | p50 | p99 | max | final chi2 | relative gap | graphslam / ISAM2 total "
          "| graphslam / ISAM2 p99 |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name in names:
        r, o = theirs.get(name, ours[name]), ours[name]
        if isinstance(r, str):
            print("| %s | %s |  |  |  |  |  |  |  |" % (name, r))
            continue
        o = o if isinstance(o, dict) else {}
        gap = "-"
        if "final_chi2" in r and o.get("batch_chi2"):
            gap = "%.2e" % ((r["final_chi2"] - o["batch_chi2"]) / o["batch_chi2"])
        print("| %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            name, cell(r, "total_s", "%.3f s"), cell(r, "p50_ms", "%.3f ms"), cell(r, "p99_ms", "%.3f ms"),
            cell(r, "max_ms", "%.3f ms"), cell(r, "final_chi2", "%.10g"), gap, ratio(o, r, "total_s"),
            ratio(o, r, "p99_ms")))


if __name__ == "__main__":
    main()
