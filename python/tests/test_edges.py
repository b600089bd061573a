"""The edge sweep (issue 48) through Python: psh.sh_complex, psh.sh_real and psh.swsh at
and near the poles to l = 1024 (sh_complex to 4096), psh.wigner_d and wigner_d_real of
rotations at and near the identity and the half turns, against mpmath oracles, spherical
and the CLI (validation/oracles.py, validation/edges.py: the same inputs as
validation/test_edges.py).

The bound is the suite's 10 l eps: an SH value's error relative to its bound
sqrt((2l+1)/4pi), a Wigner entry's error absolute (entries of unitary blocks are at most
1), l = 0 counted as 1; the figures are error / (l eps), held below TOL = 10."""

import os
import pathlib
import subprocess

import numpy as np
import pytest

import psh
from support import ROOT  # also puts validation/ on the path
from edges import POLAR, rotation_groups
from mappings import lm_arrays, psh_D_from_spherical, real_D_from_complex, real_sh_from_complex

import mpmath  # noqa: E402  (python/tests/requirements.txt: a missing anchor fails)
import oracles  # noqa: E402  validation/oracles.py

EPS = np.finfo(float).eps
TOL = 10
SH_ORDERS = [0, 1, 2, 3, 4, 100, 512, 1024]


class Worst(dict):
    """The worst figure error / (l eps) per comparison; `check` asserts all below TOL
    (one message with every figure)."""

    def note(self, key, e):
        self[key] = max(self.get(key, 0.0), float(e))

    def check(self):
        assert max(self.values()) < TOL, {k: f"{v:.3g}" for k, v in self.items()}


def directions():
    """The unit vectors of POLAR, as doubles, and their exact angles (mp numbers): psh
    takes a direction, so the oracles are evaluated at the exact angles of the doubles."""
    d = np.array([[np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)] for t, p in POLAR])
    return d, [oracles.direction_angles(v) for v in d]


def sh_scale(lmax):
    l, _ = lm_arrays(lmax)
    return np.sqrt((2 * l + 1) / (4 * np.pi)) * np.maximum(l, 1) * EPS


def mp_sh(lmax, orders, theta, phi):
    """{flat index: Y_lm} for m = +-order, all l <= lmax (mpmath Legendre recursion at
    the exact angles)."""
    cols = oracles.pbar_orders(lmax, orders, theta)
    with mpmath.workdps(30):
        out = {}
        for m, col in cols.items():
            e = complex(mpmath.expj(m * phi))
            for l in range(m, lmax + 1):
                y = col[l] * e
                out[l * l + l + m] = y
                out[l * l + l - m] = (-1) ** m * np.conj(y)
    return out


def spherical_rotor(theta, phi):
    """quaternionic's rotor of the exact angles: the quaternion of Rz(phi) Ry(theta)
    rounded once (components to an ulp), not a rotor of rounded angles."""
    quaternionic = pytest.importorskip("quaternionic")
    with mpmath.workdps(40):
        q = oracles.quaternion_from_spherical(theta, phi)
        return quaternionic.array([float(c) for c in q])


def cli_values(*args):
    """The "values" of a psh CLI JSON answer, as an array (pairs as a last axis)."""
    binary = pathlib.Path(os.environ.get("PSH_BIN", ROOT / "target" / "release" / "psh"))
    if not binary.is_file():
        pytest.fail(f"no psh binary at {binary} (cargo build --release, or set PSH_BIN)")
    text = subprocess.run([str(binary), *map(str, args)], check=True, capture_output=True,
                          text=True).stdout
    # Parsed by numpy (json.loads of a million pairs takes seconds): the "values" array
    # of [re, im] pairs.
    start = text.index('"values":') + len('"values":')
    end = text.index("]]", start) + 2
    v = np.fromstring(text[start:end].translate(str.maketrans("[]", "  ")), sep=",")
    return v.reshape(-1, 2)


def test_sh_at_the_poles_l1024():
    """sh_complex and sh_real, l <= 1024, at the eight polar angles: against the mpmath
    recursion (SH_ORDERS), spherical (every l, m) and the CLI (psh eval sh, every l, m)."""
    spherical = pytest.importorskip("spherical")
    lmax = 1024
    d, angles = directions()
    scale = sh_scale(lmax)
    got = psh.sh_complex(lmax, d)
    got_r = psh.sh_real(lmax, d)
    w = spherical.Wigner(lmax, mp_max=0)
    worst = Worst()
    for k, (theta, phi) in enumerate(angles):
        exact = mp_sh(lmax, SH_ORDERS, theta, phi)
        i = np.array(list(exact))
        y = np.zeros((lmax + 1) ** 2, dtype=complex)
        y[i] = list(exact.values())
        worst.note("complex vs mpmath", (np.abs(got[k][i] - y[i]) / scale[i]).max())
        worst.note("real vs mpmath",
                   (np.abs(got_r[k][i] - real_sh_from_complex(y, lmax)[i]) / scale[i]).max())
        ref = w.sYlm(0, spherical_rotor(theta, phi))
        # spherical's own error is at most 1.2 l eps here (validation/test_edges.py).
        worst.note("complex vs spherical", (np.abs(got[k] - ref) / scale).max())
        worst.note("real vs spherical",
                   (np.abs(got_r[k] - real_sh_from_complex(ref, lmax)) / scale).max())
        # The CLI at the angles of the direction rounded to doubles: a rounding of theta
        # by at most ulp(pi)/2 moves Y_lm by at most l ulp(pi)/2 of the bound near a pole
        # (|d Y / d theta| <= l |Y| ~ l^2 theta there), 1e-3 l eps at 1e-8 from it, and by
        # 0.5 l eps at the equator: inside the bound.
        args = ["--lmax", lmax, "--theta", repr(float(theta)), "--phi", repr(float(phi))]
        cli = cli_values("eval", "sh", "--kind", "complex", *args)
        cli_r = cli_values("eval", "sh", "--kind", "real", *args)[:, 0]
        worst.note("complex vs CLI", (np.abs(got[k] - (cli[:, 0] + 1j * cli[:, 1])) / scale).max())
        worst.note("real vs CLI", (np.abs(got_r[k] - cli_r) / scale).max())
    worst.check()


def test_sh_at_the_poles_l4096():
    """sh_complex, l <= 4096, at the eight polar angles (one direction at a time: 16.8
    million values), against the mpmath recursion at SH_ORDERS + [2048, 4096], and at
    theta = 0 against the closed form delta_m0 sqrt((2l+1)/4pi) for every (l, m)."""
    lmax = 4096
    d, angles = directions()
    scale = sh_scale(lmax)
    l, m = lm_arrays(lmax)
    worst = Worst()
    for k, (theta, phi) in enumerate(angles):
        got = psh.sh_complex(lmax, d[k])
        exact = mp_sh(lmax, SH_ORDERS + [2048, 4096], theta, phi)
        i = np.array(list(exact))
        worst.note("vs mpmath", (np.abs(got[i] - np.array(list(exact.values()))) / scale[i]).max())
        if POLAR[k][0] == 0.0:
            closed = np.where(m == 0, np.sqrt((2 * l + 1) / (4 * np.pi)), 0.0)
            worst.note("theta = 0 vs closed form", (np.abs(got - closed) / scale).max())
    worst.check()


def test_swsh_at_the_poles_l1024():
    """swsh, s = -3..3, l <= 1024, at the eight polar angles: against spherical (every l,
    m), the mpmath oracle at l = 1024 (m in {0, +-1, +-s, +-l}), and the CLI for s = 2
    at 1e-8 from both poles (psh eval swsh, l^3 per direction)."""
    spherical = pytest.importorskip("spherical")
    lmax = 1024
    d, angles = directions()
    scale = sh_scale(lmax)
    w = spherical.Wigner(lmax, mp_max=3)
    rotors = [spherical_rotor(t, p) for t, p in angles]
    worst = Worst()
    for s in range(-3, 4):
        got = psh.swsh(s, lmax, d)
        ms = sorted({0, 1, -1, s, -s, lmax, -lmax})
        i = np.array([lmax * lmax + lmax + m for m in ms])
        for k, (theta, phi) in enumerate(angles):
            # spherical's own error is at most 2.8 l eps (validation/test_edges.py).
            worst.note("vs spherical", (np.abs(got[k] - w.sYlm(s, rotors[k])) / scale).max())
            exact = oracles.swsh(s, lmax, ms, theta, phi)
            worst.note("vs mpmath", (np.abs(got[k][i] - exact) / scale[i]).max())
        if s == 2:
            for k in [3, 6]:  # 1e-8 from the north and the south pole
                theta, phi = angles[k]
                cli = cli_values("eval", "swsh", "--spin", s, "--lmax", lmax,
                                 "--theta", repr(float(theta)), "--phi", repr(float(phi)))
                worst.note("s = 2 vs CLI",
                           (np.abs(got[k] - (cli[:, 0] + 1j * cli[:, 1])) / scale).max())
    worst.check()


def rotation_cases():
    """(name, psh.Rotation, rotation) of the sweep's rotations: each through from_rotvec
    (rotation: the rotation vector) and from_quaternion (rotation: the quaternion
    (w, x, y, z) of doubles, whose exact rotation is that of the normalized quaternion),
    and the exact identity (from_rotvec of 0)."""
    cases = [("identity", psh.Rotation.from_rotvec([0.0, 0.0, 0.0]), np.zeros(3))]
    for group in rotation_groups().values():
        for name, v in group.items():
            v = np.asarray(v)
            cases.append((f"{name} (rotvec)", psh.Rotation.from_rotvec(v), v))
            big = np.abs(v).max()
            t = big * np.linalg.norm(v / big)  # no underflow at |v| = 1e-300
            q = np.array([np.cos(t / 2), *(np.sin(t / 2) / t * v)])
            cases.append((f"{name} (quaternion)",
                          psh.Rotation.from_quaternion(q, scalar_first=True), q))
    return cases


def spherical_rotation(rotation):
    quaternionic = pytest.importorskip("quaternionic")
    if len(rotation) == 3:
        return quaternionic.array.from_rotation_vector(rotation)
    return quaternionic.array(rotation).normalized


def mp_entries(l):
    """Corners, centre and a few other entries of block l (as validation/test_edges.py)."""
    e = [(l, l), (-l, -l), (l, l - 1), (l - 1, l), (l, -l), (-l, l), (l, 0), (0, l), (0, 0),
         (1, 1), (1, -1), (l // 2, l // 2), (l // 3, -(l // 5))]
    return sorted({(a, b) for a, b in e if abs(a) <= l and abs(b) <= l})


@pytest.mark.parametrize("lmax", [40, 200])
def test_wigner_d_edges(lmax):
    """wigner_d and wigner_d_real of every rotation of the sweep (l <= 40) or of five of
    them (l <= 200, all blocks: 10.8 million entries), through from_rotvec and
    from_quaternion, against spherical (every entry) and the mpmath oracle (Wigner's sum
    in R_a, R_b of the exact quaternion) at entries of blocks 1, 2 and lmax."""
    spherical = pytest.importorskip("spherical")
    w = spherical.Wigner(lmax)
    cases = rotation_cases()
    if lmax > 40:
        keep = ["identity", "1e-10,0,1e-8 (rotvec)", "1e-12 about tilted (rotvec)",
                "1e-15 about near z (1e-6) (quaternion)", "pi - 1e-12 about horizontal (rotvec)"]
        cases = [c for c in cases if c[0] in keep]
    worst = Worst()
    for name, rot, rotation in cases:
        blocks = psh.wigner_d(rot, lmax)
        real = psh.wigner_d_real(rot, lmax)
        D = w.D(spherical_rotation(rotation))
        for l in range(lmax + 1):
            n = 2 * l + 1
            i0 = w.Dindex(l, -l, -l)
            ref = psh_D_from_spherical(D[i0:i0 + n * n].reshape(n, n))
            scale = max(l, 1) * EPS
            # spherical's own error is at most 4.6 l eps (turns of 1e-15, whose phase it
            # drops; validation/test_edges.py).
            worst.note("complex vs spherical", np.abs(blocks[l] - ref).max() / scale)
            worst.note("real vs spherical",
                       np.abs(real[l] - real_D_from_complex(l, ref).real).max() / scale)
            if l in (1, 2, lmax):
                ent = mp_entries(l)
                idx = tuple(np.array([(a + l, b + l) for a, b in ent]).T)
                exact = oracles.wigner_D(l, ent, rotation)
                exact_r = oracles.wigner_D_real(l, ent, rotation)
                worst.note("complex vs mpmath", np.abs(blocks[l][idx] - exact).max() / scale)
                worst.note("real vs mpmath", np.abs(real[l][idx] - exact_r).max() / scale)
            if name == "identity":
                # Exactly the identity: D = I to rounding.
                worst.note("identity vs I", np.abs(blocks[l] - np.eye(n)).max() / scale)
                worst.note("identity vs I (real)", np.abs(real[l] - np.eye(n)).max() / scale)
    worst.check()
