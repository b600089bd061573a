"""Convention mappings between psh and the anchor packages.

Everything here is bookkeeping of conventions (signs, conjugations, index layouts,
changes of basis): no psh numerics. Each function is the exact mapping that the tests
apply and that docs/validation.md states ("Convention mappings"). psh's conventions are
in docs/conventions.md; flat coefficient index `l*l + l + m`.
"""

import numpy as np


def flat(l, m):
    """psh's flat index of (l, m)."""
    return l * l + l + m


def lm_arrays(lmax):
    """(l, m) of every flat index up to lmax."""
    l = np.concatenate([np.full(2 * k + 1, k) for k in range(lmax + 1)])
    m = np.concatenate([np.arange(-k, k + 1) for k in range(lmax + 1)])
    return l, m


def pairs_to_complex(a):
    """psh's [..., 2] float arrays ([re, im]) as complex."""
    a = np.asarray(a, dtype=float)
    return a[..., 0] + 1j * a[..., 1]


def complex_to_pairs(z):
    z = np.asarray(z, dtype=complex)
    return np.stack([z.real, z.imag], axis=-1)


# ---- spherical (Boyle 2016 conventions) -------------------------------------------

def psh_D_from_spherical(block):
    """psh's D^l_{m m'}(R) = <Y_lm, R_F[Y_lm']> (PSH (9)) from spherical's
    𝔇^l_{m', m}(R) (its `Wigner.D`, index `Dindex(l, mp, m)`, laid out here with rows
    mp and columns m): psh's D = conj(spherical's), same row/column order, same active
    rotation R (quaternionic.array.from_rotation_vector of psh's --rotvec). spherical
    follows Boyle (2016), whose 𝔇 is the complex conjugate of the quantum-mechanics D
    exp(-i m alpha) d(beta) exp(-i m' gamma) that psh uses."""
    return np.conj(block)


def real_sh_basis(l):
    """U of docs/conventions.md §4 (PSH (12)): Y^R_lm = sum_mu U[m, mu] Y_l mu,
    rows m = -l..l, columns mu = -l..l."""
    n = 2 * l + 1
    u = np.zeros((n, n), dtype=complex)
    r = 1 / np.sqrt(2)
    for m in range(-l, l + 1):
        i = m + l
        if m > 0:
            u[i, m + l] = r
            u[i, -m + l] = (-1) ** m * r
        elif m == 0:
            u[i, l] = 1
        else:
            u[i, m + l] = 1j * (-1) ** m * r
            u[i, -m + l] = -1j * r
    return u


def real_sh_from_complex(y, lmax):
    """psh's real SH (PSH (12)) from its complex SH y (flat order, last axis) of a real
    direction: Y^R_l0 = Re Y_l0, Y^R_lm = sqrt 2 Re Y_lm and Y^R_l,-m = sqrt 2 Im Y_lm
    for m > 0 (rows of U, with Y_l,-m = (-1)^m conj(Y_lm))."""
    l, m = lm_arrays(lmax)
    y = np.asarray(y)
    pos = y[..., flat(l, np.abs(m))]
    return np.where(m == 0, pos.real, np.sqrt(2) * np.where(m > 0, pos.real, pos.imag))


def real_D_from_complex(l, d):
    """psh's real block D^{l,R} = conj(U) D U^T (PSH (13), docs/conventions.md §8).
    Row m of U has its entries in the columns m and -m only, so the products are taken
    as two row (column) combinations each: O(l^2), where the dense products are O(l^3)
    (the same sums, at most two terms each)."""
    u = real_sh_basis(l)
    n = 2 * l + 1
    i = np.arange(n)
    a = u[i, i]                          # U[m, m]
    b = np.where(i == l, 0, u[i, n - 1 - i])  # U[m, -m], none at m = 0
    d = np.asarray(d)
    x = np.conj(a)[:, None] * d + np.conj(b)[:, None] * d[::-1, :]
    return x * a[None, :] + x[:, ::-1] * b[None, :]


# ---- sphericart --------------------------------------------------------------------

def sphericart_sign(lmax):
    """(-1)^m per flat index: sphericart's real SH have no Condon-Shortley phase, psh's
    do (docs/conventions.md §4), so Y_psh = (-1)^m Y_sphericart with the same flat order
    and the same cos (m > 0) / sin (m < 0) assignment."""
    _, m = lm_arrays(lmax)
    return np.where(m % 2 == 0, 1.0, -1.0)


def degree0_from_solid(l, values, grads, hessians, x):
    """Value, gradient and Hessian of the degree-0 extension Y(x) = Yt(x) / |x|^l at a
    unit x, from those of the solid harmonic Yt (homogeneous of degree l): with r = 1,
      grad Y = grad Yt - l Yt x,
      H Y = H Yt - l (x grad Yt^T + grad Yt x^T) - l Yt I + l (l + 2) Yt x x^T.
    Shapes: values [..., n], grads [..., 3, n], hessians [..., 3, 3, n], x [..., 3],
    l broadcast over n."""
    xs = x[..., :, None]
    g = grads - l * values[..., None, :] * xs
    xg = x[..., :, None, None] * grads[..., None, :, :]
    h = (hessians - l * (xg + np.swapaxes(xg, -3, -2))
         - l * values[..., None, None, :] * np.eye(3)[..., None]
         + l * (l + 2) * values[..., None, None, :] * (x[..., :, None] * x[..., None, :])[..., None])
    return values, g, h


HESSIAN_ENTRIES = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)]


# ---- ducc0 (healpy conventions) ----------------------------------------------------

def ducc_index(lmax):
    """ducc0's (healpy's) triangular alm layout, m >= 0 only, m-major:
    index(l, m) = m (2 lmax + 1 - m) / 2 + l. Returns (l, m, index) arrays."""
    ls, ms = [], []
    for m in range(lmax + 1):
        for l in range(m, lmax + 1):
            ls.append(l)
            ms.append(m)
    l, m = np.array(ls), np.array(ms)
    return l, m, m * (2 * lmax + 1 - m) // 2 + l


def real_to_ducc(c, lmax):
    """psh's real coefficients (PSH (12)) of a real field to ducc0's complex alm, m >= 0,
    of the same field: a_l0 = c_l0, a_lm = (c_lm - i c_l,-m) / sqrt 2 (m > 0), from
    Y^R_lm = sqrt 2 Re Y_lm, Y^R_l,-m = sqrt 2 Im Y_lm and a_l,-m = (-1)^m conj(a_lm).
    ducc0's Y_lm carry the Condon-Shortley phase like psh's (checked by the complex
    transform below: same harmonics)."""
    l, m, idx = ducc_index(lmax)
    a = np.zeros(len(idx), dtype=complex)
    a[idx] = np.where(m == 0, c[flat(l, m)],
                      (c[flat(l, m)] - 1j * c[flat(l, -m)]) / np.sqrt(2))
    return a


def ducc_to_real(a, lmax):
    """Inverse of real_to_ducc: c_l0 = Re a_l0, c_lm = sqrt 2 Re a_lm,
    c_l,-m = -sqrt 2 Im a_lm."""
    l, m, idx = ducc_index(lmax)
    c = np.zeros((lmax + 1) ** 2)
    c[flat(l, m)] = np.where(m == 0, a[idx].real, np.sqrt(2) * a[idx].real)
    pos = m > 0
    c[flat(l[pos], -m[pos])] = -np.sqrt(2) * a[idx][pos].imag
    return c


def complex_to_ducc_pair(f, lmax):
    """psh's complex coefficients f of a complex field g + i h (all m) to ducc0's alm of
    the real fields g and h (m >= 0): with f_l,-m of the real field g being
    (-1)^m conj(g_lm),
      g_lm = (f_lm + (-1)^m conj(f_l,-m)) / 2,  h_lm = (f_lm - (-1)^m conj(f_l,-m)) / (2 i)."""
    l, m, idx = ducc_index(lmax)
    fp, fm = f[flat(l, m)], np.conj(f[flat(l, -m)]) * (-1.0) ** m
    g, h = np.zeros(len(idx), complex), np.zeros(len(idx), complex)
    g[idx] = (fp + fm) / 2
    h[idx] = (fp - fm) / 2j
    return g, h


def ducc_pair_to_complex(g, h, lmax):
    """Inverse of complex_to_ducc_pair: f_lm = g_lm + i h_lm and
    f_l,-m = (-1)^m (conj g_lm + i conj h_lm)."""
    l, m, idx = ducc_index(lmax)
    f = np.zeros((lmax + 1) ** 2, dtype=complex)
    f[flat(l, m)] = g[idx] + 1j * h[idx]
    f[flat(l, -m)] = (-1.0) ** m * (np.conj(g[idx]) + 1j * np.conj(h[idx]))
    return f


def spin2_to_ducc(a, lmax):
    """psh's spin-2 coefficients a_lm (all m, of the field s1 + i s2 = sum a_lm 2Y_lm in
    the theta-phi frames, PSH (26)-(28)) to ducc0's gradient/curl (E, B) alm, m >= 0,
    with ducc0's maps (Q, U) = (s1, s2): ducc0 follows healpy, 2a_lm = -(E_lm + i B_lm)
    and Q + i U = sum 2a_lm 2Y_lm with the same 2Y_lm as psh (measured: this mapping
    makes the two syntheses agree; any other sign or a conjugation does not). So
      E_lm = -(a_lm + (-1)^m conj(a_l,-m)) / 2,  B_lm = -(a_lm - (-1)^m conj(a_l,-m)) / (2 i)."""
    g, h = complex_to_ducc_pair(a, lmax)
    return -g, -h


def ducc_to_spin2(e, b, lmax):
    """Inverse of spin2_to_ducc: a_lm = -(E_lm + i B_lm),
    a_l,-m = -(-1)^m (conj E_lm + i conj B_lm)."""
    return ducc_pair_to_complex(-e, -b, lmax)


def spin_minus2_from_spin2(a, lmax):
    """The spin -2 coefficients of s1 - i s2 = conj(s1 + i s2) from the spin-2 ones of
    s1 + i s2: conj(sY_lm) = (-1)^(s+m) (-s)Y_l,-m (PSH's sY_lm, proofs/swsh.md), so
    (-2)a_l,-m = (-1)^m conj(2a_lm)."""
    l, m = lm_arrays(lmax)
    out = np.zeros_like(a)
    out[flat(l, -m)] = (-1.0) ** m * np.conj(a[flat(l, m)])
    return out


# ---- Mitsuba 3 ---------------------------------------------------------------------

FLIP_Z = np.diag([1.0, 1.0, -1.0, -1.0])


def mitsuba_to_psh_frames(m):
    """psh's Fresnel Mueller matrix in psh's frames (input frame [s, w_i x s, w_i] with
    w_i towards the source, output [s, w_o x s, w_o]) from one in Mitsuba's travel
    frames [s, d x s, d] on both sides: the input frame is [x, -y, -z] of the incident
    travel frame, in which Stokes components read (s0, s1, -s2, -s3), so
    M_psh = M_mitsuba diag(1, 1, -1, -1); the output frames are the same."""
    return np.asarray(m) @ FLIP_Z
