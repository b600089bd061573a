"""Paths, inputs and measures shared by the binding's tests; puts validation/ (its
convention mappings and ISOBI2 definition) on the import path."""

import os
import pathlib
import sys

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = pathlib.Path(os.environ.get("PSH_DATA_DIR", ROOT.parent / "shared" / "data")) / "polarsh"
sys.path.insert(0, str(ROOT / "validation"))


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
