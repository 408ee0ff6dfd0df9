#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Timings of graphslam's viewer pages (docs/BENCHMARKS.md, "Viewer pages"): the time to
write a page (the tool's own figure, reading the graph excluded), its size, the time until
headless Chromium reports it ready (navigation to ready, and the page's own script time), and
the frame time while the view moves (orbit in 3D, pan in 2D), median of 60 frames.

  view_bench.py --graphslam build/apps/graphslam [--data DIR] [--work DIR] [--big-poses N]
"""
import argparse
import os
import re
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "browser"))
import cdp  # noqa: E402


def run(cmd):
    t0 = time.time()
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return out, time.time() - t0


def open_page(browser, page, moves):
    t0 = time.time()
    browser.call("Page.navigate", {"url": "file://" + os.path.abspath(page)})
    while not browser.evaluate("!!(window.graphslamView && window.graphslamView.ready)"):
        if time.time() - t0 > 120:
            raise RuntimeError(page + ": not ready after 120 s")
        time.sleep(0.02)
    ready = time.time() - t0
    script = browser.evaluate("window.graphslamView.readyMs")
    frame = browser.evaluate("""(() => { const v = window.graphslamView; const t = [];
      for (let i = 0; i < %d; i++) { const t0 = performance.now(); v.orbit(6, 1);
        t.push(performance.now() - t0); } t.sort((a, b) => a - b);
      return t[Math.floor(t.length / 2)]; })()""" % moves)
    errors = browser.errors()
    if errors:
        raise RuntimeError(page + ": console errors: " + "; ".join(errors))
    return ready, script, frame


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--graphslam", required=True)
    ap.add_argument("--data", default=os.environ.get("GRAPHSLAM_DATA", "../shared/datasets"))
    ap.add_argument("--work", default="/tmp/graphslam_view_bench")
    ap.add_argument("--big-poses", type=int, default=626000, help="poses of the simulated large graph")
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)
    tool, data, work = args.graphslam, args.data, args.work
    big = os.path.join(work, "big.g2o")
    if not os.path.exists(big):
        run([tool, "simulate", "--poses", str(args.big_poses), "-o", big])
    cases = [
        ("intel (view)", [tool, "view", os.path.join(data, "intel.g2o")]),
        ("intel (optimize --view, 5 frames)", None),
        ("city10000 (view)", [tool, "view", os.path.join(data, "city10000.g2o")]),
        ("sphere2500 (view, 3D)", [tool, "view", os.path.join(data, "sphere2500.g2o")]),
        ("simulated %d poses (view)" % args.big_poses, [tool, "view", big]),
    ]
    chromium = cdp.find_chromium()
    browser = cdp.Browser(chromium) if chromium else None
    print("| graph | vertices | edges | page | written | command | ready in Chromium | page script | frame while moving |")
    print("|---|---|---|---|---|---|---|---|---|")
    try:
        for name, cmd in cases:
            page = os.path.join(work, re.sub(r"[^a-z0-9]+", "_", name.lower()).strip("_") + ".html")
            if cmd is None:
                out, wall = run([tool, "optimize", os.path.join(data, "intel.g2o"), "-q", "--view", page])
                written, counts = "", re.search(r"graph: (\d+) vertices, (\d+) edges", out)
            else:
                out, wall = run(cmd + ["-o", page])
                written = "%.3f s" % float(re.search(r"KiB\) in ([0-9.e-]+) s", out).group(1))
                counts = re.search(r"(\d+) vertices, (\d+) edges", out)
            size = os.path.getsize(page)
            row = "| %s | %s | %s | %.0f KiB | %s | %.2f s |" % (
                name, counts.group(1), counts.group(2), size / 1024, written, wall)
            if browser:
                ready, script, frame = open_page(browser, page, 60)
                row += " %.2f s | %.0f ms | %.1f ms |" % (ready, script, frame)
            else:
                row += " (no Chromium) | | |"
            print(row, flush=True)
    finally:
        if browser:
            browser.close()


if __name__ == "__main__":
    main()
