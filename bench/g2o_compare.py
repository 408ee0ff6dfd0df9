#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Whole-process time of `graphslam optimize` (default settings) against the g2o command-line
tool's fastest configuration that reaches the same chi2, measured side by side.

usage: bench/g2o_compare.py --g2o PATH [--graphslam BIN] [--data DIR] [--files a,b]
                            [--solvers s1,s2] [--max-iterations N] [--repeats R]
                            [--g2o-env VAR=VALUE]... [--work DIR]

PATH is a g2o binary built elsewhere (nothing here builds or ships one). For each file:
1. graphslam optimizes it once; its final chi2 is the target.
2. Probe: g2o runs each solver of --solvers (default gn_var_cholmod, lm_var_cholmod,
   gn_var, lm_var) once with -v and -i --max-iterations; the first iteration whose chi2
   (g2o's own figure) is at or below the target times 1 + 1e-6 gives that solver's
   iteration count. A solver that never reaches it is reported with its best chi2; when
   none reaches it, each is timed at the iteration where it reached its own best instead.
3. Timed, alternating: per repeat graphslam once, then each reaching g2o solver with exactly
   its iteration count (`g2o -solver S -i N -o OUT FILE`): wall time of the whole process,
   reading and writing included. Medians of --repeats.
4. The fastest g2o run's output is scored by graphslam (reading the written file, one
   iteration with --init none: the chi2 before it), as graphslam's own output is for the
   target. g2o's own figures use the rotations it read without normalising the file's
   quaternions, so its scored chi2 can lie above the target it reported reaching.

--g2o-env sets variables for the g2o runs (default OMP_THREAD_LIMIT=1: Debian's CHOLMOD
otherwise starts more OpenMP threads than the machine has cores, which made g2o's sphere2500
run 1.5x slower on 2 cores; graphslam serialises those loops itself). Prints markdown.
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import time

FILES = ["smallgrid3d", "garage", "sphere2500", "torus3d"]
SOLVERS = ["gn_var_cholmod", "lm_var_cholmod", "gn_var", "lm_var"]
CHI2_SLACK = 1e-6  # relative: g2o "reaches" graphslam's chi2 within this


def timed(cmd, env=None):
    """Runs cmd; returns (wall seconds, stdout + stderr). Raises on a non-zero exit."""
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        raise RuntimeError("%s: exit %d\n%s" % (" ".join(cmd), proc.returncode, proc.stderr[-2000:]))
    return wall, proc.stdout + proc.stderr


def score(graphslam, path):
    """chi2 of a written graph at its own estimates, as graphslam computes it."""
    _, out = timed([graphslam, "optimize", path, "--init", "none", "-i", "1", "-q"])
    m = re.search(r"^chi2:\s+([0-9.eE+-]+) ->", out, re.M)
    if not m:
        raise RuntimeError("no chi2 line scoring " + path)
    return float(m.group(1))


def g2o_iterations(text):
    """(iteration, chi2) of g2o's -v lines."""
    return [(int(a), float(b)) for a, b in
            re.findall(r"^iteration=\s*(\d+)\s+chi2=\s*([0-9.eE+-]+)", text, re.M)]


def probe(args, env, path, target, solver, out):
    """(iterations to reach target or None, iterations to g2o's own best, its best chi2, note)."""
    try:
        _, text = timed([args.g2o, "-v", "-solver", solver, "-i", str(args.max_iterations),
                         "-o", out, path], env)
    except RuntimeError as e:
        return None, None, float("nan"), str(e).splitlines()[0]
    its = g2o_iterations(text)
    if not its:
        return None, None, float("nan"), "no iteration lines"
    best = min(c for _, c in its)
    own = next(it + 1 for it, c in its if c <= best * (1 + CHI2_SLACK))
    for it, chi2 in its:
        if chi2 <= target * (1 + CHI2_SLACK):
            return it + 1, own, best, ""
    return None, own, best, "not reached in %d iterations (best chi2 %.10g)" % (
        args.max_iterations, best)


def compare_file(args, env, name):
    path = os.path.join(args.data, name + ".g2o")
    if not os.path.exists(path):
        return "| %s | missing: %s |" % (name, path)
    ours_out = os.path.join(args.work, name + "_graphslam.g2o")
    g2o_out = os.path.join(args.work, name + "_g2o.g2o")
    ours_cmd = [args.graphslam, "optimize", path, "-q", "-o", ours_out]
    timed(ours_cmd)
    target = score(args.graphslam, ours_out)
    reaching, own_best, notes = {}, {}, []
    for solver in args.solvers:
        n, own, best, why = probe(args, env, path, target, solver, g2o_out)
        if n is not None:
            reaching[solver] = n
        else:
            notes.append("%s: %s" % (solver, why))
            if own is not None:
                own_best[solver] = (own, best)
    # No solver reaches graphslam's chi2: g2o is timed to its own best instead.
    timed_runs = reaching or {s: n for s, (n, _) in own_best.items()}
    ours_s, g2o_s = [], {s: [] for s in timed_runs}
    for _ in range(args.repeats):
        ours_s.append(timed(ours_cmd)[0])
        for solver, n in timed_runs.items():
            g2o_s[solver].append(timed([args.g2o, "-solver", solver, "-i", str(n), "-o", g2o_out,
                                        path], env)[0])
    ours = statistics.median(ours_s)
    cells, fastest = [], None
    for solver, n in timed_runs.items():
        t = statistics.median(g2o_s[solver])
        cells.append("%s -i %d: %.3f s" % (solver, n, t))
        if fastest is None or t < fastest[1]:
            fastest = (solver, t, n)
    g2o_chi2, ratio = "-", "-"
    if fastest:
        timed([args.g2o, "-solver", fastest[0], "-i", str(fastest[2]), "-o", g2o_out, path], env)
        g2o_chi2 = "%.10g" % score(args.graphslam, g2o_out)
        ratio = "%.3f" % (ours / fastest[1])
        if not reaching:
            ratio += " (g2o at its own best, above graphslam's chi2)"
    return "| %s | %.10g | %.3f s (%s) | %s | %s | %s | %s |" % (
        name, target, ours, ", ".join("%.3f" % t for t in ours_s), "; ".join(cells) or "-",
        g2o_chi2, ratio, "; ".join(notes))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--g2o", required=True, help="a g2o binary built outside this project")
    ap.add_argument("--graphslam", default=os.path.join(here, "..", "build", "apps", "graphslam"))
    ap.add_argument("--data", default=os.environ.get(
        "GRAPHSLAM_DATA", os.path.join(here, "..", "..", "shared", "datasets")))
    ap.add_argument("--files", default=",".join(FILES))
    ap.add_argument("--solvers", default=",".join(SOLVERS))
    ap.add_argument("--max-iterations", type=int, default=100)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--g2o-env", action="append", default=None,
                    help="VAR=VALUE for the g2o runs (repeatable; default OMP_THREAD_LIMIT=1)")
    ap.add_argument("--work", default="/tmp/graphslam_g2o_compare")
    args = ap.parse_args()
    args.solvers = [s for s in args.solvers.split(",") if s]
    if args.repeats < 1 or args.max_iterations < 1:
        ap.error("--repeats and --max-iterations must be at least 1")
    for binary in (args.g2o, args.graphslam):
        if not os.access(binary, os.X_OK):
            ap.error("not an executable: " + binary)
    env = dict(os.environ)
    for kv in args.g2o_env if args.g2o_env is not None else ["OMP_THREAD_LIMIT=1"]:
        if "=" not in kv:
            ap.error("--g2o-env takes VAR=VALUE, not " + kv)
        k, v = kv.split("=", 1)
        env[k] = v
    os.makedirs(args.work, exist_ok=True)
    print("load average at start: %s" % " ".join(open("/proc/loadavg").read().split()[:3]))
    print()
    print("| file | graphslam chi2 (target) | graphslam wall, median (runs) | g2o solvers reaching "
          "it: iterations, median wall | fastest g2o output scored by graphslam | graphslam / fastest g2o | "
          "not reaching |")
    print("|---|---:|---|---|---:|---:|---|")
    for name in [f for f in args.files.split(",") if f]:
        try:
            print(compare_file(args, env, name), flush=True)
        except RuntimeError as e:
            print("| %s | failed: %s |" % (name, str(e).splitlines()[0]), flush=True)
    print()
    print("load average at the end: %s" % " ".join(open("/proc/loadavg").read().split()[:3]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
