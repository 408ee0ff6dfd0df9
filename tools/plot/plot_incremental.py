#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Plot of `graphslam incremental --plot FILE.png`: the update time of every step (log
scale; steps whose relinearisation passes reached their limit marked) and chi2 after every
step, against the step. Reads the CSV of --stats (columns step, seconds,
pass_limit_reached, chi2, batch_chi2).
usage: plot_incremental.py DATA.csv OUT.png TITLE"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_style as style  # noqa: E402


def number(text):
    return float(text) if text not in ("", None) else math.nan


def main():
    data, out, title = sys.argv[1], sys.argv[2], sys.argv[3]
    with open(data, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        style.not_drawn(os.path.basename(out), "the replay has no steps", out)
        return
    step = [int(r["step"]) for r in rows]
    ms = [1e3 * number(r["seconds"]) for r in rows]
    chi2 = [number(r["chi2"]) for r in rows]
    fig, (ax_t, ax_c) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True)
    # A step's time can be 0 at the clock's resolution: drawn at the smallest positive one.
    positive = [t for t in ms if t > 0]
    floor = min(positive) if positive else 1e-6
    ax_t.plot(step, [max(t, floor) for t in ms], ".", ms=2, color="tab:blue", label="update")
    limited = [(s, max(t, floor)) for s, t, r in zip(step, ms, rows) if r.get("pass_limit_reached") == "1"]
    if limited:
        ax_t.plot([s for s, _ in limited], [t for _, t in limited], "x", ms=4, color="tab:red",
                  label=f"update that reached its pass limit ({len(limited)})")
    ax_t.set_yscale("log")
    ax_t.set_ylabel("update time [ms] (log scale)")
    ax_t.grid(True, which="both", linewidth=0.3)
    ax_t.legend(loc="upper left", fontsize=8)
    style.title(ax_t, title)
    drawn = [(s, c) for s, c in zip(step, chi2) if not math.isnan(c)]
    ax_c.plot([s for s, _ in drawn], [c for _, c in drawn], "-", lw=1, color="tab:blue",
              label="incremental")
    batch = [(s, number(r.get("batch_chi2"))) for s, r in zip(step, rows)]
    batch = [(s, c) for s, c in batch if not math.isnan(c)]
    if batch:
        ax_c.plot([s for s, _ in batch], [c for _, c in batch], "o", ms=3, mfc="none",
                  color="tab:red", label="batch solve of the same graph (--check-every)")
    style.chi2_axis(ax_c, [c for _, c in drawn + batch])
    ax_c.set_xlabel("step (poses added) [-]")
    ax_c.grid(True, linewidth=0.3)
    ax_c.legend(loc="upper left", fontsize=8)
    style.save(fig, out)


if __name__ == "__main__":
    main()
