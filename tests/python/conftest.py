# SPDX-License-Identifier: MIT
"""Fixtures of the Python package's tests (ctest label `python`).

Run by ctest with PYTHONPATH=build/python; GRAPHSLAM_DATA names the datasets folder (the
build's default when unset), GRAPHSLAM_TOOL the graphslam executable of the same build,
GRAPHSLAM_SOURCE_DIR the source tree (its test data and examples).
"""
import os
import pathlib
import subprocess

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("GRAPHSLAM_SOURCE_DIR",
                                         pathlib.Path(__file__).resolve().parents[2]))


def _data_dir():
    for name in ("GRAPHSLAM_DATA", "GRAPHSLAM_DEFAULT_DATA_DIR"):
        if os.environ.get(name):
            return pathlib.Path(os.environ[name])
    return SOURCE_DIR.parent / "shared" / "datasets"


@pytest.fixture(scope="session")
def data_dir():
    """The datasets folder; tests that need a file skip when it is absent."""
    return _data_dir()


@pytest.fixture(scope="session")
def test_data():
    """tests/data of the source tree (small fixtures: formats, .npz files)."""
    return SOURCE_DIR / "tests" / "data"


@pytest.fixture
def dataset(data_dir):
    """dataset("intel.g2o") -> path, skipping the test when the file is absent."""
    def get(name):
        path = data_dir / name
        if not path.exists():
            pytest.skip(f"{path} is absent (set GRAPHSLAM_DATA)")
        return path
    return get


@pytest.fixture(scope="session")
def tool():
    """Runs the graphslam executable of this build: tool("optimize", path) -> stdout."""
    exe = os.environ.get("GRAPHSLAM_TOOL")
    if not exe or not os.path.exists(exe):
        pytest.skip("GRAPHSLAM_TOOL (the graphslam executable) is not set")

    def run(*args):
        done = subprocess.run([exe, *map(str, args)], capture_output=True, text=True, check=False)
        assert done.returncode == 0, done.stderr
        return done.stdout
    return run
