# SPDX-License-Identifier: MIT
"""graphslam.load / Graph.save over every graph format the io module reads."""
import numpy as np
import pytest

import graphslam


def test_g2o_2d(dataset):
    g = graphslam.load(dataset("intel.g2o"))
    assert (g.num_vertices, g.num_edges) == (1728, 2512)
    assert g.format == "g2o" and not g.keep_initial_guess
    assert g.counts() == {"VERTEX_SE2": 1728, "EDGE_SE2": 2512}
    e = g.edge(0)
    assert e["line"] is not None and e["line"] > 1728  # vertices come first in the file


def test_g2o_3d(dataset):
    g = graphslam.load(dataset("sphere2500.g2o"))
    assert (g.num_vertices, g.num_edges) == (2500, 4949)
    ids, poses = g.estimates("VERTEX_SE3:QUAT")
    assert poses.shape == (2500, 7)
    assert np.linalg.norm(poses[:, 3:], axis=1) == pytest.approx(np.ones(2500))
    _, _, z = g.edges("EDGE_SE3:QUAT")
    assert z.shape == (4949, 7)


def test_toro_2d_and_3d(test_data):
    g = graphslam.load(test_data / "formats" / "square.graph")
    assert g.format == "toro" and g.counts()["VERTEX_SE2"] == 4
    assert g.estimate(1) == pytest.approx([1.1, 0.1, 1.6])
    g3 = graphslam.load(test_data / "formats" / "pose3.graph")
    assert g3.counts()["VERTEX_SE3:QUAT"] == 3


def test_isam(test_data):
    g = graphslam.load(test_data / "formats" / "landmarks_isam.txt")
    assert g.format == "isam"
    assert "EDGE_SE2_XY" in g.counts() and "VERTEX_XY" in g.counts()


def test_npz_homework(test_data):
    g = graphslam.load(test_data / "npz" / "hw_linear.npz")
    assert g.format == "npz" and g.keep_initial_guess
    truth = g.ground_truth
    assert truth is not None and truth["poses"].shape[1] == 2
    assert len(truth["pose_ids"]) == truth["poses"].shape[0]


def test_save_and_load_round_trip(dataset, tmp_path):
    g = graphslam.load(dataset("intel.g2o"))
    out = tmp_path / "intel_copy.g2o"
    g.save(str(out))
    back = graphslam.load(out)
    assert back.num_edges == g.num_edges
    assert back.estimates("VERTEX_SE2")[1] == pytest.approx(g.estimates("VERTEX_SE2")[1], abs=0)
    assert back.chi2() == g.chi2()


def test_graph_built_in_code_is_saved(tmp_path):
    g = graphslam.Graph()
    g.add_vertex("VERTEX_SE2", 0, [0, 0, 0], fixed=True)
    g.add_vertex("VERTEX_SE2", 1, [1, 0, 0.1])
    g.add_edge("EDGE_SE2", [0, 1], [1, 0, 0], np.diag([1.0, 2.0, 3.0]))
    path = tmp_path / "built.g2o"
    g.save(str(path))
    text = path.read_text()
    assert "FIX 0" in text and "EDGE_SE2 0 1 1 0 0 1 0 0 2 0 3" in text


def test_bad_file_names_its_line(tmp_path, test_data):
    bad = tmp_path / "bad.g2o"
    bad.write_text("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 zero 0\n")
    with pytest.raises(graphslam.InputError, match=r"bad\.g2o:2:"):
        graphslam.load(bad)
    with pytest.raises(graphslam.InputError, match="missing"):
        graphslam.load(tmp_path / "missing.g2o")
    with pytest.raises(graphslam.InputError, match=r"bad_isam\.txt:2"):
        graphslam.load(test_data / "formats" / "bad_isam.txt")


def test_edges_only_file_creates_vertices(dataset):
    g = graphslam.load(dataset("csail_sesync.g2o"))
    assert g.created_vertices == 1045 and g.num_vertices == 1045
