#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A landmark SLAM problem built in code with numpy: a robot on a circle observes four
landmarks (EDGE_SE2_XY, the landmark in the robot's frame); poses and landmarks start
perturbed and are optimised; prints the position errors and a landmark's covariance.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/landmarks_in_code.py
"""
import numpy as np

import graphslam


def se2_between(a, b):
    """a^-1 b for poses (x, y, theta)."""
    c, s = np.cos(a[2]), np.sin(a[2])
    dx, dy = b[0] - a[0], b[1] - a[1]
    return np.array([c * dx + s * dy, -s * dx + c * dy,
                     np.arctan2(np.sin(b[2] - a[2]), np.cos(b[2] - a[2]))])


def main():
    rng = np.random.default_rng(42)
    n = 40
    angles = np.linspace(0, 2 * np.pi, n, endpoint=False)
    poses = np.column_stack([5 * np.cos(angles), 5 * np.sin(angles), angles + np.pi / 2])
    landmarks = np.array([[0.0, 0.0], [8.0, 0.0], [0.0, 8.0], [-8.0, -8.0]])

    g = graphslam.Graph()
    g.add_vertices("VERTEX_SE2", np.arange(n), poses + rng.normal(0, 0.2, poses.shape))
    lm_ids = np.arange(100, 100 + len(landmarks))
    g.add_vertices("VERTEX_XY", lm_ids, landmarks + rng.normal(0, 0.5, landmarks.shape))
    g.fix(0)
    g.set_estimate(0, poses[0])

    odometry = [se2_between(poses[i], poses[(i + 1) % n]) + rng.normal(0, [0.02, 0.02, 0.005])
                for i in range(n)]
    g.add_edges("EDGE_SE2", [[i, (i + 1) % n] for i in range(n)], odometry,
                np.diag([2500.0, 2500.0, 40000.0]))
    pairs, seen = [], []
    for i, p in enumerate(poses):
        c, s = np.cos(p[2]), np.sin(p[2])
        for k, l in enumerate(landmarks):
            d = l - p[:2]
            pairs.append([i, lm_ids[k]])
            seen.append(np.array([c * d[0] + s * d[1], -s * d[0] + c * d[1]]) + rng.normal(0, 0.05, 2))
    g.add_edges("EDGE_SE2_XY", pairs, seen, np.eye(2) * 400.0)

    result = graphslam.optimize(g)
    print(f"{result.status}: chi2 {result.initial_chi2:.6g} -> {result.final_chi2:.6g} "
          f"in {result.iterations} iterations")
    _, est_poses = g.estimates("VERTEX_SE2")
    _, est_lm = g.estimates("VERTEX_XY")
    pose_err = np.linalg.norm(est_poses[:, :2] - poses[:, :2], axis=1)
    lm_err = np.linalg.norm(est_lm - landmarks, axis=1)
    print(f"pose position error: rmse {np.sqrt(np.mean(pose_err ** 2)):.4f} m")
    print(f"landmark position error: max {lm_err.max():.4f} m")
    cov = graphslam.marginals(g, tag="VERTEX_XY")
    print("covariance of landmark 101:\n", np.array2string(cov[101], precision=6))


if __name__ == "__main__":
    main()
