#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Plots of `graphslam eval --plot DIR`: trajectories overlaid, error per pose, and the
error colour-mapped on the estimated trajectory. Reads DIR/<metric>_{reference,estimate,
estimate_all,errors}.csv and DIR/<metric>_with<k>.csv (--plot-with). Every pose of the
estimate is drawn; poses the metric could not compare (no reference pose at their
timestamp) are marked and named, never dropped.
usage: plot_eval.py DIR METRIC TITLE UNIT EST_NAME [WITH_NAME...]"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_style as style  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]} if rows else {"t": [], "x": [], "y": []}


def time_label(ts):
    """An index when the timestamps count 0, 1, 2, ... (graphslam's .g2o/TUM convention)."""
    if ts and all(float(t).is_integer() for t in ts):
        return "pose index (= timestamp)"
    return "timestamp [s]"


def unmatched(est_all, est):
    used = set(est["t"])
    return [k for k, t in enumerate(est_all["t"]) if t not in used]


def mark_unmatched(ax, est_all, missing):
    for n, k in enumerate(missing):
        ax.plot([est_all["x"][k]], [est_all["y"][k]], "o", mfc="none", mec="tab:red", ms=9,
                label="no reference pose: not in the statistics" if n == 0 else None, zorder=4)
        ax.annotate(f"pose {est_all['t'][k]:g}", (est_all["x"][k], est_all["y"][k]), textcoords="offset points",
                    xytext=(6, -10), fontsize=8, color="tab:red")


def loop_note(traj):
    """Names the last pose; where the trajectory nearly returns to its start (a loop that
    should close), also how far from the first pose it ends."""
    x, y, t = traj["x"], traj["y"], traj["t"]
    note = f"pose {t[-1]:g}"
    extent = max(max(x) - min(x), max(y) - min(y))
    gap = ((x[-1] - x[0]) ** 2 + (y[-1] - y[0]) ** 2) ** 0.5
    if len(t) > 2 and 0 < gap < 0.1 * extent:
        note += f": {gap:.3g} m from pose {t[0]:g}"
    return note


def trajectories(out_dir, metric, title, names, ref, est_all, missing):
    fig, ax = plt.subplots(figsize=(7.5, 6.5))
    ax.plot(ref["x"], ref["y"], "--o", color="gray", ms=3, label="reference")
    ax.plot(est_all["x"], est_all["y"], "-o", color="tab:blue", ms=3,
            label=f"{names[0]} ({len(est_all['t'])} poses)")
    colors = ["tab:green", "tab:purple", "tab:brown", "tab:olive"]
    for k, name in enumerate(names[1:]):
        extra = read(os.path.join(out_dir, f"{metric}_with{k}.csv"))
        ax.plot(extra["x"], extra["y"], "-s", color=colors[k % len(colors)], ms=3,
                label=f"{name} ({len(extra['t'])} poses, as read)")
        # Written towards the middle of the plot, so it is never cut at the border.
        right = extra["x"][-1] > 0.5 * (min(extra["x"]) + max(extra["x"]))
        ax.annotate(loop_note(extra), (extra["x"][-1], extra["y"][-1]), textcoords="offset points",
                    xytext=(-8 if right else 8, 8), ha="right" if right else "left", fontsize=8,
                    color=colors[k % len(colors)])
    mark_unmatched(ax, est_all, missing)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=8)
    style.title(ax, title)
    style.save(fig, f"{out_dir}/{metric}_trajectories.png")


def error_curve(out_dir, metric, title, unit, err, missing_ts):
    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(err["t"], err["error"], "-o", ms=3, color="tab:blue")
    e = sorted(err["error"])
    n = len(e)
    mean = sum(e) / n
    rmse = (sum(x * x for x in e) / n) ** 0.5
    median = e[n // 2] if n % 2 else 0.5 * (e[n // 2 - 1] + e[n // 2])
    for value, name, line in ((rmse, "rmse", "-"), (mean, "mean", "--"), (median, "median", ":")):
        ax.axhline(value, linestyle=line, color="tab:red", linewidth=1, label=f"{name} {value:.6g} {unit}")
    ax.set_ylim(bottom=0)
    for t in missing_ts:  # inside the axes, left of the line: never clipped
        ax.axvline(t, color="tab:red", lw=0.8, alpha=0.5)
        ax.text(t, 0.97 * ax.get_ylim()[1], f"pose {t:g}: no reference, not compared ", fontsize=7,
                color="tab:red", va="top", ha="right")
    ax.set_xlabel(time_label(err["t"]))
    ax.set_ylabel(f"{metric.upper()} [{unit}]")
    ax.legend(fontsize=8)
    style.title(ax, title)
    style.save(fig, f"{out_dir}/{metric}_error.png")


def error_map(out_dir, metric, title, unit, ref, est, err, est_all, missing):
    fig, ax = plt.subplots(figsize=(7.5, 6.5))
    ax.plot(ref["x"], ref["y"], "--", color="gray", label="reference")
    # Colour each pose of the estimate by the error ending there (RPE: at the pair's second pose).
    index = {t: i for i, t in enumerate(est["t"])}
    xs, ys, cs = [], [], []
    for t, value in zip(err["t"], err["error"]):
        i = index.get(t)
        if i is not None:
            xs.append(est["x"][i])
            ys.append(est["y"][i])
            cs.append(value)
    ax.plot(est_all["x"], est_all["y"], "-", color="lightgray", lw=0.8, zorder=1)
    sc = ax.scatter(xs, ys, c=cs, cmap="jet", s=14, zorder=3)
    fig.colorbar(sc, ax=ax, label=f"{metric.upper()} [{unit}]")
    mark_unmatched(ax, est_all, missing)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=8)
    style.title(ax, title)
    style.save(fig, f"{out_dir}/{metric}_error_map.png")


def main():
    out_dir, metric, title, unit = sys.argv[1:5]
    names = sys.argv[5:]
    ref = read(f"{out_dir}/{metric}_reference.csv")
    est = read(f"{out_dir}/{metric}_estimate.csv")
    est_all = read(f"{out_dir}/{metric}_estimate_all.csv")
    err = read(f"{out_dir}/{metric}_errors.csv")
    missing = unmatched(est_all, est) if metric == "ape" else []
    trajectories(out_dir, metric, title, names, ref, est_all, missing)
    error_curve(out_dir, metric, title, unit, err, [est_all["t"][k] for k in missing])
    error_map(out_dir, metric, title, unit, ref, est, err, est_all, missing)
    if missing:
        print(f"  {len(missing)} pose(s) of {names[0]} without a reference pose are drawn and marked "
              f"(not in the statistics): " + ", ".join(f"{est_all['t'][k]:g}" for k in missing))


if __name__ == "__main__":
    main()
