"""Polarized convolution: kernels from tables, callables and files, their coefficients
against the closed forms of PSH (68a)-(68e) for kernels h(theta) I (scipy quadrature of
Legendre and Jacobi polynomials), and equality with `psh convolve`."""

import numpy as np
import pytest
import scipy.special

import psh
from support import rel
from test_vector import random_vector


def h(t):
    return np.exp(np.cos(t))


def closed_forms(lmax):
    """For k = h(theta) I: s0, s3 scale by 2 pi int P_l h sin (Funk-Hecke, PSH (11)); the
    spin-2 pair by 2 pi int d^l_{22} h sin, d^l_{22}(theta) = cos^4(theta/2)
    P^{(0,4)}_{l-2}(cos theta) (Wigner small d of equal orders as a Jacobi polynomial)."""
    # In x = cos(theta) the integrands are polynomials times exp(x): Gauss-Legendre with
    # 80 nodes is exact to rounding.
    x, wts = scipy.special.roots_legendre(80)

    def integral(f):
        return 2 * np.pi * np.sum(wts * f(x) * np.exp(x))

    lam = [integral(lambda x, l=l: scipy.special.eval_legendre(l, x)) for l in range(lmax + 1)]
    mu = [0.0, 0.0] + [integral(lambda x, l=l: ((1 + x) / 2) ** 2
                                * scipy.special.eval_jacobi(l - 2, 0, 4, x))
                       for l in range(2, lmax + 1)]
    return np.array(lam), np.array(mu)


def test_coefficients_are_the_closed_forms():
    lmax = 12
    lam, mu = closed_forms(lmax)
    kernel = psh.ConvolutionKernel.from_callable(lambda t: h(t) * np.eye(4))
    g = kernel.coefficients(lmax)
    assert g.lmax == lmax and g.error_estimate < 1e-12
    v = random_vector(lmax, channels=2, seed=20)
    out = g.convolve(v).coeffs
    l = np.floor(np.sqrt(np.arange((lmax + 1) ** 2))).astype(int)
    expected = v.coeffs * np.stack([lam[l], mu[l], mu[l], lam[l]], axis=-1)[None]
    assert rel(out, expected) < 1e-12
    # The real forms are diagonal with these entries.
    rf = g.real_form()
    assert rf.shape == (lmax + 1, 4, 4)
    assert rel(np.diagonal(rf, axis1=1, axis2=2), np.stack([lam, mu, mu, lam], axis=-1)) < 1e-12


def test_table_callable_and_file_agree(tmp_path):
    theta = np.linspace(0, np.pi, 2001)
    values = h(theta)[:, None, None] * np.eye(4)
    table = psh.ConvolutionKernel.from_table(theta, values)
    callable_ = psh.ConvolutionKernel.from_callable(lambda t: h(t) * np.eye(4))
    assert rel(table.value(0.3), callable_.value(0.3)) < 1e-6
    np.savetxt(tmp_path / "k.csv", np.column_stack([theta, values.reshape(len(theta), 16)]),
               delimiter=",")
    from_file = psh.ConvolutionKernel.read_csv(tmp_path / "k.csv")
    a = table.coefficients(8).real_form()
    assert np.array_equal(a, from_file.coefficients(8).real_form())
    # Linear interpolation of a smooth kernel: O(step^2) ~ 1e-7 of the coefficients.
    assert rel(a, callable_.coefficients(8).real_form()) < 1e-6


def test_synthesis_inverts_the_coefficients():
    g = psh.ConvolutionKernel.from_callable(lambda t: h(t) * np.eye(4)).coefficients(30)
    back = psh.KernelCoefficients.from_real_form(g.real_form())
    assert np.array_equal(back.real_form(), g.real_form())
    # exp(cos theta) is entire: its s0 entry is recovered to rounding at l = 30.
    assert abs(g.synthesize(0.7)[0, 0] - h(0.7)) < 1e-12


def test_callable_errors_are_raised():
    def boom(t):
        raise ZeroDivisionError("kernel failed")

    with pytest.raises(ZeroDivisionError, match="kernel failed"):
        psh.ConvolutionKernel.from_callable(boom).coefficients(4)
    with pytest.raises(ValueError, match="4, 4"):
        psh.ConvolutionKernel.from_callable(lambda t: np.eye(3)).coefficients(4)
    with pytest.raises(ValueError):
        psh.ConvolutionKernel.from_callable(lambda t: np.full((4, 4), np.nan)).coefficients(4)


def test_linear_zenith_equals_the_command_line(cli, tmp_path):
    v = random_vector(10, channels=3, seed=21).converted("travel")
    v.write_npz(tmp_path / "in.npz")
    cli("convolve", "--kernel", "linear-zenith", "-o", "out.npz", "in.npz")
    ref = psh.PshVector.read_npz(tmp_path / "out.npz")
    got = psh.ConvolutionKernel.linear_zenith().coefficients(10).convolve(
        psh.PshVector.read_npz(tmp_path / "in.npz"))
    assert np.array_equal(got.coeffs, ref.coeffs)
