"""The measured-pBRDF path against the paper's own computation, recomputed in numpy.

polarsh (the paper's code) applies an isotropic pBRDF matrix stored in its ISOBI2 layout to
a coefficient vector by expanding the matrix to a dense one and multiplying, both files in
its own convention (fields indexed by the light's direction of travel). Here that product is
formed in numpy from the files and the written definition of the layout (polarsh `SH.py`,
`lms2idx`), and compared with `psh apply MATRIX VECTOR -o OUT`. Nothing of psh's layout code
is used on this side: a wrong ISOBI2 order or a convention flip in psh's reader, product or
writer shows here as an error of order 1.
"""

import os
import pathlib

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
DATA = pathlib.Path(os.environ.get("PSH_DATA_DIR", ROOT.parent / "shared" / "data")) / "polarsh"
EPS = np.finfo(float).eps


def isobi2_index(li, lo, mi, mo):
    """Position of entry (l_i, l_o, m_i, m_o), |m_i| = |m_o| <= min(l_i, l_o), in the ISOBI2
    layout: the entries of the shells below n = max(l_o, l_i), n (4n^2 - 3n + 2)/3; of the
    lower pairs of the shell, 2k(2k - 1) for k = min(l_o, l_i); 4k + 1 more when l_i > l_o;
    then 2(k + m_i), and +1 when m_o > m_i, -1 when m_o < m_i."""
    n, k = max(li, lo), min(li, lo)
    return (n * (4 * n * n - 3 * n + 2) // 3 + 2 * k * (2 * k - 1)
            + (4 * k + 1 if li > lo else 0) + 2 * (k + mi) + int(np.sign(mo - mi)))


def isobi2_entries(lmax):
    """Every stored entry (l_i, l_o, m_i, m_o) of the layout for l <= lmax."""
    for lo in range(lmax + 1):
        for li in range(lmax + 1):
            kk = min(lo, li)
            for mi in range(-kk, kk + 1):
                for mo in sorted({mi, -mi}):
                    yield li, lo, mi, mo


def dense_from_isobi2(coeff):
    """coeff [channels, K, 4, 4] -> dense [channels, N, N, 4, 4], rows (l_o, m_o)."""
    channels, k = coeff.shape[:2]
    lmax = 0
    while isobi2_index(0, lmax + 1, 0, 0) <= k - 1:
        lmax += 1
    assert isobi2_index(lmax, lmax, lmax, lmax) == k - 1, (k, lmax)
    n = (lmax + 1) ** 2
    out = np.zeros((channels, n, n, 4, 4))
    for li, lo, mi, mo in isobi2_entries(lmax):
        out[:, lo * lo + lo + mo, li * li + li + mi] = coeff[:, isobi2_index(li, lo, mi, mo)]
    return out, lmax


def reference(matrix, vector):
    """polarsh's product: dense matrix (einsum over input index and component) times the
    vector cut to the matrix's band limit, full Stokes."""
    dense, lmax = dense_from_isobi2(matrix)
    n = (lmax + 1) ** 2
    v = np.zeros((vector.shape[0], n, 4))
    v[:, :, : vector.shape[2]] = vector[:, :n]
    return np.einsum("cijkl,cjl->cik", dense, v)


def save_polarsh_vector(path, coeff):
    np.savez(path, cod_type=np.array("POLAR4"), sh_type=np.array("REAL"), coeff=coeff)


def save_polarsh_matrix(path, coeff):
    np.savez(path, dom_type=np.array("ISOBI2"), cod_type=np.array("POLAR4"),
             sh_type=np.array("REAL"), coeff=coeff)


def relative_l2(a, b):
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


def psh_apply(psh, matrix_file, vector_file, name):
    out = psh.path(name)
    psh.run("apply", matrix_file, vector_file, "-o", out)
    return np.load(out)["coeff"]


def test_synthetic_isobi2_product(psh, record):
    """Random ISOBI2 matrices (l < 8, 3 channels, zero spin-2 rows and columns below l = 2)
    and a random vector, written by numpy as polarsh writes them."""
    rng = np.random.default_rng(7)
    lmax = 7
    k = isobi2_index(lmax, lmax, lmax, lmax) + 1
    m = rng.normal(size=(3, k, 4, 4))
    # PSH (31): no spin-2 (p = 1, 2) rows or columns below l = 2 (flat index < 4).
    low = np.zeros((3, k, 4, 4), dtype=bool)
    for li, lo, mi, mo in isobi2_entries(lmax):
        q = isobi2_index(li, lo, mi, mo)
        if lo < 2:
            low[:, q, 1:3, :] = True
        if li < 2:
            low[:, q, :, 1:3] = True
    m[low] = 0.0
    v = rng.normal(size=(3, 144, 4))
    v[:, :4, 1:3] = 0.0
    save_polarsh_matrix(psh.path("synthetic_m.npz"), m)
    save_polarsh_vector(psh.path("synthetic_v.npz"), v)
    got = psh_apply(psh, psh.path("synthetic_m.npz"), psh.path("synthetic_v.npz"), "synthetic_out.npz")
    want = reference(m, v)
    # A sum of ~4 l_max + 1 = 29 products per output: rounding well below 1e-14.
    record("ISOBI2 product of numpy-written polarsh files (random, l < 8, RGB)", "numpy",
           relative_l2(got, want), 1e-14, "relative L2 error")


@pytest.mark.parametrize("material", ["SHMat_6_gold_ds1_L20_ISOBI2.npz",
                                      "SHMat_12_fake_pearl_ds1_L20_ISOBI2.npz"])
@pytest.mark.parametrize("environment", ["SHVec_sponza_1024_L100.npz",
                                         "SHVec_bathroom_1024_L100.npz"])
def test_measured_pbrdf_product(psh, record, material, environment):
    """The shared measured pBRDF applied to the shared environment (cut to l < 20): the
    computation the paper's code performs, every channel and Stokes component."""
    if not (DATA / material).exists():
        pytest.skip(f"shared data missing: {DATA} (set PSH_DATA_DIR)")
    m = np.load(DATA / material)["coeff"]
    v = np.load(DATA / environment)["coeff"]
    got = psh_apply(psh, DATA / material, DATA / environment, "measured_out.npz")
    want = reference(m, v)
    worst = max(relative_l2(got[c, :, p], want[c, :, p]) for c in range(3) for p in range(4))
    # Double-precision sums of ~80 terms: measured ~1e-16; tolerance 1e-13.
    record(f"{material.split('_ds1')[0]} on {environment.split('_1024')[0]} (l < 20), "
           "worst channel and Stokes component", "numpy", worst, 1e-13, "relative L2 error")
