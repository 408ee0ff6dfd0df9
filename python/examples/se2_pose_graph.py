#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The SE(2) pose-graph homework (ShanghaiTech SLAM 2024, homework 1) in a few lines.

Dead reckoning from twelve noisy relative poses drifts; the pose graph that closes the loop
(the last relative pose as the edge 11 -> 0) is optimised by Gauss-Newton, and both are
compared with the ground truth by APE (evo's translation part, no alignment):
rmse 0.138007 -> 0.048338.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/se2_pose_graph.py [DATA_DIR]
"""
import os
import pathlib
import sys

import graphslam
from graphslam.eval import ape


def main():
    data = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else
                        os.environ.get("GRAPHSLAM_DATA", "../shared/datasets"))
    folder = data / "seeds" / "shanghaitech_slam2024_hw1"
    truth = folder / "gt_tum_student_generated.txt"

    relative = graphslam.read_relative_poses(folder / "hw1_data.txt")  # (12, 3): dx dy dtheta
    dead_reckoning = graphslam.dead_reckon_se2(relative)  # (13, 3) from the identity
    x, y, theta = dead_reckoning[12]
    print(f"dead reckoning, pose 12: x {x:.6f} y {y:.6f} theta {theta:.6f} (should be pose 0)")

    graph = graphslam.pose_graph_from_relative_poses(relative)  # 12 poses, 12 edges, Omega = I
    result = graphslam.optimize(graph, init="none", algorithm="gn", step_tolerance=1e-9,
                                function_tolerance=0)
    print(f"Gauss-Newton: chi2 {result.initial_chi2:.10g} -> {result.final_chi2:.10g} "
          f"in {result.iterations} iterations ({result.status})")
    _, optimised = graph.estimates("VERTEX_SE2")

    before = ape(truth, dead_reckoning)
    after = ape(truth, optimised)
    print(f"APE rmse (m): dead reckoning {before.rmse:.6f} -> optimised {after.rmse:.6f}")
    for name in ("max", "mean", "median", "min", "rmse", "sse", "std"):
        print(f"  {name:6s} {before.statistics[name]:.6f}  {after.statistics[name]:.6f}")


if __name__ == "__main__":
    main()
