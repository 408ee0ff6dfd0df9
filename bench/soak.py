#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Soak benchmark (issue 56): a long seeded DriveBot drive replayed through the incremental
optimizer with the full history and with a fixed-lag window, side by side.

usage: bench/soak.py GRAPHSLAM [--laps N] [--window N] [--slack B] [--seed S] [--work DIR]
                     [--outage-every S --outage-seconds S] [--plots DIR] [--max-seconds S]
                     [--modes full,window,window-keep]
       bench/soak.py GRAPHSLAM --pose-stream N [--window N] [--slack B] [--gtsam-fls PATH]

The drive: `graphslam drivebot` on a generated scenario (a 100 m x 60 m rectangle driven
--laps times, 28 landmarks beside the road; GPS every second, compass, laser), without
optimising (--optimize-every 0 --final-iterations 0): its final.g2o is the measurement
stream and steps.csv the ground truth. GPS outages: the GPS edges of every --outage-seconds
long interval starting each --outage-every seconds are dropped from the stream. Then
`graphslam incremental` replays the stream once per mode (--modes: `full`, the full
history; `window`, --window N poses with --marginalised-out and --reinitialise-landmarks,
landmarks leaving with their last observer; `window-keep`, the same with --keep-landmarks),
with --stats. Recorded per mode: the per-step update time (p50, p99,
max) of each tenth of the run, the resident set size of the process
after every step (the rss_kb column of --stats) against the step, and the APE of
the vehicle positions against the ground truth (RMS of the position error, no alignment:
GPS fixes the frame), over the drive and over its second half (once the map has been
driven past several times). Window mode's trajectory is the vertices as they left the window
(frozen then) and the window's at the end. Prints a markdown table and, with --plots,
writes soak_latency.png and soak_memory.png there (docs/img/soak/soak_10laps_*.png are
those of --laps 10) (matplotlib).

--pose-stream N instead replays a synthetic pose graph of N poses (`graphslam simulate
--poses N`, Manhattan world, no landmarks) through the window only (its loop closures reach
behind the window and are refused) and prints the same latency and memory figures.

--gtsam-fls PATH (with --pose-stream) also runs an external program on the same stream file,
as `PATH --lag W FILE.g2o` with W the --window (for example a replay written against a GTSAM
build with its IncrementalFixedLagSmoother; nothing here builds or ships one), after
graphslam's run, and prints both side by side: per-step update time p50 and p99 of the first
and last tenth of the steps, p99 and maximum of all, the total update time, the run's wall
time, the resident memory at the end and the edges skipped because they reach behind the
window, then the ratios graphslam / the program of p99 and of the total. For an equal window
use --slack 0 (the default): graphslam then keeps exactly W poses after every update. The
program must replay FILE pose by pose (pose k, the k-th vertex by id, with time stamp k,
initialised by composing the current estimate of pose k-1 with the odometry edge k-1 -> k;
every edge whose larger endpoint is k added at step k, one timed update per step; an edge
whose other endpoint has left the window skipped and counted), keep the newest W poses after
every update, and print, each on a line of its own (other lines are ignored; a missing key
is shown as "-"):

    steps: N                  number of steps (poses)
    total_s: SECONDS          sum of the update times
    p50_ms: MS                per-step update time percentiles (nearest rank) and maximum
    p99_ms: MS
    max_ms: MS
    p50_first_ms: MS          p50 and p99 of the first 10 % of the steps (optional: p50)
    p99_first_ms: MS
    p50_last_ms: MS           and of the last 10 %
    p99_last_ms: MS
    p99_tenths_ms: MS x 10    optional: p99 of each tenth of the steps, on one line
    skipped_edges: N          edges skipped because an endpoint had left the window
    rss_end_kb: KB            VmRSS of the process at the end
    final_chi2: VALUE         optional; not compared (both windows hold a marginalisation prior)

Every program runs with OPENBLAS_NUM_THREADS=1 and OMP_NUM_THREADS=1, one at a time.
"""
import argparse
import csv
import math
import os
import re
import subprocess
import sys
import time


def scenario(folder, laps):
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "x0.txt"), "w") as f:
        f.write("0 0 0\n")
    with open(os.path.join(folder, "wp.txt"), "w") as f:
        f.write("100 0\n100 60\n0 60\n0 0\n" * laps)
    with open(os.path.join(folder, "lm.txt"), "w") as f:
        for i in range(0, 100, 12):
            f.write(f"{i} -6\n{i + 6} 66\n")
        for j in range(0, 60, 12):
            f.write(f"-6 {j}\n106 {j + 6}\n")


def drop_gps(g2o, out, every, seconds):
    """Copies the stream without the GPS edges of vertices whose time is in an outage."""
    times, dropped = {}, 0
    with open(g2o) as f, open(out, "w") as o:
        for line in f:
            t = line.split()
            if t and t[0] == "VERTEX_VEHICLE":
                times[t[1]] = float(t[5])
            if t and t[0] == "EDGE_GPS" and every > 0:
                if times.get(t[1], 0.0) % every < seconds:
                    dropped += 1
                    continue
            o.write(line)
    return dropped


def run_sampled(cmd, max_seconds):
    """Runs cmd, sampling VmRSS (kB) every 20 ms; returns (samples [(t, kB)], seconds)."""
    start = time.monotonic()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    samples = []
    while p.poll() is None:
        try:
            with open(f"/proc/{p.pid}/status") as f:
                for line in f:
                    if line.startswith("VmRSS:"):
                        samples.append((time.monotonic() - start, int(line.split()[1])))
        except OSError:
            pass
        if time.monotonic() - start > max_seconds:
            p.kill()
            sys.exit(f"soak: {' '.join(cmd)} exceeded {max_seconds} s")
        time.sleep(0.02)
    out = p.stdout.read()
    if p.returncode != 0:
        sys.exit(f"soak: {' '.join(cmd)} failed:\n{out}")
    return samples, time.monotonic() - start, out


def pct(values, p):
    s = sorted(values)
    if not s:
        return float("nan")
    return s[min(len(s) - 1, max(0, math.ceil(p / 100 * len(s)) - 1))]


def deciles(stats_csv):
    with open(stats_csv) as f:
        rows = list(csv.DictReader(f))
    secs = [float(r["seconds"]) for r in rows]
    rss = [int(r["rss_kb"]) for r in rows]
    n = len(secs)
    out = []
    for d in range(10):
        part = [1e3 * s for s in secs[d * n // 10:(d + 1) * n // 10]]
        out.append((pct(part, 50), pct(part, 99), max(part) if part else float("nan")))
    return out, n, rss, secs


def trajectory(*files):
    est = {}
    for path in files:
        with open(path) as f:
            for line in f:
                t = line.split()
                if t and t[0] == "VERTEX_VEHICLE":
                    est[round(float(t[5]), 6)] = (float(t[2]), float(t[3]))
    return est


def ape(est, truth_csv):
    """RMS position error over the drive and over its second half, and the states matched."""
    err = []
    with open(truth_csv) as f:
        for r in csv.DictReader(f):
            key = round(float(r["time"]), 6)
            if key in est:
                x, y = est[key]
                err.append((x - float(r["true_x"])) ** 2 + (y - float(r["true_y"])) ** 2)
    half = err[len(err) // 2:]
    return math.sqrt(sum(err) / len(err)), math.sqrt(sum(half) / len(half)), len(err)


def rss_growth(rss):
    """Growth of the RSS over the last half of the steps, relative."""
    half = rss[len(rss) // 2:]
    return (half[-1] - half[0]) / half[0]


def plot(results, folder):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4))
    for name, r in results.items():
        xs = [10 * d + 5 for d in range(10)]
        ax.plot(xs, [d[1] for d in r["deciles"]], "o-", label=f"{name}: p99")
        ax.plot(xs, [d[0] for d in r["deciles"]], "s--", label=f"{name}: p50")
    ax.set_yscale("log")
    ax.set_xlabel("tenth of the run (%)")
    ax.set_ylabel("update time per step (ms)")
    ax.set_title("Soak: per-step latency, DriveBot drive")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "soak_latency.png"), dpi=110)
    fig, ax = plt.subplots(figsize=(7, 4))
    for name, r in results.items():
        n = len(r["rss"])
        stride = max(1, n // 2000)
        ax.plot([100 * k / n for k in range(0, n, stride)], [r["rss"][k] / 1024 for k in range(0, n, stride)],
                label=name)
    ax.set_xlabel("step (% of the run)")
    ax.set_ylabel("resident memory (MB)")
    ax.set_title("Soak: resident memory, DriveBot drive")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "soak_memory.png"), dpi=110)


FLS_KEYS = ["steps", "total_s", "p50_ms", "p99_ms", "max_ms", "p50_first_ms", "p99_first_ms", "p50_last_ms",
            "p99_last_ms", "skipped_edges", "rss_end_kb", "final_chi2"]


def parse_keys(out):
    """The `key: value` lines of an external program's output (FLS_KEYS only)."""
    found = {}
    for line in out.splitlines():
        m = re.match(r"^(\w+): ([-+0-9.eEnaif]+)\s*$", line)
        if m and m.group(1) in FLS_KEYS:
            found[m.group(1)] = float(m.group(2))
        m = re.match(r"^p99_tenths_ms:((?:\s+[-+0-9.eEnaif]+){10})\s*$", line)
        if m:
            found["p99_tenths"] = [float(x) for x in m.group(1).split()]
    return found


def fmt(row, key, digits):
    return f"{row[key]:.{digits}f}" if key in row else "-"


def side_by_side(a, stream, gs):
    """Runs the --gtsam-fls program on the stream and prints its row beside graphslam's."""
    cmd = [a.gtsam_fls, "--lag", str(a.window), stream]
    _, seconds, out = run_sampled(cmd, a.max_seconds)
    other = parse_keys(out)
    other["run_s"] = seconds
    if "rss_end_kb" in other:
        other["rss_end_mb"] = other["rss_end_kb"] / 1024
    print(f"\nside by side, window {a.window} poses (graphslam slack {a.slack}), the same stream:\n")
    print("| program | steps | update total (s) | run (s) | p50 first / last 10 % (ms) | "
          "p99 first / last 10 % (ms) | p99 (ms) | max (ms) | RSS end (MB) | skipped edges |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    label = f"GTSAM IFLS ({os.path.basename(a.gtsam_fls)})"
    for name, r in ((f"graphslam (slack {a.slack})", gs), (label, other)):
        print(f"| {name} | {fmt(r, 'steps', 0)} | {fmt(r, 'total_s', 2)} | {fmt(r, 'run_s', 1)} "
              f"| {fmt(r, 'p50_first_ms', 3)} / {fmt(r, 'p50_last_ms', 3)} "
              f"| {fmt(r, 'p99_first_ms', 3)} / {fmt(r, 'p99_last_ms', 3)} | {fmt(r, 'p99_ms', 3)} "
              f"| {fmt(r, 'max_ms', 1)} | {fmt(r, 'rss_end_mb', 1)} | {fmt(r, 'skipped_edges', 0)} |")

    def ratio(key):
        ok = other.get(key, 0) > 0 and key in gs
        return f"{gs[key] / other[key]:.2f}" if ok else "-"

    print("\nper tenth of the run, p99 (ms):")
    for name, r in (("graphslam", gs), ("GTSAM IFLS", other)):
        tenths = r.get("p99_tenths")
        print(f"  {name}: " + (" ".join(f"{x:.3f}" for x in tenths) if tenths else "-"))
    print(f"\ngraphslam / GTSAM IFLS: p99 {ratio('p99_ms')} (first tenth "
          f"{ratio('p99_first_ms')}, last tenth {ratio('p99_last_ms')}), total {ratio('total_s')}")
    if gs["steps"] != other.get("steps") or gs["skipped_edges"] != other.get("skipped_edges"):
        print("note: the steps or the skipped edges differ: the two did not replay the same window")


def pose_stream(a):
    os.makedirs(a.work, exist_ok=True)
    stream = os.path.join(a.work, "poses.g2o")
    subprocess.run([a.graphslam, "simulate", "--poses", str(a.pose_stream), "--seed", str(a.seed), "-o", stream],
                   check=True, stdout=subprocess.DEVNULL)
    stats = os.path.join(a.work, "poses.csv")
    cmd = [a.graphslam, "incremental", stream, "-q", "--refine", "0", "--no-batch", "--stats", stats,
           "--window", str(a.window), "--window-slack", str(a.slack)]
    _, seconds, out = run_sampled(cmd, a.max_seconds)
    dec, steps, rss, secs = deciles(stats)
    print(f"pose stream: {steps} poses, window {a.window} (slack {a.slack}), {seconds:.1f} s\n")
    print("| tenth | p50 (ms) | p99 (ms) | max (ms) | RSS at its end (MB) |")
    print("|---|---|---|---|---|")
    for d, (p50, p99, mx) in enumerate(dec):
        end = min(len(rss) - 1, (d + 1) * len(rss) // 10 - 1)
        print(f"| {d + 1} | {p50:.3f} | {p99:.3f} | {mx:.1f} | {rss[end] / 1024:.1f} |")
    print(f"\np99 last / first tenth: {dec[-1][1] / dec[0][1]:.2f}; RSS growth over the last half: "
          f"{100 * rss_growth(rss):.2f} %")
    if a.gtsam_fls:
        refused = re.search(r"(\d+) edges reaching marginalised vertices refused", out)
        ms = [1e3 * x for x in secs]
        gs = {"steps": steps, "total_s": sum(secs), "run_s": seconds, "p50_first_ms": dec[0][0],
              "p50_last_ms": dec[-1][0], "p99_first_ms": dec[0][1], "p99_last_ms": dec[-1][1],
              "p99_ms": pct(ms, 99), "max_ms": max(ms), "rss_end_mb": rss[-1] / 1024,
              "skipped_edges": int(refused.group(1)) if refused else 0, "p99_tenths": [d[1] for d in dec]}
        side_by_side(a, stream, gs)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("graphslam")
    ap.add_argument("--laps", type=int, default=73)
    ap.add_argument("--window", type=int, default=200)
    ap.add_argument("--slack", type=int, default=0)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--work", default="/tmp/graphslam-soak")
    ap.add_argument("--outage-every", type=float, default=300.0)
    ap.add_argument("--outage-seconds", type=float, default=60.0)
    ap.add_argument("--plots", default="")
    ap.add_argument("--max-seconds", type=float, default=900.0)
    ap.add_argument("--modes", default="full,window,window-keep")
    ap.add_argument("--check", action="store_true",
                    help="exit 1 unless every figure is finite and both runs covered every step")
    ap.add_argument("--pose-stream", type=int, default=0)
    ap.add_argument("--gtsam-fls", default="", help="with --pose-stream: an external fixed-lag replay program "
                    "to run beside graphslam (the protocol above)")
    a = ap.parse_args()
    os.environ.update(OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    if a.gtsam_fls and a.pose_stream <= 0:
        sys.exit("soak: --gtsam-fls needs --pose-stream N")
    if a.pose_stream > 0:
        return pose_stream(a)
    os.makedirs(a.work, exist_ok=True)
    scen = os.path.join(a.work, "scenario")
    scenario(scen, a.laps)
    drive = os.path.join(a.work, "drive")
    subprocess.run([a.graphslam, "drivebot", "--scenario", scen, "--out", drive, "--seed", str(a.seed),
                    "--sensors", "gps,compass,laser", "--optimize-every", "0", "--final-iterations", "0",
                    "--max-steps", str(a.laps * 1500 + 1000)], check=True, stdout=subprocess.DEVNULL)
    stream = os.path.join(a.work, "stream.g2o")
    dropped = drop_gps(os.path.join(drive, "final.g2o"), stream, a.outage_every, a.outage_seconds)
    truth = os.path.join(drive, "steps.csv")
    results = {}
    for mode in a.modes.split(","):
        stats = os.path.join(a.work, f"{mode}.csv")
        out = os.path.join(a.work, f"{mode}.g2o")
        cmd = [a.graphslam, "incremental", stream, "-q", "--refine", "0", "--no-batch", "--stats", stats,
               "-o", out]
        files = [out]
        if mode.startswith("window"):
            marg = os.path.join(a.work, f"{mode}-marginalised.g2o")
            cmd += ["--window", str(a.window), "--window-slack", str(a.slack), "--marginalised-out", marg,
                    "--keep-landmarks" if mode == "window-keep" else "--reinitialise-landmarks"]
            files = [marg, out]
        _, seconds, _ = run_sampled(cmd, a.max_seconds)
        dec, steps, rss, _ = deciles(stats)
        err, err_half, matched = ape(trajectory(*files), truth)
        results[mode] = {"deciles": dec, "rss": rss, "seconds": seconds, "ape": err, "ape_half": err_half,
                         "steps": steps, "matched": matched, "growth": rss_growth(rss)}
    print(f"drive: {a.laps} laps, seed {a.seed}, {next(iter(results.values()))['steps']} steps, "
          f"{dropped} GPS fixes dropped in outages ({a.outage_seconds:g} s every {a.outage_every:g} s)\n")
    print("| mode | run (s) | p50 first / last 10 % (ms) | p99 first / last 10 % (ms) | p99 ratio | "
          "max (ms) | RSS end (MB) | RSS growth, last half | APE (m) | APE, second half (m) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for mode, r in results.items():
        d = r["deciles"]
        name = {"full": "full history", "window": f"window {a.window} (slack {a.slack}), landmarks leave",
                "window-keep": f"window {a.window} (slack {a.slack}), landmarks kept"}[mode]
        print(f"| {name} | {r['seconds']:.1f} | {d[0][0]:.3f} / {d[-1][0]:.3f} | {d[0][1]:.3f} / {d[-1][1]:.3f} "
              f"| {d[-1][1] / d[0][1]:.2f} | {max(x[2] for x in d):.1f} | {r['rss'][-1] / 1024:.1f} "
              f"| {100 * r['growth']:.1f} % | {r['ape']:.3f} | {r['ape_half']:.3f} |")
    print("\nper tenth of the run, p99 (ms):")
    for mode, r in results.items():
        print(f"  {mode}: " + " ".join(f"{d[1]:.3f}" for d in r["deciles"]))
    for mode in ("window", "window-keep"):
        if "full" in results and mode in results:
            print(f"\nAPE {mode} / full: {results[mode]['ape'] / results['full']['ape']:.3f} "
                  f"(second half {results[mode]['ape_half'] / results['full']['ape_half']:.3f})")
    if a.plots:
        os.makedirs(a.plots, exist_ok=True)
        plot(results, a.plots)
    if a.check:
        for mode, r in results.items():
            figures = [r["ape"], r["growth"]] + [x for d in r["deciles"] for x in d]
            if not all(math.isfinite(x) for x in figures) or r["matched"] < r["steps"] - 1:
                sys.exit(f"soak: {mode}: a figure is not finite or steps lack an estimate "
                         f"({r['matched']} of {r['steps']} matched)")


if __name__ == "__main__":
    main()
