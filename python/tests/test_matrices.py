"""pBRDF matrices: polarsh ISOBI2 files against the paper's product recomputed in numpy
(the validation suite's definition of the layout), analytic models projected two ways
(PSH (51b)-(51c) against PSH (40)), isotropy as a symmetry, and shadowing triple products
PSH (54)-(56) against their closed form for full visibility."""

import numpy as np
import pytest

import psh
from support import rel  # also puts validation/ on the path
from test_pbrdf import isobi2_entries, isobi2_index, reference, save_polarsh_matrix
from test_vector import random_vector


def random_isobi2(lmax, channels, seed):
    rng = np.random.default_rng(seed)
    k = isobi2_index(lmax, lmax, lmax, lmax) + 1
    m = rng.normal(size=(channels, k, 4, 4))
    for li, lo, mi, mo in isobi2_entries(lmax):
        q = isobi2_index(li, lo, mi, mo)
        if lo < 2:
            m[:, q, 1:3, :] = 0  # PSH (31): no spin-2 rows below l = 2
        if li < 2:
            m[:, q, :, 1:3] = 0
    return m


def test_isobi2_product_is_polarsh_product(tmp_path):
    m = random_isobi2(6, 3, seed=30)
    save_polarsh_matrix(tmp_path / "m.npz", m)
    mat = psh.IsotropicMatrix.read_npz(tmp_path / "m.npz")
    assert (mat.lmax, mat.channels, mat.input, mat.output) == (6, 3, "travel", "travel")
    assert np.array_equal(mat.blocks(), m)
    v = random_vector(6, channels=3, seed=31).converted("travel")
    got = mat.apply(v)
    assert got.argument == "travel"
    assert rel(got.coeffs, reference(m, v.coeffs)) < 1e-14
    mat.write_npz(tmp_path / "back.npz")
    with np.load(tmp_path / "back.npz") as z:
        assert np.array_equal(z["coeff"], m)
    # The dense form of channel 1 gives the same product.
    assert rel(mat.to_dense(1).apply(v.channel(1)).coeffs, got.coeffs[1:2]) < 1e-14


def test_measured_gold_on_sponza_is_polarsh_product(data):
    mat = psh.IsotropicMatrix.read_npz(data / "SHMat_6_gold_ds1_L20_ISOBI2.npz")
    v = psh.PshVector.read_npz(data / "SHVec_sponza_1024_L100.npz").truncated(mat.lmax)
    with np.load(data / "SHMat_6_gold_ds1_L20_ISOBI2.npz") as z:
        m = z["coeff"]
    got = mat.apply(v).coeffs
    want = reference(m, v.coeffs)
    assert np.linalg.norm(got - want) / np.linalg.norm(want) < 1e-14


@pytest.mark.parametrize("model", [psh.Conductor(0.4, material="gold", channel="green"),
                                   psh.PolarizedPlastic(0.5, 1.5, 0.4)])
def test_projection_two_ways_and_isotropy(model):
    lmax = 4
    pair = psh.project_pbrdf(model, lmax, 8)
    four = psh.project_pbrdf(model, lmax, 8, block="four-integrals")
    assert (pair.input, pair.output) == ("towards-source", "travel")
    # PSH (51b)-(51c) and PSH (40) integrate the same operator on the same exact grid.
    assert rel(pair.data, four.data) < 1e-12
    # An isotropic model: unchanged by a turn about the normal, and sparse (PSH (52)-(53)).
    turned = pair.rotated(psh.Rotation.from_rotvec([0, 0, 0.7]))
    assert rel(turned.data, pair.data) < 1e-12
    iso = psh.IsotropicMatrix.from_dense(pair, 1e-10)
    assert rel(iso.to_dense(0).data, pair.data) < 1e-10
    pairs = psh.isotropic_pairs(lmax)
    assert iso.blocks().shape == (1, len(pairs), 4, 4)
    for k, (jo, ji) in enumerate(pairs):
        assert np.array_equal(iso.blocks()[0, k], iso.to_dense(0).data[jo, ji])


def test_full_visibility_is_the_identity():
    lmax = 5
    one = psh.PshVector(np.array([[[np.sqrt(4 * np.pi)]]]), "SCALAR")  # V = 1
    m = psh.visibility_transfer(one, lmax).data
    n = (lmax + 1) ** 2
    eye = np.einsum("ij,pq->ijpq", np.eye(n), np.eye(4))
    eye[:4, :4, 1:3, 1:3] = 0  # outside PSH (31)
    assert np.max(np.abs(m - eye)) < 1e-14


def test_shadow_equals_transfer_product():
    rng = np.random.default_rng(32)
    vis = psh.PshVector(rng.normal(size=(1, 9, 1)), "SCALAR")
    f = random_vector(4, channels=1, seed=33)
    table = psh.TripleTable(2, 4)
    assert rel(table.shadow(vis, f).coeffs, table.transfer(vis).apply(f).coeffs) < 1e-13
    assert np.array_equal(table.transfer(vis).data, psh.visibility_transfer(vis, 4).data)
