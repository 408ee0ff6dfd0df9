#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""graphslam.optimize from Python against `graphslam optimize FILE` on the same files.

For each file: the tool's wall time (a process: start, read, initial guess, checks,
optimisation, exit) and its optimizer time (the report's "time:" line), against Python's
graphslam.load + graphslam.optimize in this process (after one warm-up run), with and
without a per-iteration callback, and in a new interpreter (as cold as the tool's process).
Both run the same work with the same defaults. Medians of --repeats runs. The final chi2
must agree to the tool's 10 printed digits.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead.py \
        [--tool build/apps/graphslam] [--data ../shared/datasets] [--repeats 5] [FILES...]
"""
import argparse
import os
import pathlib
import re
import statistics
import subprocess
import sys
import time

import graphslam


def tool_run(tool, path):
    t0 = time.perf_counter()
    out = subprocess.run([tool, "optimize", str(path), "--quiet"], capture_output=True,
                         text=True, check=True).stdout
    wall = time.perf_counter() - t0
    chi2 = float(re.search(r"chi2:\s+\S+ -> (\S+)", out).group(1))
    opt = float(re.search(r"time:\s+(\S+) s", out).group(1))
    return wall, opt, chi2


def python_run(path, callback=None):
    t0 = time.perf_counter()
    g = graphslam.load(path)
    t1 = time.perf_counter()
    r = graphslam.optimize(g, callback=callback)
    t2 = time.perf_counter()
    return t2 - t0, t1 - t0, r.time["total"], t2 - t1, r.final_chi2


def fresh_process_run(path):
    """graphslam.load + optimize in a new interpreter, as cold as the tool's run."""
    code = ("import sys, time; t0 = time.perf_counter(); import graphslam; "
            "graphslam.configure_process(); r = graphslam.optimize(graphslam.load(sys.argv[1])); "
            "print(time.perf_counter() - t0, r.time['total'])")
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", code, str(path)], capture_output=True, text=True,
                         check=True).stdout.split()
    return time.perf_counter() - t0, float(out[0]), float(out[1])


def main():
    here = pathlib.Path(__file__).resolve().parents[1]
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("files", nargs="*", default=["city10000.g2o", "sphere2500.g2o"])
    p.add_argument("--tool", default=str(here / "build" / "apps" / "graphslam"))
    p.add_argument("--data", default=os.environ.get("GRAPHSLAM_DATA", str(here.parent / "shared" / "datasets")))
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--no-configure", action="store_true",
                   help="leave out graphslam.configure_process() (the tool's process settings)")
    a = p.parse_args()
    if not a.no_configure:
        graphslam.configure_process()
    print(f"{'file':16s} {'tool wall':>10s} {'py wall':>10s} {'py load':>9s} {'tool opt':>9s} "
          f"{'py opt':>9s} {'py+cb':>9s} {'py call':>9s} {'new py':>9s} {'new opt':>9s}  chi2")
    for name in a.files:
        path = pathlib.Path(a.data) / name
        python_run(path)  # warm-up: page cache, first-use loads (BLAS, CHOLMOD)
        tool = [tool_run(a.tool, path) for _ in range(a.repeats)]
        py = [python_run(path) for _ in range(a.repeats)]
        with_cb = [python_run(path, callback=lambda stats: None) for _ in range(a.repeats)]
        fresh = [fresh_process_run(path) for _ in range(a.repeats)]
        med = lambda rows, k: statistics.median(r[k] for r in rows)  # noqa: E731
        chi2_tool, chi2_py = tool[0][2], py[0][4]
        same = abs(chi2_py - chi2_tool) <= 1e-9 * abs(chi2_tool)
        print(f"{name:16s} {med(tool, 0):10.4f} {med(py, 0):10.4f} {med(py, 1):9.4f} "
              f"{med(tool, 1):9.4f} {med(py, 2):9.4f} {med(with_cb, 2):9.4f} {med(py, 3):9.4f} "
              f"{med(fresh, 0):9.4f} {med(fresh, 2):9.4f}  "
              f"{chi2_py:.10g} {'=' if same else '!='} {chi2_tool:.10g}")
        if not same:
            sys.exit(f"{name}: Python's chi2 {chi2_py!r} differs from the tool's {chi2_tool!r}")
    print("seconds, medians of", a.repeats, "runs. tool wall: the process; tool opt: its optimizer. "
          "py wall/load/opt: load + optimize in this (warm) process, the load, the optimizer; "
          "py+cb: the optimizer with a Python callback per iteration; py call: the whole "
          "graphslam.optimize call (initial guess, checks, optimizer); new py / new opt: a new "
          "interpreter importing graphslam, loading and optimising (wall), and its optimizer")


if __name__ == "__main__":
    main()
