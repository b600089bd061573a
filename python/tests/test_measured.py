"""Measured pBRDF tables from Python: a Mitsuba 3 `.pbsdf` written here by an independent
writer of Mitsuba's TensorFile layout (magic, version, per-field header, 8-byte aligned
data), read by psh and projected; a constant depolarizing table against the closed form
of its projection."""

import math

import numpy as np
import pytest

import psh
from support import write_tensor_file


def constant_table(path, c, bands=(450, 500, 550, 600, 650)):
    """f = diag(c, 0, 0, 0) everywhere: P = c cos(theta_i), a depolarizing Lambertian."""
    phi = np.linspace(-np.pi, np.pi, 13, dtype=np.float32)
    theta = np.linspace(0, np.pi / 2, 7, dtype=np.float32)
    m = np.zeros((13, 7, 7, len(bands), 4, 4), dtype=np.float32)
    m[..., 0, 0] = c
    write_tensor_file(path, [
        ("phi_d", phi[None, :]), ("theta_d", theta[None, :]), ("theta_h", theta[None, :]),
        ("wvls", np.array(bands, dtype=np.uint16)), ("M", m),
    ])


def test_a_constant_table_projects_to_its_closed_form(tmp_path):
    path = tmp_path / "lambert.pbsdf"
    c = 0.25
    constant_table(path, c)
    t = psh.read_measured_pbrdf(path)
    assert t.shape == (13, 7, 7)
    assert t.wavelengths == [450.0, 500.0, 550.0, 600.0, 650.0]
    assert t.invalid_fraction == 0.0
    # An even number of Gauss-Legendre rings (24): none on the horizon, whose step the
    # quadrature then splits exactly (a ring on it, with grid_lmax = 24, counts the whole
    # ring and gives 6% more).
    m = t.to_rgb().project(2, grid_lmax=23)
    assert m.channels == 3
    # M_{00,00} = int int Y_00 c cos(theta_i) Y_00 over both upper hemispheres
    # = c pi 2 pi / (4 pi) = c pi / 2 (PSH (40)); measured 1.4e-3 relative at 24 rings,
    # 3.5e-4 at 48 (the quadrature of cos(theta_i) over a half sphere).
    want = c * math.pi / 2
    for ch in range(3):
        m00 = m.to_dense(ch).data[0, 0, 0, 0]
        assert abs(m00 / want - 1) < 3e-3, m00


def test_bad_tables_raise(tmp_path):
    path = tmp_path / "t.pbsdf"
    constant_table(path, 0.1, bands=(500, 600))
    with pytest.raises(ValueError, match="KAIST bands"):
        psh.read_measured_pbrdf(path).to_rgb()
    raw = path.read_bytes()
    (tmp_path / "cut.pbsdf").write_bytes(raw[: len(raw) // 2])
    with pytest.raises(OSError, match="cut.pbsdf"):
        psh.read_measured_pbrdf(tmp_path / "cut.pbsdf")


def stokes_turn(t):
    """C(t): Stokes components in a frame turned by t about the ray (s1 + i s2 times
    e^{-2it})."""
    c, s = np.cos(2 * t), np.sin(2 * t)
    return np.array([[1, 0, 0, 0], [0, c, s, 0], [0, -s, c, 0], [0, 0, 0, 1]])


def rusinkiewicz_directions(pd, td, th):
    """(w_i, w_o) of Rusinkiewicz angles with phi_h = 0 (Rusinkiewicz 1998)."""
    h = np.array([np.sin(th), 0, np.cos(th)])
    t = np.array([np.cos(th), 0, -np.sin(th)])
    b = np.array([0.0, 1.0, 0.0])
    wi = np.sin(td) * (np.cos(pd) * t + np.sin(pd) * b) + np.cos(td) * h
    return wi, 2 * (h @ wi) * h - wi


def test_a_kaist_mat_file_in_turned_frames_projects_as_the_same_pbsdf(tmp_path, cli):
    """The KAIST dataset's layout written by scipy (MAT v5, zlib-compressed, column-major):
    a smooth polarizing table in frames turned per sample about each frame's z, with the
    info file giving those frames, projects (from Python and from the command line) as the
    same table written as a .pbsdf in the convention's frames."""
    import scipy.io

    n_p, n_t = 25, 10
    pd = np.linspace(-np.pi, np.pi, n_p)
    td = np.linspace(0, np.pi / 2, n_t)
    th = (np.arange(n_t) / (n_t - 1)) ** 2 * np.pi / 2
    conv = np.zeros((n_p, n_t, n_t, 5, 4, 4))
    data = np.zeros_like(conv)
    xyzi = np.full((n_p, n_t, n_t, 3, 3), np.nan)
    xyzo = np.full_like(xyzi, np.nan)
    rng = np.random.default_rng(3)
    for a, b, c in np.ndindex(n_p, n_t, n_t):
        wi, wo = rusinkiewicz_directions(pd[a], td[b], th[c])
        # Smooth in the angles, with s1, s2 entries that vanish where w_i = w_o, and no
        # dependence on phi_d where it is undefined (theta_h = 0, theta_d = 0).
        g = np.sin(td[b]) ** 2 * np.sin(th[c])
        # At w_i = w_o the table's input and output frames share x and have opposite y:
        # a continuous table is diag(a, -a) in s1, s2 there (a mirror's form).
        m = np.diag([1.0, 0.4, -0.4, -0.3]) * np.cos(th[c])
        m[0, 1] = m[1, 0] = 0.2 * g
        m[1, 2], m[2, 1] = 0.1 * g * np.cos(pd[a]), -0.1 * g * np.cos(pd[a])
        conv[a, b, c] = m
        xyzi[a, b, c, 2], xyzo[a, b, c, 2] = -wi, wo
        x = np.cross(wi, wo)
        if np.linalg.norm(x) < 1e-9:
            data[a, b, c] = m  # frames undefined (w_i = w_o, the horizon): as given
            continue
        x /= np.linalg.norm(x)
        ti, to = rng.uniform(-np.pi, np.pi, 2)
        for frames, z, t in ((xyzi, -wi, ti), (xyzo, wo, to)):
            xf = np.cos(t) * x + np.sin(t) * np.cross(z, x)
            frames[a, b, c, 0], frames[a, b, c, 1] = xf, np.cross(z, xf)
        # The file's x is the convention's turned by t: Stokes there are C(t) s.
        data[a, b, c] = stokes_turn(to) @ m @ stokes_turn(-ti)
    angles = dict(phi_d=pd[None].astype(np.float32), theta_d=td[None].astype(np.float32),
                  theta_h=th[None].astype(np.float32))
    scipy.io.savemat(tmp_path / "t_pbrdf.mat", dict(angles, pbrdf_T_f=data.astype(np.float32)),
                     do_compression=True)
    scipy.io.savemat(tmp_path / "info.mat", dict(angles, xyzi_T=xyzi.astype(np.float32),
                                                 xyzo_T=xyzo.astype(np.float32)),
                     do_compression=True)
    write_tensor_file(tmp_path / "t.pbsdf", [
        *((k, v) for k, v in angles.items()),
        ("wvls", np.array([450, 500, 550, 600, 650], dtype=np.uint16)),
        ("M", conv.astype(np.float32))])

    kaist = psh.read_measured_pbrdf(tmp_path / "t_pbrdf.mat", info=tmp_path / "info.mat")
    pbsdf = psh.read_measured_pbrdf(tmp_path / "t.pbsdf")
    assert kaist.shape == pbsdf.shape == (n_p, n_t, n_t)
    a, b = kaist.project(4), pbsdf.project(4)
    da, db = a.to_dense(0).data, b.to_dense(0).data
    assert np.abs(da - db).max() < 1e-5 * np.abs(db).max()
    # The s1, s2 content is there (a frame error shows at this size).
    assert np.abs(db[:, :, 1:3, 1:3]).max() > 1e-2 * np.abs(db).max()
    # Read as if in the convention (no info file), the turned matrices differ.
    bare = psh.read_measured_pbrdf(tmp_path / "t_pbrdf.mat").project(4, tolerance=1)
    bare = bare.to_dense(0).data
    assert np.abs(bare - db).max() > 1e-2 * np.abs(db).max()
    # The command line writes the same matrices.
    cli("pbrdf", "project", tmp_path / "t_pbrdf.mat", "--info", tmp_path / "info.mat",
        "--lmax", 4, "-o", tmp_path / "t.npz")
    from_cli = psh.IsotropicMatrix.read_npz(tmp_path / "t.npz").with_input(a.input)
    from_cli = from_cli.to_dense(0).data
    assert np.abs(from_cli - da).max() < 1e-12 * np.abs(da).max()
    # The info file of another sampling is refused, naming it.
    scipy.io.savemat(tmp_path / "other.mat", dict(angles, theta_h=td[None].astype(np.float32),
                                                  xyzi_T=xyzi.astype(np.float32),
                                                  xyzo_T=xyzo.astype(np.float32)))
    with pytest.raises(OSError, match="another sampling"):
        psh.read_measured_pbrdf(tmp_path / "t_pbrdf.mat", info=tmp_path / "other.mat")
