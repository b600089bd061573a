"""Measured pBRDF tables from Python: a Mitsuba 3 `.pbsdf` written here by an independent
writer of Mitsuba's TensorFile layout (magic, version, per-field header, 8-byte aligned
data), read by psh and projected; a constant depolarizing table against the closed form
of its projection."""

import math

import numpy as np
import pytest

import psh
from support import write_tensor_file


def constant_table(path, c, bands=(450, 500, 550, 600, 650)):
    """f = diag(c, 0, 0, 0) everywhere: P = c cos(theta_i), a depolarizing Lambertian."""
    phi = np.linspace(-np.pi, np.pi, 13, dtype=np.float32)
    theta = np.linspace(0, np.pi / 2, 7, dtype=np.float32)
    m = np.zeros((13, 7, 7, len(bands), 4, 4), dtype=np.float32)
    m[..., 0, 0] = c
    write_tensor_file(path, [
        ("phi_d", phi[None, :]), ("theta_d", theta[None, :]), ("theta_h", theta[None, :]),
        ("wvls", np.array(bands, dtype=np.uint16)), ("M", m),
    ])


def test_a_constant_table_projects_to_its_closed_form(tmp_path):
    path = tmp_path / "lambert.pbsdf"
    c = 0.25
    constant_table(path, c)
    t = psh.read_measured_pbrdf(path)
    assert t.shape == (13, 7, 7)
    assert t.wavelengths == [450.0, 500.0, 550.0, 600.0, 650.0]
    assert t.invalid_fraction == 0.0
    # An even number of Gauss-Legendre rings (24): none on the horizon, whose step the
    # quadrature then splits exactly (a ring on it, with grid_lmax = 24, counts the whole
    # ring and gives 6% more).
    m = t.to_rgb().project(2, grid_lmax=23)
    assert m.channels == 3
    # M_{00,00} = int int Y_00 c cos(theta_i) Y_00 over both upper hemispheres
    # = c pi 2 pi / (4 pi) = c pi / 2 (PSH (40)); measured 1.4e-3 relative at 24 rings,
    # 3.5e-4 at 48 (the quadrature of cos(theta_i) over a half sphere).
    want = c * math.pi / 2
    for ch in range(3):
        m00 = m.to_dense(ch).data[0, 0, 0, 0]
        assert abs(m00 / want - 1) < 3e-3, m00


def test_bad_tables_raise(tmp_path):
    path = tmp_path / "t.pbsdf"
    constant_table(path, 0.1, bands=(500, 600))
    with pytest.raises(ValueError, match="KAIST bands"):
        psh.read_measured_pbrdf(path).to_rgb()
    raw = path.read_bytes()
    (tmp_path / "cut.pbsdf").write_bytes(raw[: len(raw) // 2])
    with pytest.raises(OSError, match="cut.pbsdf"):
        psh.read_measured_pbrdf(tmp_path / "cut.pbsdf")
