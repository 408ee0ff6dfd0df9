#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Sparsity pictures of matrices written by `graphslam solvers --plot DIR`.
Each input file: a header `rows,cols,nnz,grid_rows,grid_cols,title`, then `r,c,count` per
occupied cell of a grid (cells are single entries when the matrix is at most 1000 wide).
usage: plot_spy.py OUTDIR FILE.csv...   (writes OUTDIR/<file stem>.png)"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_style as style  # noqa: E402


def plot(path, outdir):
    with open(path) as f:
        head = f.readline().rstrip("\n").split(",", 5)
        rows, cols, nnz, grows, gcols = (int(v) for v in head[:5])
        title = head[5]
        data = np.loadtxt(f, delimiter=",", ndmin=2)
    image = np.zeros((grows, gcols))
    if data.size:
        image[data[:, 0].astype(int), data[:, 1].astype(int)] = 1.0
    aspect = rows / cols
    fig, ax = plt.subplots(figsize=(6.5, max(2.5, min(9.0, 6.5 * aspect))))
    ax.imshow(image, cmap="Greys", interpolation="nearest", extent=(0, cols, rows, 0),
              vmin=0, vmax=1, aspect="auto" if aspect > 3 or aspect < 1 / 3 else "equal")
    density = 100.0 * nnz / (rows * cols)
    binned = "" if grows == rows and gcols == cols else f"; {grows}x{gcols} cells, dark = any"
    style.title(ax, f"{title}\n{rows} x {cols}, nnz {nnz} ({density:.3g} %){binned}")
    ax.set_xlabel("column index")
    ax.set_ylabel("row index")
    ax.tick_params(labelsize=7)
    fig.tight_layout()
    out = os.path.join(outdir, os.path.splitext(os.path.basename(path))[0] + ".png")
    fig.savefig(out, dpi=110)
    plt.close(fig)


def main():
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    for path in sys.argv[2:]:
        plot(path, sys.argv[1])
    return 0


if __name__ == "__main__":
    sys.exit(main())
