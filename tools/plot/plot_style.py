# SPDX-License-Identifier: MIT
"""One style for graphslam's plots, shared by the scripts in this folder:
- titles name files by their base name (never an absolute path) and are wrapped to the
  width of the figure, so they are never clipped;
- axes carry units in brackets ("time [s]", "APE [m]"); an index is called what it is;
- a plot with nothing to show is not drawn: `not_drawn` says which and why on stdout;
- chi2 is drawn on a linear axis unless the caller asks for a log one.
Scripts run with matplotlib's Agg backend, imported before this module."""
import os
import textwrap

DPI = 100


def clean_title(text):
    """`text` with every absolute path replaced by its file name."""
    words = []
    for word in str(text).split(" "):
        core = word.strip("()[],;:'\"")
        if core.startswith("/") and len(core) > 1:
            word = word.replace(core, os.path.basename(core.rstrip("/")) or core)
        words.append(word)
    return " ".join(words)


def wrap(text, width_inches, fontsize=9):
    """`text` (cleaned) broken into lines that fit `width_inches` at `fontsize` points."""
    chars = max(20, int(width_inches * 72.0 / (0.55 * fontsize)))
    lines = []
    for line in clean_title(text).split("\n"):
        lines.extend(textwrap.wrap(line, chars) or [""])
    return "\n".join(lines)


def title(ax, text, fontsize=9):
    """Axes title wrapped to the axes' width."""
    fig = ax.get_figure()
    width = fig.get_figwidth() * ax.get_position().width
    ax.set_title(wrap(text, width, fontsize), fontsize=fontsize)


def suptitle(fig, text, fontsize=9):
    fig.suptitle(wrap(text, fig.get_figwidth(), fontsize), fontsize=fontsize)


def not_drawn(name, why, path=None):
    """Says that plot `name` was not drawn, and why (no empty placeholder figures); removes
    `path`, a picture of that name left by an earlier run, so none is taken for this one's.
    When the tool stages its outputs, it names a list file in GRAPHSLAM_NOT_WRITTEN_LIST:
    the picture's name goes there, and the tool removes the earlier one when it puts the
    new outputs in place."""
    if path and os.path.exists(path):
        os.remove(path)
    listing = os.environ.get("GRAPHSLAM_NOT_WRITTEN_LIST")
    if path and listing:
        with open(listing, "a") as f:
            f.write(os.path.basename(path) + "\n")
    print(f"  {name} not drawn: {why}")


# PNG text entries written into every figure (e.g. the optimizer a DriveBot run used, which
# tests/docs/check_drivebot_figures.py compares with the command documented under it).
METADATA = {}


def save(fig, path, rect=None):
    """Lays out (titles included) and writes the figure, then closes it."""
    import matplotlib.pyplot as plt

    if rect is None:
        fig.tight_layout()
    else:
        fig.tight_layout(rect=rect)
    fig.savefig(path, dpi=DPI, metadata=dict(METADATA) if path.endswith(".png") else None)
    plt.close(fig)


def chi2_axis(ax, values, log=False):
    """Linear chi2 axis from 0 (log only when asked). Values at rounding level (an exactly
    consistent graph) are drawn as what they are, zero, with a note."""
    ax.set_ylabel("chi2 [-]")
    top = max(values) if values else 0.0
    if log and top > 0:
        ax.set_yscale("log")
        ax.set_ylabel("chi2 [-] (log scale)")
        return
    if top < 1e-9:
        # chi2 is never negative: the axis starts at 0 and the note sits inside it.
        ax.set_ylim(0.0, 1.0)
        ax.text(0.02, 0.9, wrap(f"chi2 at rounding level (largest {top:.2g}): the graph is exactly consistent",
                                0.9 * ax.get_position().width * ax.figure.get_figwidth(), 8),
                transform=ax.transAxes, fontsize=8, va="top")
    else:
        ax.set_ylim(bottom=0, top=1.05 * top)
