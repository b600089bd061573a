"""Paths, inputs and measures shared by the binding's tests; puts validation/ (its
convention mappings and ISOBI2 definition) on the import path."""

import os
import pathlib
import struct
import sys

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = pathlib.Path(os.environ.get("PSH_DATA_DIR", ROOT.parent / "shared" / "data")) / "polarsh"
sys.path.insert(0, str(ROOT / "validation"))
# Wall-clock bounds are multiplied by this (set it on an emulated CPU, e.g. 30 under qemu).
TIME_SCALE = float(os.environ.get("PSH_TEST_TIME_SCALE", "1"))


def unit_directions(n, seed=0, poles=True):
    """n random unit directions, with the poles and a seam point appended."""
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    if poles:
        d = np.vstack([d, [[0, 0, 1.0], [0, 0, -1.0], [-1.0, 0, 0], [np.sin(1e-8), 0, np.cos(1e-8)]]])
    return d


def rel(a, b):
    """Relative max-norm difference."""
    return np.max(np.abs(np.asarray(a) - np.asarray(b))) / max(np.max(np.abs(b)), 1e-300)


def write_tensor_file(path, fields):
    """Mitsuba's TensorFile layout (src/core/tensor.cpp), little-endian."""
    codes = {np.dtype("uint16"): 3, np.dtype("float32"): 10}
    head = b"tensor_file\0" + bytes([1, 0]) + struct.pack("<I", len(fields))
    size = len(head) + sum(2 + len(n) + 2 + 1 + 8 + 8 * a.ndim for n, a in fields)
    offsets = []
    for _, a in fields:
        size = (size + 7) // 8 * 8
        offsets.append(size)
        size += a.nbytes
    out = bytearray(head)
    for (name, a), offset in zip(fields, offsets):
        out += struct.pack("<H", len(name)) + name.encode()
        out += struct.pack("<HBQ", a.ndim, codes[a.dtype], offset)
        out += b"".join(struct.pack("<Q", d) for d in a.shape)
    for (_, a), offset in zip(fields, offsets):
        out += b"\0" * (offset - len(out))
        out += np.ascontiguousarray(a).astype(a.dtype.newbyteorder("<")).tobytes()
    path.write_bytes(bytes(out))
