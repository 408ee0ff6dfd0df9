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
