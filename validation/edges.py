"""The inputs of the edge sweep (issue 48), shared by validation/test_edges.py,
python/tests/test_edges.py and validation/stability.py: rotations at and near the
identity and the half turns, polar angles at and near the poles."""

import numpy as np


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


# Rotation axes: z, two axes near z (the 1e-10,0,1e-8 is 1e-8 about the second),
# a tilted one and a horizontal one.
AXES = {
    "z": unit([0, 0, 1]),
    "near z (1e-6)": unit([1e-6, -2e-6, 1]),
    "near z (1e-2)": unit([1e-2, 0, 1]),
    "tilted": unit([1, -2, 3]),
    "horizontal": unit([np.cos(0.4), np.sin(0.4), 0]),
}
SMALL_ANGLES = [1e-15, 1e-12, 1e-8, 1e-4, 1e-2]
NEAR_PI = np.pi - 1e-12


def random_rotvecs(n, seed=48):
    """Rotation vectors of n random unit quaternions (uniform on SO(3))."""
    q = np.random.default_rng(seed).normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    q *= np.sign(q[:, :1])
    v = q[:, 1:]
    return [2 * np.arctan2(np.linalg.norm(u), w) * unit(u) for w, u in zip(q[:, 0], v)]


def rotation_groups():
    """{group: {name: rotation vector}}. psh's CLI takes a rotation vector and refuses
    0 (no axis): the identity is 1e-300 about the tilted axis (D = I to rounding; the exact
    identity goes through Python, python/tests/test_edges.py)."""
    groups = {"identity (1e-300)": {"1e-300 tilted": 1e-300 * AXES["tilted"]}}
    for kind, names in [("small, about z and near z", ["z", "near z (1e-6)", "near z (1e-2)"]),
                        ("small, tilted axis", ["tilted"]),
                        ("small, horizontal axis", ["horizontal"])]:
        groups[f"{kind} (1e-15..1e-2)"] = {
            f"{a:g} about {n}": a * AXES[n] for n in names for a in SMALL_ANGLES}
    groups["the issue's 1e-10,0,1e-8"] = {"1e-10,0,1e-8": np.array([1e-10, 0, 1e-8])}
    groups["pi - 1e-12"] = {f"pi - 1e-12 about {n}": NEAR_PI * a for n, a in AXES.items()}
    groups["random"] = {f"random {i}": v for i, v in enumerate(random_rotvecs(3))}
    return groups


# Polar angles of the sweep, each with its own azimuth: the poles (pi is the double
# nearest pi, 1.2e-16 from the south pole), 1e-300, 1e-12, 1e-8 and 1e-4 from the north
# pole, the equator and 1e-8 from the south pole.
POLAR = [(0.0, 0.4), (1e-300, 1.1), (1e-12, -0.7), (1e-8, 2.9), (1e-4, 0.3),
         (np.pi / 2, -2.5), (np.pi - 1e-8, 0.3), (np.pi, 2.0)]


