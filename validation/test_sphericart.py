"""psh's real SH, gradients and Hessians (psh::sh::SolidHarmonics) against `sphericart`."""

import numpy as np
import sphericart

from mappings import HESSIAN_ENTRIES, degree0_from_solid, lm_arrays, sphericart_sign

LMAX = 48


def directions():
    """Unit directions: the six axes, and 40 pseudo-random ones (fixed seed)."""
    rng = np.random.default_rng(20240812)
    v = rng.normal(size=(40, 3))
    axes = np.array([[0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0]],
                    dtype=float)
    d = np.concatenate([axes, v / np.linalg.norm(v, axis=1, keepdims=True)])
    return d


def psh_derivatives(psh, dirs):
    """psh's value, gradient [3] and Hessian [3, 3] per direction and flat index:
    shapes [n, N], [n, 3, N], [n, 3, 3, N] (sphericart's layout)."""
    meta, d = psh.npy("eval", "sh-derivatives", "--lmax", LMAX,
                      "--points", psh.save("dirs.npy", dirs), out="deriv.npy")
    values = d[:, :, 0]
    grads = np.transpose(d[:, :, 1:4], (0, 2, 1))
    hess = np.zeros((d.shape[0], 3, 3, d.shape[1]))
    for k, (i, j) in enumerate(HESSIAN_ENTRIES):
        hess[:, i, j] = d[:, :, 4 + k]
        hess[:, j, i] = d[:, :, 4 + k]
    return values, grads, hess


def scale(lmax):
    """Per flat index, sqrt((2l+1)/(4 pi)), the bound of |Y_lm|; derivatives are compared
    relative to it times l and l^2."""
    l, _ = lm_arrays(lmax)
    return l, np.sqrt((2 * l + 1) / (4 * np.pi))


def test_sphericart_normalized(psh, record):
    """sphericart.SphericalHarmonics (normalized: the degree-0 extension Y(x/|x|), like
    psh) up to l = 48 with gradients and Hessians."""
    dirs = directions()
    v, g, h = psh_derivatives(psh, dirs)
    sv, sg, sh = sphericart.SphericalHarmonics(LMAX).compute_with_hessians(dirs)
    sign = sphericart_sign(LMAX)
    l, bound = scale(LMAX)
    ev = np.abs(v - sign * sv).max(axis=0) / bound
    eg = np.abs(g - sign * sg).max(axis=(0, 1)) / (bound * np.maximum(l, 1))
    eh = np.abs(h - sign * sh).max(axis=(0, 1, 2)) / (bound * np.maximum(l, 1) ** 2)
    # Errors relative to sqrt((2l+1)/(4 pi)) (times l, l^2 for the derivatives, their
    # natural size). psh's solid-harmonic recursion (psh::sh::SolidHarmonics) runs in f64 in
    # z = cos(theta), whose rounding grows with l: the largest gap, 1.6e-14 of the values,
    # is Y_40,0 at the north pole, where psh is 1.5e-14 off a 40-digit value and
    # sphericart 7e-16. Measured 1.6e-14 (values), 9.2e-15 (gradients), 8.1e-15
    # (Hessians); tolerance 5e-14, below the l^2 eps = 5e-13 of such a recursion at
    # l = 48.
    record("sphericart: real SH (CS sign (-1)^m), l <= 48, 46 directions", "sphericart",
           ev.max(), 5e-14, "max abs error / sqrt((2l+1)/4pi)")
    record("sphericart: gradients of Y(x/|x|)", "sphericart", eg.max(), 5e-14,
           "max abs error / (l sqrt((2l+1)/4pi))")
    record("sphericart: Hessians of Y(x/|x|)", "sphericart", eh.max(), 5e-14,
           "max abs error / (l^2 sqrt((2l+1)/4pi))")


def test_sphericart_solid(psh, record):
    """sphericart.SolidHarmonics (r^l Y, homogeneous polynomials) mapped to the degree-0
    extension by the factor |x|^-l (mappings.degree0_from_solid)."""
    dirs = directions()
    v, g, h = psh_derivatives(psh, dirs)
    sv, sg, sh = sphericart.SolidHarmonics(LMAX).compute_with_hessians(dirs)
    l, bound = scale(LMAX)
    sv, sg, sh = degree0_from_solid(l, sv, sg, sh, dirs)
    sign = sphericart_sign(LMAX)
    ev = np.abs(v - sign * sv).max(axis=0) / bound
    eg = np.abs(g - sign * sg).max(axis=(0, 1)) / (bound * np.maximum(l, 1))
    eh = np.abs(h - sign * sh).max(axis=(0, 1, 2)) / (bound * np.maximum(l, 1) ** 2)
    # As above (measured 1.6e-14, 8.6e-15, 7.1e-15).
    record("sphericart: solid harmonics / |x|^l: values", "sphericart", ev.max(), 5e-14,
           "max abs error / sqrt((2l+1)/4pi)")
    record("sphericart: solid harmonics / |x|^l: gradients", "sphericart", eg.max(), 5e-14,
           "max abs error / (l sqrt((2l+1)/4pi))")
    record("sphericart: solid harmonics / |x|^l: Hessians", "sphericart", eh.max(), 5e-14,
           "max abs error / (l^2 sqrt((2l+1)/4pi))")
