"""psh's scalar and spin-2 SH transforms (psh::sh::ShTransform,
psh::swsh::SpinTransform) against ducc0.sht at L = 512 on the
Gauss-Legendre grid of L + 1 rings by 2L + 2 meridians."""

import ducc0
import numpy as np
import pytest

from mappings import (complex_to_ducc_pair, complex_to_pairs, ducc_pair_to_complex,
                      ducc_to_real, ducc_to_spin2, lm_arrays, pairs_to_complex,
                      real_to_ducc, spin2_to_ducc, spin_minus2_from_spin2)

L = 512
NTHETA, NPHI = L + 1, 2 * L + 2
EPS = np.finfo(float).eps
THREADS = 2


def ducc_synthesis(alm, spin, theta=None):
    """ducc0's maps [ncomp, ntheta, nphi]: on its GL grid with phi0 = 0 (ring 0 nearest
    the north pole, phi_k = 2 pi k / nphi), or, given `theta`, on rings at those polar
    angles with the same meridians (ducc0's general ring geometry)."""
    alm = np.atleast_2d(alm)
    if theta is None:
        return ducc0.sht.synthesis_2d(alm=alm, spin=spin, lmax=L, geometry="GL",
                                      ntheta=NTHETA, nphi=NPHI, nthreads=THREADS)
    nt = len(theta)
    maps = ducc0.sht.synthesis(alm=alm, theta=np.asarray(theta, dtype=float), lmax=L,
                               spin=spin, nphi=np.full(nt, NPHI, dtype=np.uintp),
                               phi0=np.zeros(nt), ringstart=np.arange(nt, dtype=np.uintp) * NPHI,
                               nthreads=THREADS)
    return maps.reshape(-1, nt, NPHI)


# ducc0's own synthesis error at the polar rings at L = 512, relative to max |map|,
# against a 30-digit evaluation of the sum (exact_ring; the same random coefficients):
# 1.9e-12 for the complex transform at ring 512 and 1.1e-12 at ring 0 (test_scalar_complex
# records it in every run), 3.0e-13 for the real one at ring 511; psh's is 6e-14 at the
# same points. The former allowance of 5e-13 (from the real transform only) was hidden
# by the ring offsets of psh's former acos angles (1.9e-12 of the map tolerance).
DUCC0_MAP_ERROR = 2.5e-12


def exact_ring(f, theta, ks, dps=30):
    """The complex synthesis sum_{l <= L, m} f_lm Y_lm(theta, phi_k), phi_k = 2 pi k /
    NPHI, at the ring `theta` (a double, taken exactly) and the meridians `ks`, in `dps`
    digits: Pbar_lm by the sectoral start and the forward recursion in l (DLMF 14.10.3,
    as test_mpmath.pbar_column), with the reflection about pi/2 for theta > pi/2."""
    import mpmath as mp

    with mp.workdps(dps):
        t = mp.mpf(float(theta))
        south = t > mp.pi / 2
        if south:
            t = mp.pi - t
        x, s = mp.cos(t), mp.sin(t)
        fourier = {}
        p = 1 / mp.sqrt(4 * mp.pi)
        for m in range(L + 1):
            if m:
                p = -mp.sqrt(mp.mpf(2 * m + 1) / (2 * m)) * s * p
            prev, cur, inv_a = mp.mpf(0), p, mp.mpf(0)
            plus = minus = mp.mpc(0)
            for l in range(m, L + 1):
                if l > m:
                    a = mp.sqrt(mp.mpf(4 * l * l - 1) / ((l - m) * (l + m)))
                    prev, cur, inv_a = cur, a * (x * cur - prev * inv_a), 1 / a
                v = -cur if (south and (l + m) % 2) else cur
                plus += mp.mpc(f[l * l + l + m].real, f[l * l + l + m].imag) * v
                if m:
                    minus += mp.mpc(f[l * l + l - m].real, f[l * l + l - m].imag) * v
            fourier[m] = plus
            if m:
                fourier[-m] = minus * (-1) ** m  # Y_l,-m = (-1)^m conj(Y_lm)
        return np.array([complex(sum(fourier[m] * mp.expj(2 * mp.pi * m * k / NPHI)
                                     for m in range(-L, L + 1))) for k in ks])


def map_tolerance(psh_theta):
    """Tolerance of a map comparison on the two grids: psh's rings sit delta_j =
    theta_psh - theta_GL off ducc0's (at most 4 eps since the angles are computed in theta:
    test_grid), and along a meridian a band-limited map (spin 0 or spin-weighted: a
    trigonometric polynomial of degree <= L in theta) has |d f / d theta| <= L max |f|
    (Bernstein), so the maps may differ by L max_j |delta_j| max |f| (at most 4.5e-13,
    1.9e-12 with the former acos angles), plus ducc0's own error."""
    delta = np.abs(psh_theta - ducc0.misc.GL_thetas(NTHETA)).max()
    return L * delta + DUCC0_MAP_ERROR


def ducc_analysis(maps, spin):
    return ducc0.sht.analysis_2d(map=np.atleast_3d(maps).reshape(-1, NTHETA, NPHI),
                                 spin=spin, lmax=L, geometry="GL", nthreads=THREADS)


@pytest.fixture(scope="module")
def rng():
    return np.random.default_rng(512)


@pytest.fixture(scope="module")
def psh_theta(psh):
    """psh's ring angles (the grid of `psh eval sht` / `spin-sht` at L)."""
    meta = psh.run("eval", "sht", "--kind", "real", "--lmax", L, "--op", "synthesis",
                   "--input", psh.save("zero.npy", np.zeros((L + 1) ** 2)),
                   "--output", psh.path("zero_map.npy"))["grid"]
    assert (meta["n_theta"], meta["n_phi"]) == (NTHETA, NPHI)
    return np.array(meta["theta"])


def test_grid(psh_theta, record):
    """psh's Gauss-Legendre polar angles against ducc0's (accurate to an ulp), in theta:
    near the poles psh runs its Newton steps in theta with P_n in the difference form in
    1 - cos(theta) (proofs/quadrature.md), where taking them from x = cos(theta) fixed x
    to ~eps but theta only to ~eps / sin(theta) (3.7e-15 here before; the edge sweep,
    test_edges.py, checks n = 2048 against mpmath)."""
    ref = ducc0.misc.GL_thetas(NTHETA)
    # 4 eps absolute: one ulp is 2 eps next to pi, and one more ulp for the computation
    # (the edge sweep's bound).
    record("ducc0: Gauss-Legendre polar angles, 513 rings", "ducc0",
           np.abs(psh_theta - ref).max(), 4 * EPS, "max abs error in theta")


def check_transforms(record, name, psh_theta, maps_psh, maps_ducc, coeffs, back_ducc,
                     coeffs_psh, coeffs_ducc):
    """Records the three comparisons of one transform pair:
    - synthesis: psh's map of `coeffs` against ducc0's map of the same coefficients
      (mapped), on the two grids (map_tolerance);
    - synthesis through ducc0's analysis: ducc0's analysis of psh's map (`back_ducc`,
      mapped back) recovers `coeffs`; the node offsets stay below the rounding here;
    - analysis: psh's analysis of ducc0's map (`coeffs_psh`) against ducc0's analysis of it
      (`coeffs_ducc`, mapped).
    All relative to max |map|: the coefficient errors of an exact quadrature are bounded
    by eps 4 pi max |f| times the growth of the sums."""
    scale = np.abs(maps_ducc).max()
    e_map = np.abs(maps_psh - maps_ducc).max() / scale
    e_syn = np.abs(back_ducc - coeffs).max() / scale
    e_ana = np.abs(coeffs_psh - coeffs_ducc).max() / scale
    record(f"ducc0: {name} synthesis L = 512, maps on the two GL grids", "ducc0", e_map,
           map_tolerance(psh_theta), "max abs error / max |map|",
           "tolerance L max|delta theta| + ducc0's error (map_tolerance)")
    # Measured 1.6e-15 .. 2.2e-15 (all four transforms): sums of ~10^3 terms per ring
    # and per coefficient, rounding ~ 10 eps; tolerance 32 eps = 7.1e-15.
    record(f"ducc0: {name} synthesis L = 512, through ducc0's analysis", "ducc0", e_syn,
           32 * EPS, "max abs error of the coefficients / max |map|")
    record(f"ducc0: {name} analysis L = 512 of ducc0's map", "ducc0", e_ana, 32 * EPS,
           "max abs error of the coefficients / max |map|")


def test_scalar_real(psh, psh_theta, rng, record):
    """Real coefficients (PSH (12)) <-> real maps."""
    c = rng.standard_normal((L + 1) ** 2)
    _, got = psh.npy("eval", "sht", "--kind", "real", "--lmax", L, "--op", "synthesis",
                     "--input", psh.save("c.npy", c), out="map.npy")
    ref = ducc_synthesis(real_to_ducc(c, L), 0)[0]
    back = ducc_to_real(ducc_analysis(got, 0)[0], L)
    _, ana = psh.npy("eval", "sht", "--kind", "real", "--lmax", L, "--op", "analysis",
                     "--input", psh.save("ref_map.npy", ref), out="c_back.npy")
    ref_c = ducc_to_real(ducc_analysis(ref, 0)[0], L)
    check_transforms(record, "real SHT", psh_theta, got, ref, c, back, ana, ref_c)


def test_scalar_complex(psh, psh_theta, rng, record):
    """Complex coefficients (all m) <-> complex maps g + i h, through ducc0's transforms
    of the real fields g and h (mappings.complex_to_ducc_pair)."""
    n = (L + 1) ** 2
    f = rng.standard_normal(n) + 1j * rng.standard_normal(n)
    _, got = psh.npy("eval", "sht", "--kind", "complex", "--lmax", L, "--op", "synthesis",
                     "--input", psh.save("f.npy", complex_to_pairs(f)), out="zmap.npy")
    got = pairs_to_complex(got)
    g, h = complex_to_ducc_pair(f, L)
    ref = ducc_synthesis(g, 0)[0] + 1j * ducc_synthesis(h, 0)[0]

    def ducc_analysis_complex(z):
        return ducc_pair_to_complex(ducc_analysis(z.real, 0)[0], ducc_analysis(z.imag, 0)[0], L)

    back = ducc_analysis_complex(got)
    _, ana = psh.npy("eval", "sht", "--kind", "complex", "--lmax", L, "--op", "analysis",
                     "--input", psh.save("zref.npy", complex_to_pairs(ref)), out="f_back.npy")
    check_transforms(record, "complex SHT", psh_theta, got, ref, f, back,
                     pairs_to_complex(ana), ducc_analysis_complex(ref))
    # Both syntheses against the exact sums at the two polar rings, at the 4 meridians
    # where psh and ducc0 differ most and 4 others.
    scale = np.abs(ref).max()
    e_psh = e_ducc = 0.0
    for j in [0, L]:
        ks = sorted(set(np.argsort(np.abs(got[j] - ref[j]))[-4:]) | {0, 100, 513, 777})
        exact = exact_ring(f, psh_theta[j], ks)
        exact_ducc = exact if psh_theta[j] == ducc0.misc.GL_thetas(NTHETA)[j] else \
            exact_ring(f, ducc0.misc.GL_thetas(NTHETA)[j], ks)
        e_psh = max(e_psh, np.abs(got[j, ks] - exact).max() / scale)
        e_ducc = max(e_ducc, np.abs(ref[j, ks] - exact_ducc).max() / scale)
    # psh: measured 6.1e-14; a sum of (L+1)^2 terms through recursions whose rounding grows
    # like L eps: tolerance L eps = 1.1e-13.
    record("mpmath: psh's complex SHT synthesis L = 512 at the polar rings, 8 meridians each",
           "mpmath", e_psh, L * EPS, "max abs error / max |map|",
           "oracle: 30-digit sum (exact_ring)")
    # ducc0's own error there, the allowance DUCC0_MAP_ERROR of the map comparisons.
    record("mpmath: ducc0's complex SHT synthesis L = 512 at the polar rings (anchor check)",
           "mpmath", e_ducc, DUCC0_MAP_ERROR, "max abs error / max |map|",
           "oracle: 30-digit sum (exact_ring)")


@pytest.mark.parametrize("spin", [2, -2])
def test_spin2(psh, psh_theta, rng, record, spin):
    """Spin-2 coefficients <-> maps of s1 + i s2 (theta-phi frames), against ducc0's
    spin-2 transform of (Q, U) = (s1, s2) with E/B coefficients (mappings.spin2_to_ducc);
    spin -2 transforms s1 - i s2 (mappings.spin_minus2_from_spin2)."""
    n = (L + 1) ** 2
    l, _ = lm_arrays(L)
    a2 = (rng.standard_normal(n) + 1j * rng.standard_normal(n)) * (l >= 2)

    def ducc_synthesis_spin(a):
        """ducc0's map of the spin-`spin` coefficients a (psh's convention)."""
        if spin == -2:
            return np.conj(ducc_synthesis_spin_2(spin_minus2_from_spin2(a, L)))
        return ducc_synthesis_spin_2(a)

    def ducc_synthesis_spin_2(a):
        q, u = ducc_synthesis(np.array(spin2_to_ducc(a, L)), 2)
        return q + 1j * u

    def ducc_analysis_spin(z):
        if spin == -2:
            z = np.conj(z)
        e, b = ducc_analysis(np.array([z.real, z.imag]), 2)
        a = ducc_to_spin2(e, b, L)
        return spin_minus2_from_spin2(a, L) if spin == -2 else a

    # (-2)a_l,-m = (-1)^m conj(2a_lm) is an involution, so the same map serves both ways.
    a = a2 if spin == 2 else spin_minus2_from_spin2(a2, L)
    _, got = psh.npy("eval", "spin-sht", "--spin", spin, "--lmax", L, "--op", "synthesis",
                     "--input", psh.save("a.npy", complex_to_pairs(a)), out="smap.npy")
    got = pairs_to_complex(got)
    ref = ducc_synthesis_spin(a)
    _, ana = psh.npy("eval", "spin-sht", "--spin", spin, "--lmax", L, "--op", "analysis",
                     "--input", psh.save("sref.npy", complex_to_pairs(ref)), out="a_back.npy")
    check_transforms(record, f"spin {spin} SHT", psh_theta, got, ref, a,
                     ducc_analysis_spin(got), pairs_to_complex(ana), ducc_analysis_spin(ref))
