#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Per-lap optimisation times of a DriveBot run: `tools/drivebot_laps.py OUT/steps.csv
[--steps-per-lap-waypoints N]` prints one markdown row per lap (lap = waypoint index / N,
default 4: the q2_c square) with the optimisations' count, median, mean, max and sum of the
CPU time, and the median and sum of the wall time. Standard library only."""
import argparse
import csv
import statistics


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("steps_csv")
    parser.add_argument("--steps-per-lap-waypoints", type=int, default=4)
    args = parser.parse_args()
    laps = {}
    with open(args.steps_csv, newline="") as f:
        for row in csv.DictReader(f):
            if row["optimized"] != "1":
                continue
            lap = int(row["waypoint"]) // args.steps_per_lap_waypoints + 1
            laps.setdefault(lap, []).append(
                (float(row["optimization_cpu_time"]), float(row["optimization_time"])))
    print("| lap | steps | median CPU | mean CPU | max CPU | sum CPU | median wall | sum wall |")
    print("|---|---|---|---|---|---|---|---|")
    for lap in sorted(laps):
        cpu = [c for c, _ in laps[lap]]
        wall = [w for _, w in laps[lap]]
        print(f"| {lap} | {len(cpu)} | {statistics.median(cpu) * 1e3:.3f} ms "
              f"| {statistics.mean(cpu) * 1e3:.3f} ms | {max(cpu) * 1e3:.2f} ms | {sum(cpu):.2f} s "
              f"| {statistics.median(wall) * 1e3:.3f} ms | {sum(wall):.2f} s |")


if __name__ == "__main__":
    main()
