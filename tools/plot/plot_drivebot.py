#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Plots of `graphslam drivebot --plot`: state errors with 2-sigma bands, covariance
diagonals, chi2 and optimisation time (thread CPU time by kind of step, wall time beside it)
against time, the map with landmark covariance ellipses, and (when DIR/loop_closure.csv
exists) the map just before and just after the loop closure with the change of each
landmark's covariance determinant, and every vehicle state's variances before and after it.
Reads DIR/steps.csv, landmarks.csv, scenario.csv, summary.csv, loop_closure*.csv. A plot with
nothing to show is not drawn; the script says why.
usage: plot_drivebot.py DIR TITLE [--log-chi2]"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Ellipse  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_style as style  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def column(rows, key):
    return [float(r[key]) for r in rows]


def save(fig, out_dir, name):
    style.save(fig, os.path.join(out_dir, name))


def errors_plot(steps, out_dir, title):
    t = column(steps, "time")
    fig, axes = plt.subplots(3, 1, figsize=(8, 6.5), sharex=True)
    for ax, (key, label, scale) in zip(
        axes, [("x", "x error [m]", 1.0), ("y", "y error [m]", 1.0), ("psi", "psi error [deg]", 180 / math.pi)]
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
    axes[-1].set_xlabel("time [s]")
    style.title(axes[0], f"{title}\nvehicle state errors (final smoothed estimate)")
    save(fig, out_dir, "errors.png")


def covariance_plot(steps, out_dir, title):
    t = column(steps, "time")
    fig, axes = plt.subplots(3, 1, figsize=(8, 6.5), sharex=True)
    for ax, (key, label) in zip(
        axes, [("var_x", "var x [m²]"), ("var_y", "var y [m²]"), ("var_psi", "var psi [rad²]")]
    ):
        pairs = [(a, b) for a, b in zip(t, column(steps, key)) if not math.isnan(b)]
        ax.plot([a for a, _ in pairs], [b for _, b in pairs], color="tab:red", lw=1)
        ax.set_ylabel(label)
        ax.set_ylim(bottom=0)
    axes[-1].set_xlabel("time [s]")
    style.title(axes[0], f"{title}\nvehicle covariance diagonal (marginals of the final graph)")
    save(fig, out_dir, "covariance.png")


def step_kind(r):
    """The richest event of a step: a GPS fix, landmark observations, a compass reading, or
    none (prediction only)."""
    if r.get("gps") == "1":
        return "gps"
    if r["observations"] != "0":
        return "landmarks"
    return "compass" if r.get("compass") == "1" else "prediction"


# The coursework's kinds of step: its timing plots show one trend per kind.
KINDS = [("GPS fix", "tab:blue", "gps"), ("landmark observations", "tab:orange", "landmarks"),
         ("compass only", "tab:purple", "compass"), ("prediction only", "tab:green", "prediction")]


def chi2_plot(opt, out_dir, title, log):
    fig, ax = plt.subplots(figsize=(8, 3.8))
    chi2 = column(opt, "chi2")
    ax.plot(column(opt, "time"), chi2, "-o" if len(opt) < 50 else "-", ms=3, lw=1, color="tab:purple")
    style.chi2_axis(ax, chi2, log)
    ax.set_xlabel("time [s]")
    style.title(ax, f"{title}\nchi2 after each optimisation during the run")
    save(fig, out_dir, "chi2.png")


def timing_plot(opt, out_dir, title):
    """Thread CPU time per optimisation, one series per kind of step, and the wall time
    beside it on its own scale (pre-emption on a busy machine shows in the wall time only,
    as outliers that would flatten the CPU time on a shared axis)."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, key, what in ((axes[0], "optimization_cpu_time", "thread CPU time"),
                          (axes[1], "optimization_time", "wall time")):
        top = 0.0
        for name, color, kind in KINDS:
            rows = [r for r in opt if step_kind(r) == kind]
            if not rows:
                continue
            ms = [1e3 * v for v in column(rows, key)]
            top = max(top, max(ms))
            ax.plot(column(rows, "time"), ms, "*", ms=3, color=color, label=f"{name} ({len(rows)} steps)")
        ax.set_ylim(0, 1.05 * top if top > 0 else 1.0)
        ax.set_xlabel("time [s]")
        ax.set_ylabel(f"optimisation {what} [ms]")
        ax.legend(fontsize=7, loc="upper left")
        style.title(ax, f"{what} of each optimisation, by the step's events")
    style.suptitle(fig, title)
    style.save(fig, os.path.join(out_dir, "optimization_time.png"))


def optimisation_plots(steps, summary, out_dir, title, log_chi2):
    opt = [r for r in steps if r["optimized"] == "1"]
    if len(opt) < 2:  # one point is no series: said, not drawn
        final = (f"after its last step (chi2 {float(summary['final_chi2']):.6g}, "
                 f"{summary['final_iterations']} iterations, {1e3 * float(summary['final_time']):.1f} ms)")
        once = "" if not opt else (f" and once during the run, at step {opt[0]['step']} (chi2 "
                                   f"{float(opt[0]['chi2']):.6g}, {1e3 * float(opt[0]['optimization_cpu_time']):.2f} ms CPU)")
        why = f"the run optimised only {final}{once}"
        for name in ("chi2.png", "optimization_time.png"):
            style.not_drawn(name, why, os.path.join(out_dir, name))
        return
    chi2_plot(opt, out_dir, title, log_chi2)
    timing_plot(opt, out_dir, title)


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
    if landmarks:  # the scenario's landmarks only when the run maps them
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
        x, y, cxx, cxy, cyy = vehicle
        ax.plot([x], [y], "o", color="tab:green", ms=5, label="vehicle")
        if not math.isnan(cxx):
            ellipse(ax, x, y, cxx, cxy, cyy, scale, color="tab:green", lw=1)
            ax.plot([], [], "-", color="tab:green", label="vehicle 3σ ellipse")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")


def extent_of(steps, scenario, landmarks):
    """Size of what the run uses: its path, the waypoints and the landmarks it mapped."""
    xs = column(steps, "true_x") + column([r for r in scenario if r["kind"] == "waypoint"], "x")
    ys = column(steps, "true_y") + column([r for r in scenario if r["kind"] == "waypoint"], "y")
    xs += column(landmarks, "x")
    ys += column(landmarks, "y")
    return max(max(xs) - min(xs), max(ys) - min(ys), 1.0)


def map_plot(steps, scenario, landmarks, out_dir, title):
    fig, ax = plt.subplots(figsize=(7, 6.5))
    scale = ellipse_scale([landmarks], extent_of(steps, scenario, landmarks))
    draw_map(ax, steps, scenario, landmarks, scale)
    if landmarks:
        ax.plot([], [], "-", color="tab:red", label="landmark 3σ ellipse" + (f" ×{scale:g}" if scale != 1 else ""))
    ax.legend(fontsize=7, loc="best")
    style.title(ax, f"{title}\nmap after the run")
    save(fig, out_dir, "map.png")


def loop_closure_plot(steps, scenario, rows, out_dir, title):
    before = [r for r in rows if r["phase"] == "before"]
    after = [r for r in rows if r["phase"] == "after"]
    scale = ellipse_scale([before, after], extent_of(steps, scenario, before + after))
    fig = plt.figure(figsize=(14, 5.5))
    for k, (phase, lms) in enumerate([("just before", before), ("just after", after)]):
        ax = fig.add_subplot(1, 3, k + 1)
        r0 = lms[0]
        draw_map(ax, steps, scenario, lms, scale, upto=int(r0["step"]),
                 vehicle=tuple(float(r0[k]) for k in ("vehicle_x", "vehicle_y", "vehicle_cov_xx",
                                                        "vehicle_cov_xy", "vehicle_cov_yy")))
        style.title(ax, f"{phase} the loop closure (step {r0['step']}, t = {float(r0['time']):.1f} s); "
                        f"3σ ellipses ×{scale:g}, chi2 {float(r0['chi2']):.3g}", fontsize=8)
        if k == 0:
            ax.legend(fontsize=6, loc="center")
    ax = fig.add_subplot(1, 3, 3)
    by_id = {r["landmark"]: r for r in after}
    shared = [b for b in before if b["landmark"] in by_id]
    ids = [r["landmark"] for r in shared]
    ratios = [float(by_id[r["landmark"]]["det"]) / float(r["det"]) for r in shared]
    last_seen = {r["landmark"]: int(r["last_seen_step"]) for r in before}
    recent = max(ids, key=lambda i: last_seen[i])
    colors = ["tab:red" if i == recent else "tab:blue" for i in ids]
    ax.bar(range(len(ids)), ratios, color=colors)
    ax.set_yscale("log")
    ax.set_xticks(range(len(ids)))
    ax.set_xticklabels([f"{i}\n{last_seen[i] - 1}" for i in ids], fontsize=7)
    ax.set_xlabel("landmark id / step of its last sighting before the closure")
    ax.set_ylabel("det(P) after / det(P) before [-] (log scale)")
    style.title(ax, "change of each landmark's covariance determinant (red: the most recently seen)",
                fontsize=8)
    style.suptitle(fig, title)
    style.save(fig, os.path.join(out_dir, "loop_closure.png"), rect=(0, 0, 1, 0.95))


def loop_closure_vehicle_plot(rows, out_dir, title):
    """Every vehicle state's variances just before and just after the closure (log scale:
    they fall by orders of magnitude)."""
    fig, axes = plt.subplots(3, 1, figsize=(8, 7), sharex=True)
    phases = [("before", "tab:blue", "just before the closure"), ("after", "tab:red", "just after it")]
    for ax, (key, label) in zip(axes, [("var_x", "var x [m²]"), ("var_y", "var y [m²]"),
                                       ("var_psi", "var psi [rad²]")]):
        for phase, color, name in phases:
            part = [r for r in rows if r["phase"] == phase and float(r[key]) > 0]
            step = part[0]["step"] if part else "?"
            ax.plot(column(part, "time"), column(part, key), color=color, lw=1,
                    label=f"{name} (graph up to step {step})")
        ax.set_yscale("log")
        ax.set_ylabel(label + " (log)")
    axes[0].legend(fontsize=8, loc="upper left")
    axes[-1].set_xlabel("time of the vehicle state [s]")
    style.title(axes[0], f"{title}\nvehicle covariance diagonal of every state, before and after the loop closure")
    save(fig, out_dir, "loop_closure_vehicle.png")


def main():
    out_dir, title = sys.argv[1], sys.argv[2]
    log_chi2 = "--log-chi2" in sys.argv[3:]
    steps = read(os.path.join(out_dir, "steps.csv"))
    scenario = read(os.path.join(out_dir, "scenario.csv"))
    landmarks = read(os.path.join(out_dir, "landmarks.csv"))
    summary = {r["quantity"]: r["value"] for r in read(os.path.join(out_dir, "summary.csv"))}
    style.METADATA["graphslam-optimizer"] = summary.get("optimizer", "")
    errors_plot(steps, out_dir, title)
    covariance_plot(steps, out_dir, title)
    optimisation_plots(steps, summary, out_dir, title, log_chi2)
    map_plot(steps, scenario, landmarks, out_dir, title)
    lc = os.path.join(out_dir, "loop_closure.csv")
    if os.path.exists(lc):
        loop_closure_plot(steps, scenario, read(lc), out_dir, title)
    lcv = os.path.join(out_dir, "loop_closure_vehicle.csv")
    if os.path.exists(lcv):
        loop_closure_vehicle_plot(read(lcv), out_dir, title)


if __name__ == "__main__":
    main()
