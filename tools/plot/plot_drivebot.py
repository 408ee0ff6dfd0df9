#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Plots of `graphslam drivebot --plot`: state errors with 2-sigma bands, covariance
diagonals, chi2 and optimisation time against time, the map with landmark covariance
ellipses, and (when DIR/loop_closure.csv exists) the map just before and just after the
loop closure with the change of each landmark's covariance determinant.
Reads DIR/steps.csv, landmarks.csv, scenario.csv, summary.csv, loop_closure.csv.
usage: plot_drivebot.py DIR TITLE"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Ellipse  # noqa: E402

DPI = 90


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def column(rows, key):
    return [float(r[key]) for r in rows]


def save(fig, out_dir, name):
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, name), dpi=DPI)
    plt.close(fig)


def errors_plot(steps, out_dir, title):
    t = column(steps, "time")
    fig, axes = plt.subplots(3, 1, figsize=(8, 6.5), sharex=True)
    for ax, (key, label, scale) in zip(
        axes, [("x", "x error (m)", 1.0), ("y", "y error (m)", 1.0), ("psi", "psi error (deg)", 180 / math.pi)]
    ):
        est = column(steps, key)
        true = column(steps, "true_" + key)
        err = [e - g for e, g in zip(est, true)]
        if key == "psi":
            err = [(e + math.pi) % (2 * math.pi) - math.pi for e in err]
        var = column(steps, "var_" + key)
        # Vertices without covariance (NaN: no edge, not estimated) are left out.
        keep = [k for k, v in enumerate(var) if not math.isnan(v)]
        tk = [t[k] for k in keep]
        err = [err[k] * scale for k in keep]
        sigma = [2 * math.sqrt(max(var[k], 0.0)) * scale for k in keep]
        ax.fill_between(tk, [-s for s in sigma], sigma, color="tab:blue", alpha=0.2, label="±2σ (marginal)")
        ax.plot(tk, err, color="tab:blue", lw=1, label="estimate − truth")
        ax.axhline(0, color="gray", lw=0.5)
        ax.set_ylabel(label)
    axes[0].legend(loc="upper left", fontsize=8)
    axes[-1].set_xlabel("time (s)")
    axes[0].set_title(f"{title}\nvehicle state errors (final smoothed estimate)", fontsize=9)
    save(fig, out_dir, "errors.png")


def covariance_plot(steps, out_dir, title):
    t = column(steps, "time")
    fig, axes = plt.subplots(3, 1, figsize=(8, 6.5), sharex=True)
    for ax, (key, label) in zip(
        axes, [("var_x", "var x (m²)"), ("var_y", "var y (m²)"), ("var_psi", "var psi (rad²)")]
    ):
        pairs = [(a, b) for a, b in zip(t, column(steps, key)) if not math.isnan(b)]
        ax.plot([a for a, _ in pairs], [b for _, b in pairs], color="tab:red", lw=1)
        ax.set_ylabel(label)
        ax.set_ylim(bottom=0)
    axes[-1].set_xlabel("time (s)")
    axes[0].set_title(f"{title}\nvehicle covariance diagonal (marginals of the final graph)", fontsize=9)
    save(fig, out_dir, "covariance.png")


def time_series(opt, out_dir, title, name, ylabel, subtitle, draw, note):
    """One plot of the optimised steps against time (or a note when there are none)."""
    fig, ax = plt.subplots(figsize=(8, 3.5))
    if opt:
        draw(ax)
    else:
        ax.text(0.5, 0.5, note, transform=ax.transAxes, ha="center")
    ax.set_xlabel("time (s)")
    ax.set_ylabel(ylabel)
    ax.set_title(f"{title}\n{subtitle}", fontsize=9)
    save(fig, out_dir, name)


def optimisation_plots(steps, summary, out_dir, title):
    opt = [r for r in steps if r["optimized"] == "1"]
    note = (f"optimised only after the last step: chi2 {float(summary['final_chi2']):.6g}, "
            f"{summary['final_iterations']} iterations, {1e3 * float(summary['final_time']):.1f} ms")

    def chi2_curve(ax):
        chi2 = column(opt, "chi2")
        ax.plot(column(opt, "time"), chi2, "-o" if len(opt) < 50 else "-", ms=3, lw=1, color="tab:purple")
        # Log scale when chi2 spans decades; values at rounding level (an exactly
        # consistent graph before the first absolute measurement) stay off the scale.
        significant = [c for c in chi2 if c > 1e-9 * max(chi2)] if max(chi2) > 0 else []
        if significant and max(significant) / min(significant) > 100:
            ax.set_yscale("log")
            ax.set_ylim(bottom=min(significant) / 2)

    def time_points(ax):
        ax.plot(column(opt, "time"), [1e3 * v for v in column(opt, "optimization_time")], "*", ms=3,
                color="tab:green")
        ax.set_ylim(bottom=0)

    time_series(opt, out_dir, title, "chi2.png", "chi2 after optimisation",
                "chi2 at each optimisation during the run", chi2_curve, note)
    time_series(opt, out_dir, title, "optimization_time.png", "optimisation time (ms)",
                "wall time of each optimisation during the run", time_points, note)


def ellipse(ax, x, y, cxx, cxy, cyy, scale, **kw):
    """3-sigma ellipse of a 2x2 covariance, semi-axes multiplied by `scale`."""
    tr, det = cxx + cyy, cxx * cyy - cxy * cxy
    disc = math.sqrt(max(tr * tr / 4 - det, 0.0))
    l1, l2 = tr / 2 + disc, max(tr / 2 - disc, 0.0)
    angle = math.degrees(math.atan2(l1 - cxx, cxy)) if abs(cxy) > 1e-300 else (0.0 if cxx >= cyy else 90.0)
    ax.add_patch(Ellipse((x, y), 2 * 3 * math.sqrt(l1) * scale, 2 * 3 * math.sqrt(l2) * scale, angle=angle,
                         fill=False, **kw))


def ellipse_scale(landmark_sets, extent):
    """Magnification that makes the median 3-sigma semi-axis about 1.5 % of the map."""
    axes = []
    for rows in landmark_sets:
        for r in rows:
            tr = float(r["cov_xx"]) + float(r["cov_yy"])
            if tr > 0:
                axes.append(3 * math.sqrt(tr / 2))
    if not axes:
        return 1.0
    axes.sort()
    median = axes[len(axes) // 2]
    target = 0.015 * extent
    if median >= target:
        return 1.0
    return float(f"{target / median:.0e}") if target / median >= 10 else round(target / median)


def draw_map(ax, steps, scenario, landmarks, scale, upto=None, vehicle=None):
    # Vertices without covariance (no edge, not estimated) keep their predictions: left out.
    rows = [r for r in steps if upto is not None or r["var_x"] != "nan"]
    rows = rows if upto is None else [r for r in rows if int(r["step"]) <= upto]
    ax.plot(column(rows, "true_x"), column(rows, "true_y"), "-", color="gray", lw=1, label="true path")
    key = "x" if upto is None else "online_x"
    ax.plot(column(rows, key), column(rows, key.replace("x", "y")), "-", color="tab:blue", lw=0.8,
            label="estimated path" if upto is None else "online estimate")
    lm = [r for r in scenario if r["kind"] == "landmark"]
    ax.plot(column(lm, "x"), column(lm, "y"), "k+", ms=8, label="true landmarks")
    wp = [r for r in scenario if r["kind"] == "waypoint"]
    ax.plot(column(wp, "x"), column(wp, "y"), "s", mfc="none", color="tab:orange", ms=6, label="waypoints")
    for r in landmarks:
        x, y = float(r["x"]), float(r["y"])
        ax.plot([x], [y], ".", color="tab:red", ms=4)
        ellipse(ax, x, y, float(r["cov_xx"]), float(r["cov_xy"]), float(r["cov_yy"]), scale, color="tab:red",
                lw=1)
        ax.annotate(r["landmark"], (x, y), textcoords="offset points", xytext=(4, 4), fontsize=7)
    if vehicle is not None:
        ax.plot([vehicle[0]], [vehicle[1]], "o", color="tab:green", ms=5, label="vehicle")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def extent_of(scenario):
    xs = column(scenario, "x")
    ys = column(scenario, "y")
    return max(max(xs) - min(xs), max(ys) - min(ys), 1.0)


def map_plot(steps, scenario, landmarks, out_dir, title):
    fig, ax = plt.subplots(figsize=(7, 6.5))
    scale = ellipse_scale([landmarks], extent_of(scenario))
    draw_map(ax, steps, scenario, landmarks, scale)
    if landmarks:
        ax.plot([], [], "-", color="tab:red", label="landmark 3σ ellipse" + (f" ×{scale:g}" if scale != 1 else ""))
    ax.legend(fontsize=7, loc="best")
    ax.set_title(f"{title}\nmap after the run", fontsize=9)
    save(fig, out_dir, "map.png")


def loop_closure_plot(steps, scenario, rows, out_dir, title):
    before = [r for r in rows if r["phase"] == "before"]
    after = [r for r in rows if r["phase"] == "after"]
    scale = ellipse_scale([before, after], extent_of(scenario))
    fig = plt.figure(figsize=(13, 5))
    for k, (phase, lms) in enumerate([("just before", before), ("just after", after)]):
        ax = fig.add_subplot(1, 3, k + 1)
        r0 = lms[0]
        draw_map(ax, steps, scenario, lms, scale, upto=int(r0["step"]),
                 vehicle=(float(r0["vehicle_x"]), float(r0["vehicle_y"])))
        ax.set_title(f"{phase} the loop closure (step {r0['step']}, t = {float(r0['time']):.1f} s)\n"
                     f"3σ ellipses ×{scale:g}, chi2 {float(r0['chi2']):.3g}", fontsize=8)
        if k == 0:
            ax.legend(fontsize=6, loc="center")
    ax = fig.add_subplot(1, 3, 3)
    by_id = {r["landmark"]: r for r in after}
    ids = [r["landmark"] for r in before if r["landmark"] in by_id]
    ratios = [float(by_id[i]["det"]) / float(r["det"]) for i, r in zip(ids, [b for b in before if b["landmark"] in by_id])]
    last_seen = {r["landmark"]: int(r["last_seen_step"]) for r in before}
    recent = max(ids, key=lambda i: last_seen[i])
    colors = ["tab:red" if i == recent else "tab:blue" for i in ids]
    ax.bar(range(len(ids)), ratios, color=colors)
    ax.set_yscale("log")
    ax.set_xticks(range(len(ids)))
    ax.set_xticklabels([f"{i}\n(seen {last_seen[i] - 1})" for i in ids], fontsize=7)
    ax.set_xlabel("landmark (step of its last sighting before the closure)")
    ax.set_ylabel("det(P) after / det(P) before")
    ax.set_title("change of each landmark's covariance determinant\n(red: the most recently seen)", fontsize=8)
    fig.suptitle(title, fontsize=9)
    save(fig, out_dir, "loop_closure.png")


def main():
    out_dir, title = sys.argv[1], sys.argv[2]
    steps = read(os.path.join(out_dir, "steps.csv"))
    scenario = read(os.path.join(out_dir, "scenario.csv"))
    landmarks = read(os.path.join(out_dir, "landmarks.csv"))
    errors_plot(steps, out_dir, title)
    covariance_plot(steps, out_dir, title)
    summary = {r["quantity"]: r["value"] for r in read(os.path.join(out_dir, "summary.csv"))}
    optimisation_plots(steps, summary, out_dir, title)
    map_plot(steps, scenario, landmarks, out_dir, title)
    lc = os.path.join(out_dir, "loop_closure.csv")
    if os.path.exists(lc):
        loop_closure_plot(steps, scenario, read(lc), out_dir, title)


if __name__ == "__main__":
    main()
