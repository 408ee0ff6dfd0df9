#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Several PNGs (e.g. the sparsity pictures of `graphslam solvers --plot DIR`) side by side
in one figure, COLS per row, in the order given. Errors are reported in one line, never as
a traceback.
usage: plot_montage.py OUT.png COLS IMAGE.png..."""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_style as style  # noqa: E402


def main(argv):
    if len(argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    out, cols, images = argv[0], int(argv[1]), argv[2:]
    if cols < 1:
        raise ValueError("COLS must be at least 1")
    rows = math.ceil(len(images) / cols)
    pictures = [mpimg.imread(path) for path in images]
    height = max(p.shape[0] / p.shape[1] for p in pictures)
    fig, axes = plt.subplots(rows, cols, figsize=(5 * cols, 5 * height * rows), squeeze=False)
    for ax in axes.flat:
        ax.axis("off")
    for ax, picture in zip(axes.flat, pictures):
        ax.imshow(picture)
    style.save(fig, out)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except (OSError, ValueError, SyntaxError) as e:
        print(f"plot_montage.py: {e}", file=sys.stderr)
        sys.exit(1)
