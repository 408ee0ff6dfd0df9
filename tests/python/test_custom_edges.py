# SPDX-License-Identifier: MIT
"""Edge types written in Python: registered under a tag, used like the library's own."""
import math

import numpy as np
import pytest

import graphslam


class PythonSE2(graphslam.CustomEdge):
    """EDGE_SE2's error written in numpy: t2v(Z^-1 (X_i^-1 X_j))."""
    tag = "EDGE_SE2_PYTHON"
    vertex_tags = ("VERTEX_SE2", "VERTEX_SE2")
    dimension = 3

    def error(self, estimates, measurement):
        (xi, yi, ti), (xj, yj, tj) = estimates
        c, s = math.cos(ti), math.sin(ti)
        dx, dy = xj - xi, yj - yi
        rel = np.array([c * dx + s * dy, -s * dx + c * dy, tj - ti])
        cz, sz = math.cos(measurement[2]), math.sin(measurement[2])
        ex, ey = rel[0] - measurement[0], rel[1] - measurement[1]
        return np.array([cz * ex + sz * ey, -sz * ex + cz * ey,
                         math.remainder(rel[2] - measurement[2], 2 * math.pi)])


class Range(graphslam.CustomEdge):
    """Distance from a pose to a point."""
    tag = "EDGE_RANGE_PYTHON"
    vertex_tags = ("VERTEX_SE2", "VERTEX_XY")
    dimension = 1

    def error(self, estimates, measurement):
        pose, point = estimates
        return np.array([np.hypot(*(point - pose[:2])) - measurement[0]])


@pytest.fixture(scope="module", autouse=True)
def registered():
    graphslam.register_edge(PythonSE2)
    graphslam.register_edge(Range)
    assert "EDGE_RANGE_PYTHON" in graphslam.edge_tags()


def test_python_edge_matches_the_library_edge(dataset, tmp_path):
    ref = graphslam.load(dataset("intel.g2o"))
    # The same graph with every EDGE_SE2 as the Python type.
    g = graphslam.Graph()
    ids, poses = ref.estimates("VERTEX_SE2")
    g.add_vertices("VERTEX_SE2", ids, poses)
    _, pairs, z = ref.edges("EDGE_SE2")
    info = ref.edge_information("EDGE_SE2")
    for k in range(len(pairs)):
        g.add_edge("EDGE_SE2_PYTHON", pairs[k], z[k], info[k])
    assert g.chi2() == pytest.approx(ref.chi2(), rel=1e-12)
    expected = graphslam.optimize(ref, init="none", algorithm="gn", max_iterations=5)
    got = graphslam.optimize(g, init="none", algorithm="gn", max_iterations=5)
    assert got.final_chi2 == pytest.approx(expected.final_chi2, rel=1e-6)
    # Saved and read back under its tag.
    path = tmp_path / "python_edges.g2o"
    g.save(path)
    assert "EDGE_SE2_PYTHON 0 1 " in path.read_text()
    back = graphslam.load(path)
    assert back.counts()["EDGE_SE2_PYTHON"] == len(pairs)
    assert back.chi2() == pytest.approx(g.chi2(), rel=1e-12)


def test_range_only_localisation():
    g = graphslam.Graph()
    g.add_vertex("VERTEX_SE2", 0, [0.3, -0.2, 0.0])
    beacons = np.array([[5.0, 0.0], [0.0, 5.0], [-4.0, -3.0]])
    truth = np.array([1.0, 1.0])
    for k, b in enumerate(beacons):
        g.add_vertex("VERTEX_XY", 10 + k, b, fixed=True)
        g.add_edge("EDGE_RANGE_PYTHON", [0, 10 + k], [np.linalg.norm(b - truth)], [[100.0]])
    g.add_edge("EDGE_PRIOR_SE2", [0], [0, 0, 0], np.diag([1e-6, 1e-6, 1.0]))
    r = graphslam.optimize(g)
    assert r.ok, r.message
    assert g.estimate(0)[:2] == pytest.approx(truth, abs=1e-5)


def test_errors_of_python_edges():
    class Broken(graphslam.CustomEdge):
        tag = "EDGE_BROKEN_PYTHON"
        vertex_tags = ("VERTEX_XY",)
        dimension = 2

        def error(self, estimates, measurement):
            raise ZeroDivisionError("broken on purpose")

    graphslam.register_edge(Broken)
    g = graphslam.Graph()
    g.add_vertex("VERTEX_XY", 0, [0, 0])
    g.add_edge("EDGE_BROKEN_PYTHON", [0], [1, 1])
    with pytest.raises(ZeroDivisionError, match="broken on purpose"):
        graphslam.optimize(g)
    with pytest.raises(graphslam.Error, match="VERTEX_SE2"):
        g.add_vertex("VERTEX_SE2", 1, [0, 0, 0])
        g.add_edge("EDGE_RANGE_PYTHON", [0, 1], [1.0])  # slot 0 wants a VERTEX_SE2
    with pytest.raises(graphslam.RegistryError):
        graphslam.register_edge(Range)  # the tag is taken
    with pytest.raises(graphslam.Error):
        g.add_edge("EDGE_RANGE_PYTHON", [1], [1.0])  # one vertex of two
