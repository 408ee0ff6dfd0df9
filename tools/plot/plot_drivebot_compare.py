#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Several `graphslam drivebot` runs in one figure (e.g. the Q3a/Q3b variants): position
error against the truth, the marginal position variance (var x + var y) of every vehicle
state, chi2 at each optimisation and the cumulative optimisation CPU time, one colour per
run, named after its output folder. States without a covariance (not estimated) are left
out. Errors in the input are reported in one line, never as a traceback.
usage: plot_drivebot_compare.py OUT.png DIR [DIR...] [--title TEXT]"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_style as style  # noqa: E402


def read_run(folder):
    with open(os.path.join(folder, "steps.csv"), newline="") as f:
        steps = list(csv.DictReader(f))
    with open(os.path.join(folder, "graph_stats.csv"), newline="") as f:
        stats = {r["quantity"]: r["value"] for r in csv.DictReader(f)}
    return steps, stats


def draw(ax_err, ax_var, ax_chi2, ax_time, name, steps, stats, color):
    est = [r for r in steps if r["var_x"] != "nan"]
    t = [float(r["time"]) for r in est]
    err = [math.hypot(float(r["x"]) - float(r["true_x"]), float(r["y"]) - float(r["true_y"])) for r in est]
    var = [float(r["var_x"]) + float(r["var_y"]) for r in est]
    rms = math.sqrt(sum(e * e for e in err) / len(err)) if err else float("nan")
    label = f"{name}: {stats.get('observation_edges', '?')} observation edges, RMS error {rms:.3f} m"
    ax_err.plot(t, err, lw=0.8, color=color, label=label)
    ax_var.plot(t, var, lw=0.8, color=color)
    opt = [r for r in steps if r["optimized"] == "1"]
    ax_chi2.plot([float(r["time"]) for r in opt], [float(r["chi2"]) for r in opt], "-o", ms=3, color=color)
    total, cumulative = 0.0, []
    for r in opt:
        total += float(r.get("optimization_cpu_time", r["optimization_time"]))
        cumulative.append(total)
    ax_time.step([float(r["time"]) for r in opt], cumulative, where="post", color=color)


def main(argv):
    title = None
    if "--title" in argv:
        k = argv.index("--title")
        title = argv[k + 1]
        argv = argv[:k] + argv[k + 2:]
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    out, folders = argv[0], argv[1:]
    fig, axes = plt.subplots(2, 2, figsize=(13, 8), sharex=True)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    chi2 = []
    for k, folder in enumerate(folders):
        steps, stats = read_run(folder)
        chi2 += [float(r["chi2"]) for r in steps if r["optimized"] == "1"]
        draw(axes[0][0], axes[0][1], axes[1][0], axes[1][1], os.path.basename(os.path.normpath(folder)),
             steps, stats, colors[k % len(colors)])
    axes[0][0].set_ylabel("position error |estimate − truth| [m]")
    axes[0][1].set_ylabel("var x + var y [m²]")
    style.chi2_axis(axes[1][0], chi2)
    axes[1][1].set_ylabel("cumulative optimisation CPU time [s]")
    for ax in axes[1]:
        ax.set_xlabel("time [s]")
    for ax, what in zip([a for row in axes for a in row],
                        ["error of the final smoothed estimate", "marginal position variance of each state",
                         "chi2 after each optimisation", "optimisation CPU time during the run, cumulative"]):
        style.title(ax, what)
    for ax in (axes[0][0], axes[0][1], axes[1][1]):
        ax.set_ylim(bottom=0)
    fig.legend(*axes[0][0].get_legend_handles_labels(), loc="lower center", ncol=2, fontsize=8)
    style.suptitle(fig, title or "comparison of " + ", ".join(os.path.basename(os.path.normpath(f)) for f in folders))
    style.save(fig, out, rect=(0, 0.07, 1, 0.96))
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except (OSError, KeyError, ValueError, IndexError) as e:
        print(f"plot_drivebot_compare.py: {e}", file=sys.stderr)
        sys.exit(1)
