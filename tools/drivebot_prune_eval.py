#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Evaluates the DriveBot pruning rules on the coursework's q3_a setting (laser range 30 m,
optimise every 500 steps) over several seeds, against the unpruned graph of the same seed:
observation edges kept, mean marginal vehicle variance (var x + var y) and landmark variance
relative to the unpruned graph, RMS distance of the estimate from the unpruned estimate and
from the truth, and total optimisation time (thread CPU time, wall time beside it; the minimum over
--repeats runs, as a busy machine only ever adds time). Pruned and unpruned runs use the same
per-step optimizer (--optimizer: batch, incremental or both, one table each); a rule that removes
edges from the graph (the coursework's) runs on the batch optimizer only, and its row in the
incremental table says so instead of comparing it with the other optimizer. Writes Markdown tables
on stdout and, with --plot FILE, variance against edges kept.
usage: drivebot_prune_eval.py GRAPHSLAM WORKDIR [--seeds N] [--repeats N] [--optimizer WHICH]
                              [--plot FILE.png]"""
import argparse
import csv
import math
import os
import re
import statistics
import subprocess
import sys

RULES = [("none", []), ("coursework n=2", ["--prune", "coursework"])]
for n in (2, 3, 4):
    RULES.append((f"every-nth n={n}", ["--prune", "every-second", "--prune-every", str(n)]))
    RULES.append((f"staggered n={n}", ["--prune", "staggered", "--prune-every", str(n)]))
for d in ("0.3", "0.5", "1", "2"):
    RULES.append((f"keyframe {d} m", ["--prune", "keyframe", "--keyframe-distance", d]))


def run(tool, work, name, args, seed, optimizer, repeats=1):
    out = os.path.join(work, f"{optimizer}_{name.replace(' ', '_').replace('=', '')}_{seed}")
    cpu, wall = [], []
    for _ in range(repeats):
        p = subprocess.run([tool, "drivebot", "--experiment", "q3_a", "--seed", str(seed), "--out", out, "-q",
                            "--optimizer", optimizer] + args, capture_output=True, text=True, check=True)
        m = re.search(r"optimisation: +\d+ runs, ([0-9.]+) s CPU \(([0-9.]+) s wall\)", p.stdout)
        cpu.append(float(m.group(1)))
        wall.append(float(m.group(2)))
    steps = list(csv.DictReader(open(os.path.join(out, "steps.csv"))))
    landmarks = {r["landmark"]: r for r in csv.DictReader(open(os.path.join(out, "landmarks.csv")))}
    stats = {r["quantity"]: r["value"] for r in csv.DictReader(open(os.path.join(out, "graph_stats.csv")))}
    summary = {r["quantity"]: r["value"] for r in csv.DictReader(open(os.path.join(out, "summary.csv")))}
    stats["optimizer"] = summary["optimizer"]
    return steps, landmarks, stats, (min(cpu), min(wall))


def rms(values):
    return math.sqrt(statistics.mean(values))


HEADER = ("| rule | observation edges | share | vehicle var / unpruned | landmark var / unpruned "
          "| RMS from unpruned estimate (m) | RMS error (m) | optimisation CPU time (s) | CPU time / unpruned "
          "| wall time (s) |\n|---|---|---|---|---|---|---|---|---|---|")


def compare(run_pruned, unpruned, seeds):
    """Mean over the seeds of each measure of one rule's runs against the unpruned runs."""
    cols = {k: [] for k in ("edges", "share", "var", "lvar", "dev", "err", "time", "tratio", "wall")}
    for s in seeds:
        st, lm, gs, t = run_pruned(s)
        st0, lm0, gs0, t0 = unpruned[s]
        idx = [k for k, r in enumerate(st) if r["var_x"] != "nan"]
        cols["edges"].append(int(gs["observation_edges"]))
        cols["share"].append(int(gs["observation_edges"]) / int(gs0["observation_edges"]))
        cols["var"].append(statistics.mean(float(st[k]["var_x"]) + float(st[k]["var_y"]) for k in idx) /
                           statistics.mean(float(st0[k]["var_x"]) + float(st0[k]["var_y"]) for k in idx))
        cols["lvar"].append(statistics.mean(float(r["cov_xx"]) + float(r["cov_yy"]) for r in lm.values()) /
                            statistics.mean(float(r["cov_xx"]) + float(r["cov_yy"]) for r in lm0.values()))
        cols["dev"].append(rms([(float(st[k]["x"]) - float(st0[k]["x"])) ** 2 +
                                (float(st[k]["y"]) - float(st0[k]["y"])) ** 2 for k in idx]))
        cols["err"].append(rms([(float(st[k]["x"]) - float(st[k]["true_x"])) ** 2 +
                                (float(st[k]["y"]) - float(st[k]["true_y"])) ** 2 for k in idx]))
        cols["time"].append(t[0])
        cols["tratio"].append(t[0] / t0[0])
        cols["wall"].append(t[1])
    return {k: statistics.mean(v) for k, v in cols.items()}


def table(a, optimizer, seeds, curves):
    """One Markdown table: every rule against the unpruned graph, all on `optimizer`; the
    rules' (share, variance) points go into `curves` unless it is None."""
    full = {s: run(a.tool, a.work, "none", [], s, optimizer, a.repeats) for s in seeds}
    print(f"\nPer-step optimizer: {optimizer} (pruned and unpruned alike)\n\n{HEADER}")
    for name, args in RULES:
        probe = full[seeds[0]] if name == "none" else run(a.tool, a.work, name, args, seeds[0], optimizer, a.repeats)
        if probe[2]["optimizer"] != optimizer:
            print(f"| {name} | runs on the {probe[2]['optimizer']} optimizer only (it removes edges from the "
                  f"graph): see that table |" + " |" * 8, flush=True)
            continue
        runs = {seeds[0]: probe}  # the probe is the first seed's run: not run again
        m = compare(lambda s: full[s] if name == "none" else
                    runs.get(s) or run(a.tool, a.work, name, args, s, optimizer, a.repeats), full, seeds)
        print(f"| {name} | {m['edges']:.0f} | {m['share']:.3f} | {m['var']:.3f} | {m['lvar']:.3f} | "
              f"{m['dev']:.3f} | {m['err']:.3f} | {m['time']:.3f} | {m['tratio']:.2f} | {m['wall']:.3f} |", flush=True)
        if curves is not None:
            curves.setdefault(name.split(" ")[0], []).append((m["share"], m["var"]))


def plot(curves, path, seeds, optimizer):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for family, pts in curves.items():
        if family == "none":
            continue
        pts.sort()
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "-o" if len(pts) > 1 else "D", ms=4 if len(pts) > 1 else 7,
                label=family + (" (halved at every optimisation)" if family == "coursework" else ""))
    ax.set_xlabel("share of landmark observations kept as edges [-]")
    ax.set_ylabel("mean vehicle variance / unpruned [-]")
    ax.set_title(f"q3_a pruning rules, mean over {seeds} seeds ({optimizer} optimizer)", fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=100)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("tool")
    ap.add_argument("work")
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--optimizer", choices=("batch", "incremental", "both"), default="both")
    ap.add_argument("--plot")
    a = ap.parse_args()
    seeds = list(range(1, a.seeds + 1))
    curves = {}
    optimizers = ("batch", "incremental") if a.optimizer == "both" else (a.optimizer,)
    for optimizer in optimizers:  # the plot shows the first optimizer's table
        table(a, optimizer, seeds, curves if optimizer == optimizers[0] else None)
    if a.plot:
        plot(curves, a.plot, a.seeds, optimizers[0])


if __name__ == "__main__":
    try:
        main()
    except (OSError, subprocess.CalledProcessError, AttributeError, KeyError, ValueError) as e:
        detail = getattr(e, "stderr", "") or ""
        print(f"drivebot_prune_eval.py: {e}{': ' + detail.strip() if detail else ''}", file=sys.stderr)
        sys.exit(1)
