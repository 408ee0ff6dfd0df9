#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Plots of `graphslam eval --plot DIR`: trajectories overlaid, error over time, and the
error colour-mapped on the estimated trajectory. Reads DIR/<metric>_{reference,estimate,errors}.csv.
usage: plot_eval.py DIR METRIC TITLE"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]} if rows else {}


def main():
    out_dir, metric, title = sys.argv[1], sys.argv[2], sys.argv[3]
    ref = read(f"{out_dir}/{metric}_reference.csv")
    est = read(f"{out_dir}/{metric}_estimate.csv")
    err = read(f"{out_dir}/{metric}_errors.csv")

    fig, ax = plt.subplots(figsize=(7, 6))
    ax.plot(ref["x"], ref["y"], "--", color="gray", label="reference")
    ax.plot(est["x"], est["y"], "-", color="tab:blue", label="estimate")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend()
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(f"{out_dir}/{metric}_trajectories.png", dpi=120)

    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(err["t"], err["error"], "-", color="tab:blue")
    e = sorted(err["error"])
    n = len(e)
    mean = sum(e) / n
    rmse = (sum(x * x for x in e) / n) ** 0.5
    median = e[n // 2] if n % 2 else 0.5 * (e[n // 2 - 1] + e[n // 2])
    for value, name, style in ((rmse, "rmse", "-"), (mean, "mean", "--"), (median, "median", ":")):
        ax.axhline(value, linestyle=style, color="tab:red", linewidth=1, label=f"{name} {value:.6g}")
    ax.set_xlabel("timestamp")
    ax.set_ylabel(metric.upper())
    ax.legend()
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(f"{out_dir}/{metric}_error.png", dpi=120)

    fig, ax = plt.subplots(figsize=(7, 6))
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
    sc = ax.scatter(xs, ys, c=cs, cmap="jet", s=12, zorder=3)
    fig.colorbar(sc, ax=ax, label=metric.upper())
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend()
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(f"{out_dir}/{metric}_error_map.png", dpi=120)


if __name__ == "__main__":
    main()
