"""The module behaves like its numpy neighbours: objects pickle and copy to equal values,
vectors add and scale as their coefficients do (conventions checked, never guessed), the
operators apply with `@`, `coeffs` cannot be edited in vain, and every object prints what
it is."""

import copy
import pickle

import numpy as np
import pytest

import psh
from test_vector import random_vector


def gold_matrix(lmax=3):
    """An isotropic matrix: GGX gold projected (dense) and kept in the isotropic layout."""
    dense = psh.project_pbrdf(psh.Conductor(0.4, material="gold"), lmax)
    return psh.IsotropicMatrix.from_dense(dense, 1e-8)


def same_vector(a, b):
    assert (a.lmax, a.channels, a.codomain, a.argument) == (b.lmax, b.channels, b.codomain,
                                                            b.argument)
    assert np.array_equal(a.coeffs, b.coeffs)


def test_vectors_rotations_and_matrices_pickle_and_copy():
    v = random_vector(6, channels=3).converted("travel")
    r = psh.Rotation.from_euler_zyz(0.3, 1.1, -2.0)
    iso = psh.IsotropicMatrix.from_channels([gold_matrix(), gold_matrix()])
    dense = iso.to_dense(1)
    for clone in (lambda x: pickle.loads(pickle.dumps(x)), copy.copy, copy.deepcopy):
        same_vector(clone(v), v)
        assert np.array_equal(clone(r).matrix(), r.matrix())
        c = clone(iso)
        assert (c.lmax, c.channels, c.input, c.output) == (iso.lmax, 2, iso.input, iso.output)
        assert np.array_equal(c.blocks(), iso.blocks())
        d = clone(dense)
        assert (d.lmax, d.input, d.output) == (dense.lmax, dense.input, dense.output)
        assert np.array_equal(d.data, dense.data)
    # The copies act as the originals.
    f = random_vector(3, channels=2).converted(iso.input)
    same_vector(pickle.loads(pickle.dumps(iso)) @ f, iso @ f)


def test_vector_arithmetic_is_the_coefficients_arithmetic():
    v, w = random_vector(5, seed=1), random_vector(5, seed=2)
    assert np.array_equal((v + w).coeffs, v.coeffs + w.coeffs)
    assert np.array_equal((v - w).coeffs, v.coeffs - w.coeffs)
    assert np.array_equal((2.5 * v).coeffs, 2.5 * v.coeffs)
    assert np.array_equal((v * 2.5).coeffs, 2.5 * v.coeffs)
    assert np.array_equal((v / 4).coeffs, v.coeffs / 4)
    assert np.array_equal((-v).coeffs, -v.coeffs)
    # Linear in the field: evaluating the sum is the sum of evaluations.
    d = np.array([[0.0, 0.6, 0.8], [1.0, 0.0, 0.0]])
    assert np.allclose((v + 3 * w).evaluate(d), v.evaluate(d) + 3 * w.evaluate(d),
                       rtol=1e-13, atol=1e-13)


@pytest.mark.parametrize("other, what", [
    (lambda v: random_vector(4), "band limit"),
    (lambda v: random_vector(5, codomain="POLAR3"), "codomain"),
    (lambda v: random_vector(5, channels=1), "channel count"),
    (lambda v: v.converted("travel"), "argument convention"),
])
def test_mismatched_vectors_do_not_combine(other, what):
    v = random_vector(5)
    with pytest.raises(ValueError, match=what):
        v + other(v)


def test_bad_scales_and_operands():
    v = random_vector(3)
    with pytest.raises(ZeroDivisionError):
        v / 0
    with pytest.raises(ValueError, match="finite"):
        v * float("nan")
    with pytest.raises(TypeError):
        v + 1.0
    with pytest.raises(TypeError):
        v * v


def test_matmul_applies_operators():
    iso = gold_matrix()
    f = random_vector(3, channels=1)
    same_vector(iso @ f, iso.apply(f))
    dense = iso.to_dense(0)
    same_vector(dense @ f, dense.apply(f))


def test_coeffs_is_a_read_only_copy():
    v = random_vector(3)
    c = v.coeffs
    with pytest.raises(ValueError, match="read-only"):
        c[0, 0, 0] = 1.0
    edited = c.copy()
    edited[0, 0, 0] = 7.0
    assert psh.PshVector(edited).coeffs[0, 0, 0] == 7.0
    assert v.coeffs[0, 0, 0] != 7.0


def test_objects_print_what_they_are():
    iso = gold_matrix()
    assert repr(iso) == "IsotropicMatrix(lmax=3, channels=1, input={}, output={})".format(
        iso.input, iso.output)
    assert repr(iso.to_dense(0)).startswith("PshMatrix(lmax=3, input=")
    assert repr(psh.Conductor(0.3, n=0.2, k=3.0)) == "Conductor(alpha=0.3, n=0.2, k=3)"
    assert repr(psh.PolarizedPlastic(0.2, 1.5, 0.4)) == (
        "PolarizedPlastic(alpha=0.2, n=1.5, albedo=0.4)")
    assert repr(random_vector(2)).startswith("PshVector(lmax=2, channels=2, codomain=POLAR4")


def test_single_precision_directions_are_renormalized_within_their_bound():
    rng = np.random.default_rng(3)
    d = rng.normal(size=(50, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    d32 = d.astype(np.float32)
    exact = d32.astype(np.float64)
    exact /= np.linalg.norm(exact, axis=1, keepdims=True)
    # The float32 rows, renormalized in float64, are the directions evaluated.
    assert np.array_equal(psh.sh_real(4, d32), psh.sh_real(4, exact))
    v = random_vector(3)
    assert np.array_equal(v.evaluate(d32), v.evaluate(exact))
    assert np.array_equal(psh.FrameField.theta_phi().frame(d32[0]),
                          psh.FrameField.theta_phi().frame(exact[0]))
    # float64 directions keep their own bound; a float32 row far from unit is refused.
    with pytest.raises(ValueError, match="not a unit vector"):
        psh.sh_real(2, d[:1] * (1 + 1e-8))
    with pytest.raises(ValueError, match=r"norm 1\.0000099.*single-precision"):
        psh.sh_real(2, (d[:1] * 1.00001).astype(np.float32))


def test_scipy_rotations_turn_fields_as_psh_rotations():
    transform = pytest.importorskip("scipy.spatial.transform")
    r = transform.Rotation.from_rotvec([0.3, -1.2, 0.5])
    v = random_vector(4, channels=1)
    turned = v.rotated(r)
    same_vector(turned, v.rotated(psh.Rotation.from_matrix(r.as_matrix())))
    # Independent of psh's matrices: the turned field at R w is the field at w (scalar
    # part; Stokes frames turn with the field, so s0 compares directly).
    w = np.array([[0.0, 0.6, 0.8], [0.48, 0.6, 0.64], [-1.0, 0.0, 0.0]])
    assert np.allclose(turned.evaluate(r.apply(w))[..., 0], v.evaluate(w)[..., 0],
                       rtol=1e-12, atol=1e-12)
    for d_psh, d_scipy in zip(psh.wigner_d(psh.Rotation.from_matrix(r.as_matrix()), 3),
                              psh.wigner_d(r, 3)):
        assert np.array_equal(d_psh, d_scipy)
    with pytest.raises(ValueError, match=r"shape \[2, 3, 3\]"):
        v.rotated(transform.Rotation.from_rotvec([[0, 0, 1.0], [1.0, 0, 0]]))
    with pytest.raises(TypeError, match="not a psh.Rotation"):
        v.rotated([0.0, 0.0, 1.0])


def test_quaternionic_rotations_are_accepted():
    quaternionic = pytest.importorskip("quaternionic")
    q = quaternionic.array.from_rotation_vector([0.3, -1.2, 0.5])
    r = psh.Rotation.from_rotvec([0.3, -1.2, 0.5])
    assert np.allclose(psh.wigner_d_real(q, 2)[2], psh.wigner_d_real(r, 2)[2], atol=1e-14)
