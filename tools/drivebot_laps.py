#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Per-lap optimisation times of a DriveBot run: `tools/drivebot_laps.py OUT/steps.csv
[--steps-per-lap-waypoints N]` prints one markdown row per lap (lap = waypoint index / N,
default 4: the q2_c square) with the optimisations' count, median, mean, max and sum of the
CPU time, the median CPU time of the steps with landmark observations and of the others
(the overall median lies between the two), and the median and sum of the wall time.
Standard library only."""
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
                (float(row["optimization_cpu_time"]), float(row["optimization_time"]),
                 int(row["observations"]) > 0))
    print("| lap | steps | median CPU | mean CPU | max CPU | sum CPU | median CPU, landmark steps "
          "| median CPU, other steps | median wall | sum wall |")
    print("|---|---|---|---|---|---|---|---|---|---|")

    def median_ms(values):
        return f"{statistics.median(values) * 1e3:.3f} ms" if values else "-"

    for lap in sorted(laps):
        cpu = [c for c, _, _ in laps[lap]]
        wall = [w for _, w, _ in laps[lap]]
        seen = [c for c, _, obs in laps[lap] if obs]
        other = [c for c, _, obs in laps[lap] if not obs]
        print(f"| {lap} | {len(cpu)} | {median_ms(cpu)} "
              f"| {statistics.mean(cpu) * 1e3:.3f} ms | {max(cpu) * 1e3:.2f} ms | {sum(cpu):.2f} s "
              f"| {median_ms(seen)} ({len(seen)}) | {median_ms(other)} ({len(other)}) "
              f"| {median_ms(wall)} | {sum(wall):.2f} s |")


if __name__ == "__main__":
    main()
