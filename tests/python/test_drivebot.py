# SPDX-License-Identifier: MIT
"""graphslam.drivebot: a short DriveBot run with GPS, from Python."""
import numpy as np

import graphslam


def test_short_run_with_gps():
    assert "q1_b" in graphslam.drivebot.scenarios()
    r = graphslam.drivebot.run("q1_b", sensors=["gps"], max_steps=300, seed=1)
    assert not r.failed, r.message
    steps = r.steps
    n = len(steps["time"])
    assert n > 10 and steps["truth"].shape == (n, 3) and steps["online"].shape == (n, 3)
    # The final smoothed history follows the truth within a few metres (GPS sigma 1 m).
    err = np.linalg.norm(r.history[:, :2] - steps["truth"][: len(r.history), :2], axis=1)
    assert err.mean() < 3.0, err.mean()
    assert r.graph.counts().get("EDGE_GPS", 0) > 0
    assert r.final_chi2 > 0


def test_optimizer_switch_gives_the_same_estimate():
    """optimize_every=1 with either optimizer: same final chi2, the optimizer named."""
    runs = {name: graphslam.drivebot.run("q1_b", sensors=["gps"], max_steps=200, seed=1,
                                         optimize_every=1, optimizer=name)
            for name in ("incremental", "batch")}
    assert runs["incremental"].optimizer == "incremental"
    assert runs["batch"].optimizer == "batch"
    assert runs["batch"].optimizations == runs["incremental"].optimizations > 100
    assert np.isclose(runs["batch"].final_chi2, runs["incremental"].final_chi2, rtol=1e-6)


def test_unknown_optimizer_is_refused():
    import pytest
    with pytest.raises(ValueError, match="'incremental' or 'batch'"):
        graphslam.drivebot.run("q1_b", max_steps=10, optimizer="isam")


def test_fixed_lag_window_keeps_the_map():
    """window=N: the states leave (history as they left, variance NaN), landmarks kept."""
    import pytest
    r = graphslam.drivebot.run("q2_b", sensors=["gps", "laser"], seed=2, optimize_every=1,
                               window=100, window_slack=20, landmarks="keep")
    assert not r.failed, r.message
    n = len(r.history)
    assert r.marginalized > n - 130
    assert r.refused_observations == 0
    assert np.isnan(r.history_variance[0]).all() and (r.history_variance[-1] > 0).all()
    assert r.graph.counts()["VERTEX_VEHICLE"] <= 120
    assert len(r.landmark_ids) == 7
    err = np.linalg.norm(r.history[:, :2] - r.steps["truth"][:n, :2], axis=1)
    assert err.mean() < 1.0, err.mean()
    with pytest.raises(ValueError, match="'leave', 'anew' or 'keep'"):
        graphslam.drivebot.run("q1_b", max_steps=10, window=5, landmarks="forget")


def test_checkpoint_and_resume(tmp_path):
    """A run resumed from the last checkpoint of another ends with its estimates exactly."""
    import pytest
    ck = str(tmp_path / "run.ck")
    args = dict(sensors=["gps"], max_steps=400, seed=1, optimize_every=1, window=50,
                landmarks="keep")
    first = graphslam.drivebot.run("q1_b", checkpoint=ck, checkpoint_every=150, **args)
    resumed = graphslam.drivebot.run("q1_b", resume=ck, **args)
    assert not first.failed and not resumed.failed
    assert np.array_equal(first.history, resumed.history)
    assert np.array_equal(first.steps["online"], resumed.steps["online"])
    with pytest.raises(graphslam.InputError, match="other settings"):
        graphslam.drivebot.run("q1_b", resume=ck, **dict(args, seed=2))
    with pytest.raises(ValueError, match="go together"):
        graphslam.drivebot.run("q1_b", checkpoint=ck, **args)
