"""PSH coefficient vectors: polarsh .npz files, evaluation PSH (30) against the basis sum
written in numpy, rotation PSH (35)-(37) against the geometric definition PSH (25), and
equality with the command line's results."""

import numpy as np

import psh
from support import rel, unit_directions

EPS = np.finfo(float).eps


def random_vector(lmax, channels=2, seed=0, codomain="POLAR4"):
    p = {"SCALAR": 1, "POLAR2": 2, "POLAR3": 3, "POLAR4": 4}[codomain]
    c = np.random.default_rng(seed).normal(size=(channels, (lmax + 1) ** 2, p))
    comps = psh.PshVector(np.zeros((1, 1, p)), codomain).components
    for k, s in enumerate(comps):
        if s in (1, 2):
            c[:, :4, k] = 0  # spin 2 starts at l = 2 (PSH (31))
    return psh.PshVector(c, codomain)


def basis_sum(v, d):
    """Stokes components in the theta-phi frames from the definition (module docs of
    psh::polarized): s0 = sum f_lm0 Y^R_lm, s1 + i s2 = sum (f_lm1 + i f_lm2) 2Y_lm."""
    y = psh.sh_real(v.lmax, d)
    y2 = psh.swsh(2, v.lmax, d)
    f = v.coeffs
    out = np.zeros((v.channels, len(d), 4))
    out[:, :, 0] = np.einsum("dj,cj->cd", y, f[:, :, 0])
    z = np.einsum("dj,cj->cd", y2, f[:, :, 1] + 1j * f[:, :, 2])
    out[:, :, 1], out[:, :, 2] = z.real, z.imag
    out[:, :, 3] = np.einsum("dj,cj->cd", y, f[:, :, 3])
    return out


def test_evaluate_is_the_basis_sum():
    v = random_vector(12)
    d = unit_directions(100, seed=4)
    got = v.evaluate(d)
    assert got.shape == (2, len(d), 4)
    assert rel(got, basis_sum(v, d)) < 1e-13


def rotate_linear(s1, s2, angle):
    """Components of a linear Stokes part in a frame turned by `angle` about the ray:
    s1' + i s2' = exp(-2i angle) (s1 + i s2) (PSH (14))."""
    z = (s1 + 1j * s2) * np.exp(-2j * angle)
    return z.real, z.imag


def test_rotation_is_the_geometric_rotation():
    """R_F[f](w) = R f(R^-1 w) PSH (25): the Stokes vector of R^-1 w, carried to w with its
    frame turned by R, read in the theta-phi frame at w."""
    v = random_vector(10, seed=5)
    r = psh.Rotation.from_rotvec([0.4, -0.9, 1.3])
    rm = r.matrix()
    turned = v.rotated(r)
    d = unit_directions(60, seed=6, poles=False)
    src = d @ rm  # R^-1 w for each row w
    before = v.evaluate(src)
    after = turned.evaluate(d)
    tp = psh.FrameField.theta_phi()
    for i, (w, u) in enumerate(zip(d, src)):
        x_carried = rm @ tp.frame(u)[0]
        fx, fy, _ = tp.frame(w)
        angle = np.arctan2(x_carried @ fy, x_carried @ fx)  # from the carried x to e_theta
        s1, s2 = rotate_linear(before[:, i, 1], before[:, i, 2], -angle)
        expected = np.stack([before[:, i, 0], s1, s2, before[:, i, 3]], axis=-1)
        assert rel(after[:, i], expected) < 1e-12, i


def test_frame_fields_read_the_same_stokes_vector():
    v = random_vector(6, seed=7)
    d = unit_directions(30, seed=8, poles=False)
    tp = v.evaluate(d)
    cam = psh.FrameField.perspective([0, 1.0, 0], [0, 0, 1.0])
    other = v.evaluate(d, cam)
    for i, w in enumerate(d):
        a, b = psh.FrameField.theta_phi().frame(w), cam.frame(w)
        assert np.allclose(a[2], w) and np.allclose(b[2], w)
        angle = np.arctan2(b[0] @ a[1], b[0] @ a[0])
        s1, s2 = rotate_linear(tp[:, i, 1], tp[:, i, 2], angle)
        assert np.allclose(other[:, i, 1], s1, atol=1e-12)
        assert np.allclose(other[:, i, 2], s2, atol=1e-12)
        assert np.allclose(other[:, i, [0, 3]], tp[:, i, [0, 3]], atol=1e-14)


def test_npz_round_trip_and_numpy(tmp_path):
    v = random_vector(5, channels=3, seed=9)
    path = tmp_path / "v.npz"
    v.write_npz(path)
    back = psh.PshVector.read_npz(path)
    assert back.argument == "travel" and back.codomain == "POLAR4"
    assert rel(back.converted("towards-source").coeffs, v.coeffs) < 1e-15
    with np.load(path) as z:
        assert np.array_equal(z["coeff"], back.coeffs)
    scalar = random_vector(4, channels=1, codomain="SCALAR")
    scalar.write_npz(tmp_path / "s.npz")
    assert psh.PshVector.read_npz(tmp_path / "s.npz").codomain == "SCALAR"


def test_vector_methods():
    v = random_vector(8, channels=3, seed=10)
    assert (v.lmax, v.channels, v.codomain, v.argument) == (8, 3, "POLAR4", "towards-source")
    assert v.truncated(3).coeffs.shape == (3, 16, 4)
    assert np.array_equal(v.channel(1).coeffs[0], v.coeffs[1])
    both = psh.PshVector.from_channels([v.channel(0), v.channel(2)])
    assert np.array_equal(both.coeffs, v.coeffs[[0, 2]])
    assert np.array_equal(v.with_codomain("POLAR2").coeffs, v.coeffs[:, :, 1:3])
    e = v.band_energies()
    l = np.floor(np.sqrt(np.arange(81))).astype(int)
    assert np.allclose(e, [np.sum(v.coeffs[:, l == k] ** 2) for k in range(9)], rtol=1e-14)
    # travel <-> towards-source is an involution.
    assert np.array_equal(v.converted("travel").converted("towards-source").coeffs, v.coeffs)


def test_rotation_equals_the_command_line(cli, data, tmp_path):
    v = psh.PshVector.read_npz(data / "SHVec_sponza_1024_L100.npz").truncated(40)
    tmp = tmp_path
    v.write_npz(tmp / "in.npz")
    cli("rotate", "--rotvec", "0.3,-1.1,0.7", "-o", "out.npz", "in.npz")
    ref = psh.PshVector.read_npz(tmp / "out.npz")
    got = v.rotated(psh.Rotation.from_rotvec([0.3, -1.1, 0.7]))
    assert got.argument == ref.argument == "travel"
    assert np.array_equal(got.coeffs, ref.coeffs)


def test_fortran_ordered_files_are_read_in_their_order(tmp_path):
    """numpy writes a Fortran-ordered array with `fortran_order: True`; its values are the
    same array (issue 21: it was read as C order, channels and coefficients swapped)."""
    c = np.random.default_rng(40).normal(size=(3, 25, 4))
    c[:, :4, 1:3] = 0
    np.savez(tmp_path / "f.npz", cod_type=np.array("POLAR4"), sh_type=np.array("REAL"),
             coeff=np.asfortranarray(c))
    with np.load(tmp_path / "f.npz") as z:
        assert z["coeff"].flags.f_contiguous and not z["coeff"].flags.c_contiguous
    assert np.array_equal(psh.PshVector.read_npz(tmp_path / "f.npz").coeffs, c)
