# SPDX-License-Identifier: MIT
"""graphslam.certify, verify_certificate and write_view: the certify and view modules from
Python, against the tool."""
import re

import numpy as np
import pytest

import graphslam


def test_certify_matches_the_tool(dataset, tool):
    path = dataset("intel.g2o")
    g = graphslam.load(str(path))
    c = graphslam.certify(g)
    assert c.certified, c.reason
    assert c.objective == pytest.approx(52.35, abs=0.005)  # SE-Sync's f* (MANIFEST.md)
    assert c.dual_bound <= c.objective and c.suboptimality < 1e-6
    assert c.rank >= 3 and c.steps and c.steps[-1]["rank"] == c.rank
    # The tool reports the same F(x).
    out = tool("certify", path)
    f = float(re.search(r"F\(x\)\s*[=:]?\s*([0-9.eE+-]+)", out).group(1))
    assert f == pytest.approx(c.objective, rel=1e-6)
    # The graph now holds the certified poses: their certificate holds without a solve.
    v = graphslam.verify_certificate(g)
    assert v.certified, v.reason
    assert v.objective == pytest.approx(c.objective, rel=1e-6)


def test_certify_refuses_landmarks_and_bad_options(test_data):
    g = graphslam.Graph()
    g.add_vertex("VERTEX_SE2", 0, [0.0, 0.0, 0.0])
    g.add_vertex("VERTEX_XY", 1, [1.0, 0.0])
    g.add_edge("EDGE_SE2_XY", [0, 1], [1.0, 0.0], np.eye(2))
    with pytest.raises(graphslam.InputError):
        graphslam.certify(g)
    with pytest.raises(ValueError, match="'chordal' or 'estimates'"):
        graphslam.certify(g, start="odometry")


def test_write_view_is_one_page(dataset, tmp_path):
    g = graphslam.load(str(dataset("intel.g2o")))
    graphslam.optimize(g)
    m = graphslam.marginals(g, [1000])
    page = tmp_path / "intel.html"
    graphslam.write_view(g, str(page), title="intel from Python", covariances={1000: m[1000]})
    text = page.read_text()
    assert text.startswith("<!DOCTYPE html>") and "intel from Python" in text
    assert "http://" not in text and "https://" not in text  # nothing fetched
    with pytest.raises(graphslam.Error):
        graphslam.write_view(g, str(tmp_path / "no" / "folder" / "x.html"))
    assert not (tmp_path / "no").exists()
