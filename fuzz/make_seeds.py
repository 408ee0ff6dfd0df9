#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Writes OUT/<harness>/ seed corpora from tests/data and a few lines in each reader's format.

Each harness reads its first byte as a mode (see fuzz_*.cpp), so every seed is written once
per mode of interest. fuzz/CMakeLists.txt runs it at configure time: make_seeds.py OUT
"""
import pathlib
import shutil
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
DATA = ROOT / "tests" / "data"
SEEDS = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "fuzz" / "seeds"


def write(harness, name, mode, body):
    folder = SEEDS / harness
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"{name}.{mode:02x}").write_bytes(bytes([mode]) + body)


def main():
    shutil.rmtree(SEEDS, ignore_errors=True)
    slam3d = (b"VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\nFIX 0\n"
              b"EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n")
    g2o = {p.stem: p.read_bytes() for p in sorted(DATA.rglob("*.g2o"))}
    g2o["slam3d"] = slam3d
    for name, body in g2o.items():
        for mode in (0x00, 0x13, 0x0c):  # strict; 2 threads, lenient, 7-byte chunks; created, repaired
            write("g2o", name, mode, body)
    tum = b"# t x y z qx qy qz qw\n0 0 0 0 0 0 0 1\n1.5 1 0 0 0 0 0.0998 0.995\n2 2 1 0 0 0 0 1"
    kitti = b"1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n"
    matrix = b"1 1 1 0\n0 0 0 -2\n0 1.5708 0 0\n"
    write("trajectory", "tum", 0, tum)
    write("trajectory", "kitti", 1, kitti)
    write("trajectory", "matrix", 2, matrix)
    write("npz", "single", 0, (DATA / "npz" / "single.npy").read_bytes())
    for p in sorted((DATA / "npz").glob("*.npz")):
        for mode in (1, 3):  # automatic model; linear
            write("npz", p.stem, mode, p.read_bytes())
    scenario = b"0 0 0|10 0\n20 5\n30 -5\n|5 5\n7 8 1\n-3 4\n"
    (SEEDS / "scenario").mkdir(parents=True, exist_ok=True)
    (SEEDS / "scenario" / "square").write_bytes(scenario)
    for p in sorted((DATA / "formats").iterdir()):
        for mode in (0x00, 0x01, 0x02, 0x04):  # detected; TORO; iSAM; detected, 2 threads
            write("formats", p.stem, mode, p.read_bytes())

    # The pipe harness takes whole files (no mode byte): every graph format the registry
    # detects, among them files larger than a pipe's 64 KiB.
    (SEEDS / "pipe").mkdir(parents=True, exist_ok=True)
    sources = sorted(DATA.rglob("*.g2o")) + sorted((DATA / "formats").iterdir()) + \
        sorted((DATA / "npz").glob("*.npz"))
    for p in sources:
        (SEEDS / "pipe" / f"{p.parent.name}_{p.name}").write_bytes(p.read_bytes())


if __name__ == "__main__":
    main()
