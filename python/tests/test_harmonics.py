"""Bases at arrays of directions and Wigner blocks, against independent packages:
scipy's complex SH, sphericart's real SH, spherical's spin-weighted SH and Wigner D, and
scipy's rotations (conventions mapped as in validation/mappings.py)."""

import numpy as np
import pytest
import scipy.special
from scipy.spatial.transform import Rotation as SciRotation

import psh
from support import unit_directions  # also puts validation/ on the path
from mappings import lm_arrays, psh_D_from_spherical, real_D_from_complex, sphericart_sign

EPS = np.finfo(float).eps
# Errors are measured relative to the bound sqrt((2l+1)/4pi) of |Y_lm|, with the
# tolerance of the validation suite's real-SH row (docs/validation.md): 5e-14, above the
# 1.6e-14 psh's f64 recursions reach at l = 40-60 at the poles (a 40-digit value there
# shows psh 1.5e-14 off, the anchor 7e-16), below the l^2 eps of such recursions.
TOL = 5e-14


def scaled_error(got, ref, lmax):
    l, _ = lm_arrays(lmax)
    return np.max(np.abs(got - ref) / np.sqrt((2 * l + 1) / (4 * np.pi)))


def angles(d):
    return np.arctan2(np.hypot(d[:, 0], d[:, 1]), d[:, 2]), np.arctan2(d[:, 1], d[:, 0])


def test_sh_complex_against_scipy_and_mpmath():
    lmax = 60
    d = unit_directions(200, poles=False)
    theta, phi = angles(d)
    l, m = lm_arrays(lmax)
    ref = scipy.special.sph_harm_y(l[None, :], m[None, :], theta[:, None], phi[:, None])
    got = psh.sh_complex(lmax, d)
    assert got.shape == (len(d), (lmax + 1) ** 2) and got.dtype == np.complex128
    assert scaled_error(got, ref, lmax) < TOL
    # At and 1e-8 from the poles scipy rounds cos(theta) to 1 (an error of l^2 theta^2 / 4
    # relative): there the oracle is mpmath at 30 digits.
    mpmath = pytest.importorskip("mpmath")
    mpmath.mp.dps = 30
    pts = np.array([[0, 0, 1.0], [0, 0, -1.0], [np.sin(1e-8), 0, np.cos(1e-8)]])
    got = psh.sh_complex(lmax, pts)
    t, p = angles(pts)
    ref = np.array([[complex(mpmath.spherharm(int(a), int(b), mpmath.mpf(ti), mpmath.mpf(pi)))
                     for a, b in zip(l, m)] for ti, pi in zip(t, p)])
    assert scaled_error(got, ref, lmax) < TOL


def test_sh_real_against_sphericart():
    sphericart = pytest.importorskip("sphericart")
    d = unit_directions(300, seed=1)
    # Both kernels of the batch: Cartesian (lmax <= 24) and the Legendre lanes.
    for lmax in (4, 24, 40):
        ref = sphericart.SphericalHarmonics(lmax).compute(d) * sphericart_sign(lmax)
        got = psh.sh_real(lmax, d)
        assert scaled_error(got, ref, lmax) < TOL, lmax
    # Leading shapes are kept.
    assert psh.sh_real(3, d.reshape(2, -1, 3)).shape == (2, len(d) // 2, 16)


def test_swsh_against_spherical():
    spherical = pytest.importorskip("spherical")
    quaternionic = pytest.importorskip("quaternionic")
    lmax = 30
    d = unit_directions(40, seed=2)
    theta, phi = angles(d)
    w = spherical.Wigner(lmax, mp_max=3)
    for s in (-2, -1, 0, 1, 2, 3):
        got = psh.swsh(s, lmax, d)
        ref = np.array([w.sYlm(s, quaternionic.array.from_spherical_coordinates(t, p))
                        for t, p in zip(theta, phi)])
        assert scaled_error(got, ref, lmax) < TOL, s


def test_wigner_d_against_spherical():
    spherical = pytest.importorskip("spherical")
    quaternionic = pytest.importorskip("quaternionic")
    lmax = 25
    v = np.array([0.3, -1.1, 0.7])
    blocks = psh.wigner_d(psh.Rotation.from_rotvec(v), lmax)
    real = psh.wigner_d_real(psh.Rotation.from_rotvec(v), lmax)
    w = spherical.Wigner(lmax)
    dd = w.D(quaternionic.array.from_rotation_vector(v))
    for l in range(lmax + 1):
        ms = range(-l, l + 1)
        # spherical's D[Dindex(l, mp, m)] laid out with rows mp... (validation/mappings.py)
        ref = psh_D_from_spherical(np.array([[dd[w.Dindex(l, a, b)] for b in ms] for a in ms]))
        assert blocks[l].shape == (2 * l + 1, 2 * l + 1)
        assert np.max(np.abs(blocks[l] - ref)) < 100 * EPS, l
        assert np.max(np.abs(real[l] - real_D_from_complex(l, ref))) < 100 * EPS, l


def test_rotations_against_scipy():
    rng = np.random.default_rng(3)
    for q in rng.normal(size=(5, 4)):
        q /= np.linalg.norm(q)
        ref = SciRotation.from_quat(q)
        assert np.allclose(psh.Rotation.from_quaternion(q).matrix(), ref.as_matrix(), atol=1e-15)
        wxyz = np.roll(q, 1)
        assert np.allclose(psh.Rotation.from_quaternion(wxyz, scalar_first=True).matrix(),
                           ref.as_matrix(), atol=1e-15)
        v = ref.as_rotvec()
        assert np.allclose(psh.Rotation.from_rotvec(v).matrix(), ref.as_matrix(), atol=1e-14)
        a, b, g = ref.as_euler("ZYZ")
        assert np.allclose(psh.Rotation.from_euler_zyz(a, b, g).matrix(), ref.as_matrix(),
                           atol=1e-14)
        r = psh.Rotation.from_matrix(ref.as_matrix())
        assert np.allclose(r.matrix(), ref.as_matrix(), atol=1e-15)
        assert np.allclose((r * r.inverse()).matrix(), np.eye(3), atol=1e-15)
        assert np.allclose(psh.Rotation.from_euler_zyz(*r.euler_zyz()).matrix(),
                           ref.as_matrix(), atol=1e-14)
