#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Sparsity picture of a block matrix written by graphslam (`info --plot-hessian`).
Input CSV: a line `n,<size>`, a header `row,col,rows,cols`, then one dense block per line.
usage: plot_sparsity.py BLOCKS.csv OUT.png TITLE"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PatchCollection  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_style as style  # noqa: E402


def main():
    path, out, title = sys.argv[1], sys.argv[2], sys.argv[3]
    with open(path) as f:
        n = int(f.readline().split(",")[1])
        f.readline()
        blocks = {tuple(int(v) for v in line.split(",")) for line in f if line.strip()}
    fig, ax = plt.subplots(figsize=(6.5, 6.5))
    if n <= 600:
        patches = [Rectangle((c, r), w, h) for r, c, h, w in blocks]
        ax.add_collection(PatchCollection(patches, facecolor="tab:blue", edgecolor="none"))
    else:
        # Blocks are far below a pixel: draw each as a marker of at least one pixel.
        xs = [c + 0.5 * w for r, c, h, w in blocks]
        ys = [r + 0.5 * h for r, c, h, w in blocks]
        ax.plot(xs, ys, ",", color="tab:blue", rasterized=True)
    ax.set_xlim(0, n)
    ax.set_ylim(n, 0)
    ax.set_aspect("equal")
    nnz = sum(h * w for _, _, h, w in blocks)
    style.title(ax, f"{title}\n{n} x {n}, {nnz} non-zeros ({100.0 * nnz / max(n * n, 1):.3g} %)")
    ax.set_xlabel("column index")
    ax.set_ylabel("row index")
    if n <= 60:
        ax.set_xticks(range(0, n + 1, 3))
        ax.set_yticks(range(0, n + 1, 3))
        ax.grid(True, linewidth=0.3)
        ax.tick_params(labelsize=6)
    fig.tight_layout()
    fig.savefig(out, dpi=130)


if __name__ == "__main__":
    main()
