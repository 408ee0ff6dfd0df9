# SPDX-License-Identifier: MIT
"""graphslam.IncrementalOptimizer: an online run reaches the batch optimum."""
import numpy as np
import pytest

import graphslam


def test_online_run_matches_batch():
    sim = graphslam.simulate_manhattan(num_poses=200, seed=11)
    full = sim.graph
    ids, poses = full.estimates("VERTEX_SE2")
    edges_idx, pairs, z = full.edges("EDGE_SE2")
    info = full.edge_information("EDGE_SE2")
    inc = graphslam.IncrementalOptimizer()
    inc.add_vertex("VERTEX_SE2", 0, poses[0], fixed=True)
    added = 0
    for j in range(1, len(ids)):
        inc.add_vertex("VERTEX_SE2", int(ids[j]), poses[j])
        for k in np.nonzero(np.max(pairs, axis=1) == ids[j])[0]:
            inc.add_edge("EDGE_SE2", pairs[k], z[k], info[k])
            added += 1
        assert inc.update(), inc.failure
    assert added == len(pairs)
    assert inc.stats["passes"] >= 1
    assert inc.refine()
    batch = full.copy()
    batch.fix(0)
    r = graphslam.optimize(batch, init="none")
    assert inc.chi2() == pytest.approx(r.final_chi2, rel=1e-4)
    _, online = inc.graph.estimates("VERTEX_SE2")
    _, best = batch.estimates("VERTEX_SE2")
    assert online[:, :2] == pytest.approx(best[:, :2], abs=1e-3)
    cov = inc.marginal_covariance(int(ids[-1]))
    assert cov.shape == (3, 3) and np.all(np.linalg.eigvalsh(cov) > 0)
