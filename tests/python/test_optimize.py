# SPDX-License-Identifier: MIT
"""graphslam.optimize against the graphslam tool and the library's reference values."""
import re
import threading

import numpy as np
import pytest

import graphslam

# Final chi2 of the tool's default run (global initialisation, Gauss-Newton with LM
# fallback): tests/datasets/test_datasets.cpp's reference values.
REFERENCE = {
    "intel.g2o": 45.00469581,
    "mit.g2o": 41.16326884,
    "city10000.g2o": 511.9851636,
    "sphere2500.g2o": 727.1496672,
    "smallgrid3d.g2o": 458.1537843,
}


def tool_final_chi2(tool, path, *args):
    """The final chi2 `graphslam optimize PATH --quiet` prints."""
    out = tool("optimize", path, "--quiet", *args)
    m = re.search(r"chi2\s*[:=]?\s*([-+0-9.eE]+)\s*->\s*([-+0-9.eE]+)", out)
    assert m, out
    return float(m.group(2)), out


@pytest.mark.parametrize("name", ["intel.g2o", "mit.g2o", "smallgrid3d.g2o"])
def test_default_run_reaches_the_reference_chi2(dataset, name):
    g = graphslam.load(dataset(name))
    r = graphslam.optimize(g)
    assert r.ok, r.message
    assert r.status == "converged"
    assert r.final_chi2 == pytest.approx(REFERENCE[name], rel=1e-6)
    assert r.initial_chi2 > r.final_chi2
    assert r.initialization and r.gauge_fixed == [0]
    assert g.chi2() == pytest.approx(r.final_chi2, rel=1e-12)


@pytest.mark.parametrize("name", ["city10000.g2o", "sphere2500.g2o"])
def test_same_chi2_as_the_tool(dataset, tool, name):
    path = dataset(name)
    expected, out = tool_final_chi2(tool, path)
    r = graphslam.optimize(graphslam.load(path))
    assert r.final_chi2 == pytest.approx(REFERENCE[name], rel=1e-6)
    # The tool prints 10 significant digits.
    assert r.final_chi2 == pytest.approx(expected, rel=1e-9), out
    assert re.search(rf"iterations:\s+{r.iterations}\n", out), out


def test_gauss_newton_from_the_file(dataset, tool):
    path = dataset("intel.g2o")
    expected, _ = tool_final_chi2(tool, path, "--init", "none", "--algorithm", "gn")
    r = graphslam.optimize(graphslam.load(path), init="none", algorithm="gn")
    assert r.final_chi2 == pytest.approx(expected, rel=1e-9)
    assert r.algorithm == "gauss-newton"


def test_callback_sees_every_iteration_and_can_stop(dataset):
    g = graphslam.load(dataset("intel.g2o"))
    seen = []

    def stop_after_two(stats):
        seen.append(stats)
        return stats["iteration"] < 2

    r = graphslam.optimize(g, init="none", algorithm="gn", callback=stop_after_two)
    assert r.status == "stopped" and r.stopped and r.ok
    assert r.iterations == 2 and [s["iteration"] for s in seen] == [1, 2]
    assert seen[1]["chi2"] == pytest.approx(r.chi2_history[1])
    assert seen[0]["chi2"] > seen[1]["chi2"] > 0


def test_callback_exception_propagates(dataset):
    g = graphslam.load(dataset("mit.g2o"))

    def boom(stats):
        raise RuntimeError("from the callback")

    with pytest.raises(RuntimeError, match="from the callback"):
        graphslam.optimize(g, callback=boom)
    # The graph is usable afterwards.
    assert graphslam.optimize(g).ok


def test_gil_is_released_while_optimising(dataset):
    g = graphslam.load(dataset("city10000.g2o"))
    ticks = []
    done = threading.Event()

    def ticker():
        while not done.is_set():
            ticks.append(1)
            done.wait(0.001)

    t = threading.Thread(target=ticker)
    t.start()
    try:
        r = graphslam.optimize(g)
    finally:
        done.set()
        t.join()
    assert r.ok and r.seconds > 0.05
    # The other thread ran while the library worked (at least a tick per 10 ms).
    assert len(ticks) > r.seconds * 100 * 0.5, (len(ticks), r.seconds)


def test_robust_kernel_and_options(dataset, tool):
    path = dataset("intel.g2o")
    expected, out = tool_final_chi2(tool, path, "--robust-kernel", "huber:0.1",
                                    "--robust-edges", "loop-closures")
    g = graphslam.load(path)
    r = graphslam.optimize(g, robust_kernel="huber:0.1", robust_edges="loop-closures")
    assert r.ok and r.robust_edges == 2512 - 1727  # every edge but the odometry
    assert r.final_chi2 == pytest.approx(expected, rel=1e-9), out
    assert r.final_cost < r.final_chi2
    with pytest.raises(graphslam.RegistryError, match="nope"):
        graphslam.optimize(g, robust_kernel="nope")
    with pytest.raises(ValueError, match="algorithm"):
        graphslam.optimize(g, algorithm="newton")
    with pytest.raises(ValueError, match="solver"):
        graphslam.optimize(g, solver="no-such-solver")
    with pytest.raises(ValueError, match="max_iterations"):
        graphslam.optimize(g, max_iterations=0)


def test_reject_outliers_as_the_tool(dataset, tool, tmp_path):
    g = graphslam.load(dataset("intel.g2o"))
    added = graphslam.add_wrong_loop_closures(g, count=20, seed=3)
    wrong = {tuple(g.edge(int(i))["vertex_ids"]) for i in added}
    path = tmp_path / "intel_wrong.g2o"
    g.save(path)
    listed = tmp_path / "outliers.txt"
    expected, out = tool_final_chi2(tool, path, "--reject-outliers", "--outliers", listed)
    tool_lines = sorted(int(line.split()[0]) for line in listed.read_text().splitlines()
                        if not line.startswith("#"))
    g = graphslam.load(path)
    r = graphslam.optimize(g, reject_outliers=True)
    assert r.ok, r.message
    assert r.final_chi2 == pytest.approx(expected, rel=1e-9), out
    assert sorted(e["line"] for e in r.rejected_edges) == tool_lines
    rejected = {tuple(e["vertex_ids"]) for e in r.rejected_edges}
    assert wrong <= rejected
    assert g.num_edges == 2512 + 20 - len(rejected)


def test_undetermined_vertex_is_named(dataset):
    g = graphslam.Graph()
    g.add_vertex("VERTEX_SE2", 0, [0, 0, 0], fixed=True)
    g.add_vertex("VERTEX_XY", 1, [1, 1])
    g.add_edge("EDGE_BEARING_SE2_XY", [0, 1], [0.7])
    with pytest.raises(graphslam.InputError, match="vertex 1"):
        graphslam.optimize(g)
    r = graphslam.optimize(g, drop_unobservable=True)
    assert r.dropped_vertices == [1] and g.num_vertices == 1


def test_marginals_match_the_tool(dataset, tool, tmp_path):
    path = dataset("mit.g2o")
    out = tmp_path / "cov.txt"
    tool("optimize", path, "--quiet", "--marginals", out)
    expected = {}
    for line in out.read_text().splitlines():
        if line.startswith("#"):
            continue
        v = line.split()
        expected[int(v[0])] = np.array(list(map(float, v[1:])))
    g = graphslam.load(path)
    graphslam.optimize(g)
    m = graphslam.marginals(g)
    assert len(m) == len(expected) == g.num_vertices
    iu = np.triu_indices(3)
    for vid in (1, 100, 807):
        c = m[vid]
        assert c.shape == (3, 3) and c == pytest.approx(c.T)
        assert c[iu] == pytest.approx(expected[vid], rel=1e-6, abs=1e-12)
    stacked = m.stack()
    assert stacked.shape == (g.num_vertices, 3, 3)


def test_marginals_of_a_free_vertex_fail_with_its_id():
    g = graphslam.Graph()
    g.add_vertex("VERTEX_SE2", 0, [0, 0, 0], fixed=True)
    g.add_vertex("VERTEX_SE2", 1, [1, 0, 0])
    g.add_vertex("VERTEX_SE2", 2, [2, 0, 0])
    g.add_edge("EDGE_SE2", [0, 1], [1, 0, 0])
    with pytest.raises(graphslam.InputError, match="2"):
        graphslam.marginals(g, ids=[1, 2])


def test_ctrl_c_stops_the_library(dataset):
    import os
    import signal
    g = graphslam.load(dataset("city10000.g2o"))
    timer = threading.Timer(0.05, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            graphslam.optimize(g, init="none", algorithm="lm", function_tolerance=0,
                               step_tolerance=0, max_iterations=1_000_000)
    finally:
        timer.cancel()
    assert g.chi2() > 0  # the graph stays usable


def test_callback_may_read_but_not_change_the_graph(dataset):
    g = graphslam.load(dataset("mit.g2o"))
    seen = []

    def watch(stats):
        ids, poses = g.estimates("VERTEX_SE2")
        seen.append(poses.copy())

    r = graphslam.optimize(g, callback=watch)
    assert r.ok and len(seen) == r.iterations
    assert seen[-1] == pytest.approx(g.estimates("VERTEX_SE2")[1])

    def change(stats):
        g.set_estimate(1, [0, 0, 0])

    with pytest.raises(RuntimeError, match="in use"):
        graphslam.optimize(g, callback=change)
