# SPDX-License-Identifier: MIT
"""graphslam.eval (APE/RPE as evo), trajectories, dead reckoning: the SE(2) homework's
numbers (../shared/SEEDS.md section 3)."""
import math

import numpy as np
import pytest

import graphslam
from graphslam.eval import ape, rpe


@pytest.fixture
def homework(data_dir):
    folder = data_dir / "seeds" / "shanghaitech_slam2024_hw1"
    if not (folder / "hw1_data.txt").exists():
        pytest.skip(f"{folder} is absent (set GRAPHSLAM_DATA)")
    return folder


def test_dead_reckoning_drifts(homework):
    rel = graphslam.read_relative_poses(homework / "hw1_data.txt")
    assert rel.shape == (12, 3)
    poses = graphslam.dead_reckon_se2(rel)
    assert poses.shape == (13, 3)
    assert poses[12] == pytest.approx([-0.056860, 0.057527, -0.141896], abs=5e-7)
    result = ape(homework / "gt_tum_student_generated.txt", poses)
    assert len(result.errors) == 12
    s = result.statistics
    assert s["rmse"] == pytest.approx(0.138007, abs=5e-7)
    assert s["max"] == pytest.approx(0.221483, abs=5e-7)
    assert s["median"] == pytest.approx(0.138624, abs=5e-7)
    assert s["std"] == pytest.approx(0.076387, abs=5e-7)


def test_pose_graph_optimisation_improves_ape(homework):
    rel = graphslam.read_relative_poses(homework / "hw1_data.txt")
    g = graphslam.pose_graph_from_relative_poses(rel)
    assert (g.num_vertices, g.num_edges) == (12, 12)
    r = graphslam.optimize(g, init="none", algorithm="gn", step_tolerance=1e-9,
                           function_tolerance=0)
    assert r.initial_chi2 == pytest.approx(0.02667689807, rel=1e-9)
    assert r.final_chi2 == pytest.approx(0.004044419348, rel=1e-9)
    assert r.iterations == 7
    _, poses = g.estimates("VERTEX_SE2")
    assert poses[3] == pytest.approx([-0.958422, 0.931622, 1.537147], abs=5e-7)
    result = ape(homework / "gt_tum_student_generated.txt", poses)
    assert result.rmse == pytest.approx(0.048338, abs=5e-7)
    assert result.max == pytest.approx(0.080027, abs=5e-7)
    full = ape(homework / "gt_tum_student_generated.txt", poses, pose_relation="full")
    assert full.rmse == pytest.approx(0.083525, abs=1e-6)  # SEEDS.md: 0.083525


def test_trajectory_round_trips(tmp_path):
    se2 = np.array([[0, 0, 0], [1, 0, 0.5], [1.5, 1, math.pi - 1e-3], [1, 2, -2.0]])
    t = graphslam.Trajectory.from_se2(se2, timestamps=[10, 11, 12, 13])
    assert len(t) == 4 and t.timestamps.tolist() == [10, 11, 12, 13]
    assert t.to_se2() == pytest.approx(se2)
    assert t.poses.shape == (4, 4, 4)
    t.write_tum(tmp_path / "t.tum")
    back = graphslam.Trajectory.read(tmp_path / "t.tum")
    assert back.to_tum() == pytest.approx(t.to_tum(), abs=1e-15)
    t.write_kitti(tmp_path / "t.kitti")
    k = graphslam.Trajectory.read(tmp_path / "t.kitti")
    assert k.timestamps.tolist() == [0, 1, 2, 3]
    assert k.poses == pytest.approx(t.poses, abs=1e-15)
    assert graphslam.Trajectory(t.poses).to_se2() == pytest.approx(se2)
    assert graphslam.Trajectory.from_tum(t.to_tum()).poses == pytest.approx(t.poses)


def test_alignment_removes_a_rigid_motion():
    rng = np.random.default_rng(1)
    ref = np.cumsum(rng.normal(size=(50, 3)), axis=0)
    ref[:, 2] = np.arctan2(np.sin(ref[:, 2]), np.cos(ref[:, 2]))
    c, s = math.cos(0.3), math.sin(0.3)
    est = ref.copy()
    est[:, 0] = c * ref[:, 0] - s * ref[:, 1] + 5
    est[:, 1] = s * ref[:, 0] + c * ref[:, 1] - 2
    est[:, 2] = ref[:, 2] + 0.3
    assert ape(ref, est).rmse > 1.0
    aligned = ape(ref, est, align=True)
    assert aligned.rmse == pytest.approx(0.0, abs=1e-9)
    assert aligned.rotation.shape == (3, 3)
    # RPE does not see a rigid motion of the whole trajectory.
    assert rpe(ref, est).rmse == pytest.approx(0.0, abs=1e-9)
    r = rpe(ref, est, delta=2, pose_relation="angle_deg")
    assert r.id_pairs.shape[1] == 2 and r.id_pairs[0].tolist() == [0, 2]


def test_eval_input_errors(tmp_path):
    with pytest.raises(ValueError, match="shape"):
        ape(np.zeros((3, 5)), np.zeros((3, 5)))
    with pytest.raises(ValueError, match="pose_relation"):
        ape(np.zeros((3, 3)), np.zeros((3, 3)), pose_relation="nope")
    bad = tmp_path / "bad.tum"
    bad.write_text("0 0 0 0 0 0 0 1\n1 0 0 x 0 0 0 1\n")
    with pytest.raises(graphslam.InputError, match=r"bad\.tum:2"):
        graphslam.Trajectory.read(bad)


def test_dead_reckon_graph_and_position_errors(test_data):
    sim = graphslam.simulate_manhattan(num_poses=50, seed=3)
    t = graphslam.dead_reckon(sim.graph)
    assert len(t) == 50
    # The simulator's estimates are the dead-reckoned odometry.
    assert t.to_se2()[:, :2] == pytest.approx(sim.graph.estimates("VERTEX_SE2")[1][:, :2], abs=1e-9)
    g = graphslam.load(test_data / "npz" / "hw_linear.npz")
    before = graphslam.eval.position_errors(g)
    graphslam.optimize(g)
    after = graphslam.eval.position_errors(g)
    assert after["poses"]["rmse"] < before["poses"]["rmse"]
    assert after["poses"]["count"] == len(g.ground_truth["pose_ids"])
