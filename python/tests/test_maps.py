"""Stokes maps: EXR files, projection PSH (32) and reconstruction PSH (30) on cube crosses,
equirectangular maps and perspective images, against the command line and the analytic
sky of a band-limited field."""

import numpy as np
import pytest

import psh
from support import rel
from test_vector import random_vector


def test_projection_equals_the_command_line(cli, data, tmp_path):
    texels = psh.read_stokes_map(data / "sponza_64_s%d.exr")
    assert texels.shape == (3, 192, 256, 4)
    got = psh.project_map(texels, 12)
    cli("project", data / "sponza_64_s%d.exr", "--lmax", 12, "-o", "p.npz")
    ref = psh.PshVector.read_npz(tmp_path / "p.npz")
    # The command writes polarsh's travel convention; the map is indexed towards the source.
    assert got.argument == "towards-source" and ref.argument == "travel"
    assert np.array_equal(got.converted("travel").coeffs, ref.coeffs)


def test_reconstruct_then_project_recovers_a_band_limited_field():
    """A band-limited field sampled on a fine equirect map and projected back: the texel
    quadrature's error shrinks with the texel size (here below 2e-3 of the coefficients)."""
    v = random_vector(4, channels=1, seed=11)
    eq = psh.reconstruct_map(v, 256, 512)
    assert eq.shape == (1, 256, 512, 4)
    back = psh.project_map(eq, 4)
    assert rel(back.coeffs, v.coeffs) < 2e-3
    cube = psh.reconstruct_map(v, 3 * 96, 4 * 96)
    assert rel(psh.project_map(cube, 4).coeffs, v.coeffs) < 2e-3


def test_reconstruction_is_evaluation_in_the_layout_frames():
    """Texel (row, column) of an H x 2H map is centred at theta = pi (row + 1/2) / H,
    phi = 2 pi (column + 1/2) / W (docs/conventions.md), components in the theta-phi frames;
    a cube cross's texels in the cube-map frame field."""
    v = random_vector(6, channels=2, seed=12)
    h, w = 16, 32
    eq = psh.reconstruct_map(v, h, w)
    theta = np.pi * (np.arange(h) + 0.5) / h
    phi = 2 * np.pi * (np.arange(w) + 0.5) / w
    t, p = np.meshgrid(theta, phi, indexing="ij")
    d = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1)
    assert rel(eq, v.evaluate(d)) < 1e-13
    e = 8
    cube = psh.reconstruct_map(v, 3 * e, 4 * e)
    # The Front face (row 1, column 1 of the cross) is a 90-degree camera looking along
    # +y, image-right +x, image-up +z (docs/conventions.md).
    u = 2 * (np.arange(e) + 0.5) / e - 1
    uu, vv = np.meshgrid(u, u, indexing="xy")  # column, row
    d = np.stack([uu, np.ones_like(uu), -vv], axis=-1)
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    front = cube[:, e:2 * e, e:2 * e]
    assert rel(front, v.evaluate(d, psh.FrameField.cube_map())) < 1e-13
    # Off the cross the texels are zero.
    assert not cube[:, :8, :8].any()


def test_perspective_view_is_evaluation_in_camera_frames():
    v = random_vector(5, channels=1, seed=13)
    fwd, up, fov = np.array([0.0, 1.0, 0.0]), np.array([0.0, 0.0, 1.0]), 0.9
    img = psh.reconstruct_perspective(v, fwd, up, fov, 8, 6)
    assert img.shape == (1, 6, 8, 4)
    # The centre ray of an even-sized image is between pixels; the pixel (i, j) direction
    # of a pinhole camera: x right, y down, z forward, tan(fov/2) at the top edge.
    t = np.tan(fov / 2)
    right = np.cross(fwd, up)
    field = psh.FrameField.perspective(fwd, up)
    for j in range(6):
        for i in range(8):
            x = (2 * (i + 0.5) / 8 - 1) * t * 8 / 6
            y = (2 * (j + 0.5) / 6 - 1) * t
            d = fwd + x * right - y * up
            d /= np.linalg.norm(d)
            assert np.allclose(img[0, j, i], v.evaluate(d[None], field)[0, 0], atol=1e-12)
    with pytest.raises(ValueError, match="travel"):
        psh.reconstruct_perspective(v.converted("travel"), fwd, up, fov, 8, 6)


def test_exr_round_trip(tmp_path):
    v = random_vector(3, channels=3, seed=14)
    m = psh.reconstruct_map(v, 24, 32)
    paths = psh.write_stokes_map(m, tmp_path / "m_s%d.exr")
    assert len(paths) == 4
    back = psh.read_stokes_map(tmp_path / "m_s%d.exr")
    # EXR stores float32 (or half); relative to the field's size.
    assert rel(back, m) < 1e-6
