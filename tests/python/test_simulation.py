# SPDX-License-Identifier: MIT
"""Simulators, the global initial guess and the observability check."""
import numpy as np
import pytest

import graphslam


def test_manhattan_is_seeded_and_optimises_to_the_truth():
    a = graphslam.simulate_manhattan(num_poses=300, seed=5, num_landmarks=20)
    b = graphslam.simulate_manhattan(num_poses=300, seed=5, num_landmarks=20)
    assert np.array_equal(a.graph.estimates("VERTEX_SE2")[1], b.graph.estimates("VERTEX_SE2")[1])
    assert a.true_poses.shape == (300, 3) and a.true_landmarks.shape == (20, 2)
    assert a.num_loop_closures > 0
    g = a.graph
    r = graphslam.optimize(g)
    assert r.ok
    _, est = g.estimates("VERTEX_SE2")
    # The first pose is the origin in both; the optimised poses lie near the truth.
    err = np.linalg.norm(est[:, :2] - a.true_poses[:, :2], axis=1)
    assert err.max() < 0.5
    dr = np.linalg.norm(b.graph.estimates("VERTEX_SE2")[1][:, :2] - a.true_poses[:, :2], axis=1)
    assert err.mean() < dr.mean()


def test_sphere_3d():
    s = graphslam.simulate_pose_graph_3d(num_poses=200, seed=2)
    assert s.true_poses.shape == (200, 7)
    g = s.graph
    g.keep_initial_guess = False
    r = graphslam.optimize(g)
    assert r.ok and r.final_chi2 < r.initial_chi2


def test_initialize_and_observability(dataset):
    g = graphslam.load(dataset("intel.g2o"))
    before = g.chi2()
    lines = graphslam.initialize(g)
    assert lines and g.chi2() < before
    report = graphslam.check_observability(g)
    assert report["ok"] and report["unanchored"]
    h = graphslam.Graph()
    h.add_vertex("VERTEX_XY", 0, [0, 0], fixed=True)
    h.add_vertex("VERTEX_XY", 1, [1, 0])
    report = graphslam.check_observability(h)
    assert not report["ok"] and report["undetermined"][0]["id"] == 1
    assert report["undetermined"][0]["reason"] == "no edges"
