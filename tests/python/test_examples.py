# SPDX-License-Identifier: MIT
"""Every example of python/examples runs and prints what it promises."""
import os
import re
import subprocess
import sys

import pytest

from conftest import SOURCE_DIR

EXAMPLES = SOURCE_DIR / "python" / "examples"


def run(script, *args):
    done = subprocess.run([sys.executable, str(EXAMPLES / script), *map(str, args)],
                          capture_output=True, text=True, env=os.environ.copy(), check=False)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_every_example_is_tested():
    tested = {"se2_pose_graph.py", "optimize_dataset.py", "landmarks_in_code.py"}
    assert {p.name for p in EXAMPLES.glob("*.py")} == tested


def test_se2_pose_graph(data_dir):
    if not (data_dir / "seeds" / "shanghaitech_slam2024_hw1").exists():
        pytest.skip("homework data absent")
    out = run("se2_pose_graph.py", data_dir)
    assert "APE rmse (m): dead reckoning 0.138007 -> optimised 0.048338" in out
    assert "chi2 0.02667689807 -> 0.004044419348 in 7 iterations" in out


def test_optimize_dataset(dataset, tmp_path):
    out = run("optimize_dataset.py", dataset("intel.g2o"), tmp_path / "out.g2o")
    assert re.search(r"converged: chi2 [0-9.e+]+ -> 45\.0046958", out), out
    assert "iter   1" in out and (tmp_path / "out.g2o").exists()


def test_landmarks_in_code():
    out = run("landmarks_in_code.py")
    m = re.search(r"landmark position error: max ([0-9.]+) m", out)
    assert m and float(m.group(1)) < 0.15, out  # from 0.5 m of initial noise
    assert "covariance of landmark 101" in out
