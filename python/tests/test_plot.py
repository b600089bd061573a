"""psh.plot: the quantities it draws are the textbook ones (Malus's law, DoLP, AoLP), the
glyphs point along the polarization, and every panel is labelled."""

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import psh.plot  # noqa: E402


def test_derived_quantities_are_the_textbook_ones():
    s = np.array([2.0, 0.6, 0.8, 0.1])
    assert np.isclose(psh.plot.dolp(s), 0.5)
    assert np.isclose(psh.plot.aolp_deg(s), np.degrees(0.5 * np.arctan2(0.8, 0.6)))
    # Malus: light polarized at 30 degrees through a polarizer at a: cos^2(a - 30).
    full = np.array([1.0, np.cos(np.radians(60)), np.sin(np.radians(60)), 0.0])
    for a in (0.0, 30.0, 75.0, 120.0):
        assert np.isclose(psh.plot.through_polarizer(full, a), np.cos(np.radians(a - 30)) ** 2)


def test_stokes_image_panels_and_values():
    h, w = 12, 16
    img = np.zeros((h, w, 3, 4))
    img[..., 0] = 1.0
    img[..., 1] = 0.5  # horizontal linear polarization, DoLP 0.5
    fig, panels = psh.plot.stokes_image(img, title="t")
    assert [p.get_title() for p in panels] == [
        "s0 (R, G, B)", "DoLP", "AoLP", "polarizer 0 deg", "polarizer 45 deg",
        "polarizer 90 deg", "polarizer 135 deg"]
    assert np.allclose(panels[1].images[0].get_array(), 0.5)
    assert np.allclose(panels[2].images[0].get_array(), 0.0)
    # Behind the polarizers: (1 + 0.5 cos 2a) / 2 on s0's tone scale (white = 1).
    for panel, a in zip(panels[3:], (0, 45, 90, 135)):
        want = (0.5 * (1 + 0.5 * np.cos(np.radians(2 * a)))) ** (1 / 2.2)
        assert np.allclose(panel.images[0].get_array(), want)
    # An image without light (s0 <= 0, or NaN) draws on the scale of 1, not of its own
    # non-positive or NaN percentile.
    for dark in (np.full((4, 4, 4), -1.0), np.full((4, 4, 4), np.nan)):
        fig, panels = psh.plot.stokes_image(dark)
        assert panels[0].images[0].get_clim() == (0, 1.0)
    with pytest.raises(ValueError, match="shape"):
        psh.plot.stokes_image(np.zeros((4, 4, 2)))
    matplotlib.pyplot.close("all")


def test_sphere_glyphs_follow_the_polarization():
    # Light polarized along world x everywhere near +z: at the zenith the theta-phi frame
    # is x = e_theta = (1, 0, 0) (phi = 0), so s1 > 0, s2 = 0 there; the glyph through
    # the centre must lie along the screen's x axis.
    coeffs = np.zeros((1, 9, 4))
    coeffs[0, 0, 0] = 1.0
    v = psh.PshVector(coeffs)
    z = v.evaluate([[0.0, 0.0, 1.0]])
    assert z[0, 0, 1] == 0.0  # no polarization: no glyph length
    fig, ax = psh.plot.sphere(v, glyphs=3)
    lengths = [np.ptp(line.get_xdata()) + np.ptp(line.get_ydata()) for line in ax.lines]
    assert max(lengths) == 0.0
    # A spin-2 field of degree 2 polarized along x at the zenith.
    h = 64
    theta = (np.arange(h) + 0.5) / h * np.pi
    phi = (np.arange(2 * h) + 0.5) / (2 * h) * 2 * np.pi
    t, p = np.meshgrid(theta, phi, indexing="ij")
    a = np.array([1.0, 0.0, 0.0])
    e_t = np.stack([np.cos(t) * np.cos(p), np.cos(t) * np.sin(p), -np.sin(t)], -1)
    e_p = np.stack([-np.sin(p), np.cos(p), np.zeros_like(p)], -1)
    zz = (e_t @ a + 1j * (e_p @ a)) ** 2
    texels = np.zeros((1, h, 2 * h, 4))
    texels[0, ..., 0] = 1.0
    texels[0, ..., 1] = zz.real
    texels[0, ..., 2] = zz.imag
    fig, ax = psh.plot.sphere(psh.project_map(texels, 4), glyphs=3)
    centre = [ln for ln in ax.lines if np.allclose(np.mean(ln.get_xdata()), 0, atol=1e-9)
              and np.allclose(np.mean(ln.get_ydata()), 0, atol=1e-9)]
    (line,) = centre
    dx, dy = np.ptp(line.get_xdata()), np.ptp(line.get_ydata())
    assert dx > 0.1 and dy < 1e-2 * dx
    assert ax.get_title()
    matplotlib.pyplot.close("all")


def test_coefficient_and_matrix_plots_are_labelled():
    v = psh.PshVector(np.random.default_rng(1).normal(size=(1, 16, 1)), codomain="SCALAR")
    fig, axes = psh.plot.coefficients(v)
    assert axes[0, 0].get_title() == "s0" and axes[0, 0].get_xlabel() == "m"
    assert all(float(t).is_integer() for t in axes[0, 0].get_xticks())
    m = psh.project_pbrdf(psh.Conductor(0.4, material="gold"), 3)
    fig, axes = psh.plot.matrix(m)
    assert [a.get_title() for a in axes.flat] == [
        "spin 0 <- 0", "spin 0 <- 2", "spin 2 <- 0", "spin 2 <- 2"]
    # Spin-2 rows and columns of degrees 0 and 1 do not exist (PSH (31)): floor there.
    spin22 = axes[1, 1].images[0].get_array()
    assert np.all(spin22[:2, :] == -12) and np.all(spin22[2:, 2:] > -12)
    matplotlib.pyplot.close("all")
