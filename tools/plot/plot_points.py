#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Plot of `graphslam optimize --plot FILE.png`: the trajectory and landmarks before and
after optimisation, side by side, each over the ground truth when there is one.
Reads a CSV with columns set (initial|final|truth), role (pose|landmark), id, x, y.
usage: plot_points.py DATA.csv OUT.png TITLE [LEFT|RIGHT]  (the panels' titles; default
"initial guess|optimised")"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_style as style  # noqa: E402


def main():
    data, out, title = sys.argv[1], sys.argv[2], sys.argv[3]
    sets = {}
    with open(data, newline="") as f:
        for r in csv.DictReader(f):
            sets.setdefault((r["set"], r["role"]), []).append((int(r["id"]), float(r["x"]), float(r["y"])))
    for points in sets.values():
        points.sort()

    def xy(set_name, role):
        points = sets.get((set_name, role), [])
        return [p[1] for p in points], [p[2] for p in points]

    # Same limits in both panels, so before and after compare directly.
    xs = [p[1] for points in sets.values() for p in points]
    ys = [p[2] for points in sets.values() for p in points]
    pad = 0.05 * max(max(xs) - min(xs), max(ys) - min(ys), 1e-9) if xs else 1.0
    aspect = (max(ys) - min(ys) + 2 * pad) / (max(xs) - min(xs) + 2 * pad) if xs else 1.0
    fig, axes = plt.subplots(1, 2, figsize=(13, min(9.0, max(3.5, 6.2 * aspect + 1.6))))
    labels = sys.argv[4].split("|") if len(sys.argv) > 4 else ["initial guess", "optimised"]
    for ax, name, label in ((axes[0], "initial", labels[0]), (axes[1], "final", labels[1])):
        tx, ty = xy("truth", "pose")
        if tx:
            ax.plot(tx, ty, "-", color="tab:blue", linewidth=1, label="ground-truth trajectory")
        lx, ly = xy("truth", "landmark")
        if lx:
            ax.scatter(lx, ly, marker="+", s=60, color="tab:blue", label="ground-truth landmarks")
        px, py = xy(name, "pose")
        if px:
            ax.plot(px, py, "-", color="tab:red", linewidth=1, label="estimated trajectory")
        qx, qy = xy(name, "landmark")
        if qx:
            ax.scatter(qx, qy, marker="x", s=25, color="tab:red", label="estimated landmarks")
        points = list(zip(px + qx, py + qy))
        if len(points) > 1 and len(set(points)) == 1:
            # One point for all (the linear homework starts from zeros): say so, visibly.
            ax.plot([points[0][0]], [points[0][1]], "o", ms=10, mfc="none", color="tab:red")
            # The note sits in the axes' top-left corner, wrapped to their width: never outside.
            ax.text(0.02, 0.98, style.wrap(f"all {len(px)} poses and {len(qx)} landmarks at "
                                           f"({points[0][0]:g}, {points[0][1]:g}) (circled)", 2.5, 9),
                    transform=ax.transAxes, va="top", ha="left", fontsize=9, color="tab:red",
                    bbox=dict(facecolor="white", edgecolor="none", alpha=0.8))
        ax.set_title(label)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        if xs:
            ax.set_xlim(min(xs) - pad, max(xs) + pad)
            ax.set_ylim(min(ys) - pad, max(ys) + pad)
        ax.set_aspect("equal", adjustable="box")
        ax.grid(True, linewidth=0.3)
    handles, labels = axes[1].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=8)
    style.suptitle(fig, title)
    fig.tight_layout(rect=(0, 0.06, 1, 0.97))
    fig.savefig(out, dpi=120)


if __name__ == "__main__":
    main()
