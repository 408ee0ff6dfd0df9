#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Writes the tiny .npz/.npy fixtures of the NumPy reader tests (run once with
/usr/bin/python3 and numpy; the outputs are committed). Values are chosen so that every
element is distinct: a[i, j] = 10 * i + j + 0.5, t[i, j, k] = 100 * i + 10 * j + k."""
import io
import zipfile

import numpy as np

a = np.array([[0.5, 1.5, 2.5], [10.5, 11.5, 12.5]])  # (2, 3)
t = np.arange(2 * 3 * 4).reshape(2, 3, 4)
t = (100 * (t // 12) + 10 * ((t // 4) % 3) + t % 4).astype("<i8")

arrays = {
    "c_f8": a,
    "fortran_f8": np.asfortranarray(a),
    "fortran_i8_3d": np.asfortranarray(t),
    "c_i8_3d": t,
    "big_f8": a.astype(">f8"),
    "f4": a.astype("<f4"),
    "i4": np.array([-3, 0, 7, 2147483647], dtype="<i4"),
    "i2": np.array([-300, 5], dtype="<i2"),
    "i1": np.array([-128, 127], dtype="i1"),
    "u1": np.array([0, 255], dtype="u1"),
    "u2": np.array([65535], dtype=">u2"),
    "u8": np.array([2**53], dtype="<u8"),
    "bool": np.array([True, False, True]),
    "scalar": np.float64(3.25),
    "empty": np.zeros((0, 2)),
    "text": np.array("abc"),  # '<U3': not numeric
}
np.savez("arrays.npz", **arrays)
np.savez_compressed("arrays_compressed.npz", c_f8=a, fortran_f8=np.asfortranarray(a))
np.save("single.npy", np.asfortranarray(a))


def npy(array, version=(1, 0)):
    buf = io.BytesIO()
    np.lib.format.write_array(buf, array, version=version)
    return buf.getvalue()


good = npy(a)
header_end = good.index(b"\n") + 1
bad = {
    "v2": npy(a, (2, 0)),
    "v3": npy(a, (3, 0)),
    "bad_magic": b"\x93NUMPZ" + good[6:],
    "version9": good[:6] + b"\x09\x00" + good[8:],
    "short_data": good[:-8],
    "long_data": good + b"\x00" * 8,
    "short_header": good[:20],
    "bad_header": good[:10] + good[10:header_end].replace(b"'shape': (2, 3)", b"'shape': [2, 3]"),
    "unknown_key": good[:10] + good[10:header_end].replace(b"'fortran_order'", b"'fortran_ordr' "),
    "structured": npy(np.zeros(2, dtype=[("x", "<f8"), ("y", "<f8")])),
    "complex": npy(np.zeros(2, dtype="<c16")),
    "f2": npy(np.zeros(2, dtype="<f2")),
    "object": good.replace(b"'<f8'", b"'|O' ", 1),  # header of an object (pickled) array
    "i8_too_big": npy(np.array([2**53 + 1], dtype="<i8")),
}
with zipfile.ZipFile("members.npz", "w", zipfile.ZIP_STORED) as z:
    for name, data in bad.items():
        z.writestr(name + ".npy", data)

# Archive-level corruption: a flipped data byte under a stored and a deflated member
# (CRC mismatch), a cut-off archive, and something that is not a zip file at all.
raw = open("arrays_compressed.npz", "rb").read()
with zipfile.ZipFile("bad_crc_stored.npz", "w", zipfile.ZIP_STORED) as z:
    z.writestr("c_f8.npy", good)
stored = bytearray(open("bad_crc_stored.npz", "rb").read())
stored[stored.index(good) + len(good) - 3] ^= 0x40
open("bad_crc_stored.npz", "wb").write(bytes(stored))
with zipfile.ZipFile("bad_crc_deflated.npz", "w", zipfile.ZIP_DEFLATED) as z:
    z.writestr("c_f8.npy", good * 4)
deflated = bytearray(open("bad_crc_deflated.npz", "rb").read())
deflated[60] ^= 0x01
open("bad_crc_deflated.npz", "wb").write(bytes(deflated))
open("truncated.npz", "wb").write(raw[: len(raw) // 2])
open("not_a_zip.npz", "wb").write(b"this is not a zip archive\n" * 4)

# Small homework-format files (CMU 16-833 HW3 keys), noise free: 3 poses, 2 landmarks.
gt_traj = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.5]])
gt_lm = np.array([[1.0, 2.0], [3.0, -1.0]])
odom = np.diff(gt_traj, axis=0)
pairs = [(0, 0), (1, 0), (1, 1), (2, 1), (2, 0)]


def observations(bearing_range):
    rows = []
    for p, l in pairs:
        d = gt_lm[l] - gt_traj[p]
        m = (np.arctan2(d[1], d[0]), np.hypot(d[0], d[1])) if bearing_range else d
        rows.append([p, l, m[0], m[1]])
    return np.asfortranarray(np.array(rows))


def homework(name, bearing_range=False, **changes):
    arrays = dict(gt_traj=gt_traj, gt_landmarks=gt_lm, odom=odom,
                  observations=observations(bearing_range),
                  sigma_odom=np.diag([0.01, 0.01]), sigma_landmark=np.diag([0.04, 0.04]))
    arrays.update(changes)
    np.savez(name, **{k: v for k, v in arrays.items() if v is not None})


homework("hw_linear.npz")
homework("hw_bearing_range.npz", bearing_range=True)
obs = observations(False)
homework("hw_no_truth_nonlinear.npz", True, gt_traj=None, gt_landmarks=None)
bad = obs.copy(); bad[3, 0] = 1.5
homework("hw_fractional_index.npz", observations=bad)
bad = obs.copy(); bad[4, 1] = 2
homework("hw_index_out_of_range.npz", observations=bad)
bad = obs.copy(); bad[2, 3] = np.nan
homework("hw_nan.npz", observations=bad)
homework("hw_sigma_not_pd.npz", sigma_odom=np.array([[1.0, 2.0], [2.0, 1.0]]))
homework("hw_missing_odom.npz", odom=None)
homework("hw_bad_shape.npz", observations=obs[:, :3])
