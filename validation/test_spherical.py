"""psh's Wigner D (complex and real) and spin-weighted SH against `spherical`
(Boyle's package, rotations as `quaternionic` unit quaternions)."""

import numpy as np
import quaternionic
import spherical

from mappings import pairs_to_complex, psh_D_from_spherical, real_D_from_complex

# Rotation vectors (axis times angle, active, PSH (8)): a generic one, a small one, a
# half turn about an axis in the xy plane (beta = pi: psh's Euler angles are degenerate
# there and set gamma = 0) and one about z (beta = 0).
ROTATIONS = {
    "generic": (0.3, -0.7, 0.5),
    "small": (1e-3, -2e-3, 5e-4),
    "beta=pi": (np.pi * np.cos(0.4), np.pi * np.sin(0.4), 0.0),
    "about z": (0.0, 0.0, 2.0),
}


def spherical_block(wigner, R, l):
    """spherical's 𝔇^l(R) as a (2l+1)^2 array, rows m', columns m."""
    D = wigner.D(R)
    idx = np.array([[wigner.Dindex(l, mp, m) for m in range(-l, l + 1)]
                    for mp in range(-l, l + 1)])
    return D[idx]


def rotvec_arg(v):
    return ",".join(repr(float(x)) for x in v)


# The small rotation is kept apart: psh builds D from ZYZ Euler angles of the rotation
# matrix (psh::geometry::euler_zyz), and alpha, gamma are atan2 of matrix entries of
# size sin(beta), so they carry an error ~ eps / sin(beta) that the phases
# e^{-i (m alpha + m' gamma)} multiply by up to 2l. spherical works from the quaternion
# and has no such loss (checked once against a 50-digit evaluation of Wigner's formula:
# at l = 40, entry (40, 40), spherical is off by 4e-15 and psh by 4e-13).
WELL_CONDITIONED = ["generic", "beta=pi", "about z"]
EPS = np.finfo(float).eps


def euler_conditioning_bound(v, l):
    """l eps / sin(beta) for the rotation vector v: the size of the phase error of the
    Euler-angle route at degree l (an entry's error is at most about |m delta alpha +
    m' delta gamma| <= 2 l eps / sin(beta) with the atan2 errors eps / sin(beta); the
    measured errors are a tenth of this)."""
    r = quaternionic.array.from_rotation_vector(v).to_rotation_matrix
    return l * EPS / np.hypot(r[0, 2], r[1, 2])


def test_wigner_D_low_degrees(psh, record):
    """All blocks l <= 40 of four rotations (psh eval wigner, JSON)."""
    lmax = 40
    w = spherical.Wigner(lmax)
    worst = {}
    for name, v in ROTATIONS.items():
        R = quaternionic.array.from_rotation_vector(v)
        blocks = {k: psh.run("eval", "wigner", "--kind", k, "--lmax", lmax,
                             "--rotvec", rotvec_arg(v))["blocks"] for k in ["complex", "real"]}
        for l in range(lmax + 1):
            n = 2 * l + 1
            ref = psh_D_from_spherical(spherical_block(w, R, l))
            got = pairs_to_complex(blocks["complex"][l]).reshape(n, n)
            ref_r = real_D_from_complex(l, ref)
            assert np.abs(ref_r.imag).max() < 1e-13  # the change of basis gives a real D
            got_r = np.array(blocks["real"][l])[:, 0].reshape(n, n)
            for kind, e in [("complex", np.abs(got - ref).max()),
                            ("real", np.abs(got_r - ref_r.real).max())]:
                worst[name, kind] = max(worst.get((name, kind), 0.0), e)
    # Entries are bounded by 1 (unitary blocks). Two independent double-precision
    # recursions (psh: Risbo's; spherical: Gumerov-Duraiswami's) to l = 40, whose rounding
    # grows about like l eps = 8.9e-15: measured 9.5e-15 (complex) and 9.9e-15 (real);
    # tolerance 3 l eps.
    for kind in ["complex", "real"]:
        e = max(worst[n, kind] for n in WELL_CONDITIONED)
        record(f"spherical: {kind} Wigner D, l <= 40, rotations {', '.join(WELL_CONDITIONED)}",
               "spherical", e, 3 * lmax * EPS)
    v = ROTATIONS["small"]
    for kind in ["complex", "real"]:
        record(f"spherical: {kind} Wigner D, l <= 40, small rotation (|v| = 2.3e-3)",
               "spherical", worst["small", kind], euler_conditioning_bound(v, lmax),
               detail="tolerance l eps / sin(beta): Euler-angle conditioning of psh")


def test_wigner_D_high_degree_blocks(psh, record):
    """Single blocks at l = 100 and l = 500 (psh eval wigner-block, .npy)."""
    for l in [100, 500]:
        w = spherical.Wigner(l, ell_min=l)
        worst = {}
        for name in ["generic", "beta=pi", "small"]:
            v = ROTATIONS[name]
            R = quaternionic.array.from_rotation_vector(v)
            ref = psh_D_from_spherical(spherical_block(w, R, l))
            _, got = psh.npy("eval", "wigner-block", "--kind", "complex", "--l", l,
                             "--rotvec", rotvec_arg(v), out=f"d{l}.npy")
            worst[name, "complex"] = np.abs(pairs_to_complex(got) - ref).max()
            _, got_r = psh.npy("eval", "wigner-block", "--kind", "real", "--l", l,
                               "--rotvec", rotvec_arg(v), out=f"r{l}.npy")
            worst[name, "real"] = np.abs(got_r - real_D_from_complex(l, ref).real).max()
        for kind in ["complex", "real"]:
            # Rounding grows about like l eps (2.2e-14 at l = 100, 1.1e-13 at l = 500):
            # measured 1.6e-14 and 5.3e-14; tolerance 3 l eps.
            e = max(worst["generic", kind], worst["beta=pi", kind])
            record(f"spherical: {kind} Wigner D block l = {l}, rotations generic, beta=pi",
                   "spherical", e, 3 * l * EPS)
            record(f"spherical: {kind} Wigner D block l = {l}, small rotation",
                   "spherical", worst["small", kind],
                   euler_conditioning_bound(ROTATIONS["small"], l),
                   detail="tolerance l eps / sin(beta): Euler-angle conditioning of psh")


# Directions (theta, phi): the poles (theta = 0 and the double nearest pi), 1e-300
# from the north pole (the south pole is at pi, whose nearest doubles are pi - 1.2e-16
# and pi - 4.4e-16: no double lies closer), 1e-8 from both poles, and generic ones.
POINTS = np.array([
    [0.0, 0.4],
    [np.pi, 2.0],
    [1e-300, 1.1],
    [1e-8, -0.7],
    [np.pi - 1e-8, 0.3],
    [0.3, 0.2],
    [np.pi / 2, -2.5],
    [2.2, 3.0],
])


def test_swsh_l500(psh, record):
    """sY_lm for s = -3..3, l <= 500, at POINTS (psh eval swsh-points)."""
    lmax = 500
    w = spherical.Wigner(lmax, mp_max=3)
    pts = psh.save("points.npy", POINTS)
    R = [quaternionic.array.from_spherical_coordinates(t, p) for t, p in POINTS]
    l = np.concatenate([np.full(2 * k + 1, k) for k in range(lmax + 1)])
    bound = np.sqrt((2 * l + 1) / (4 * np.pi))  # |sY_lm| <= bound (unitarity of d^l)
    worst_all = worst_pole = 0.0
    for s in range(-3, 4):
        _, got = psh.npy("eval", "swsh-points", "--spin", s, "--lmax", lmax,
                         "--points", pts, out=f"swsh{s}.npy")
        got = pairs_to_complex(got)
        for i, r in enumerate(R):
            # psh's sY_lm (PSH (26)-(27), proofs/swsh.md) is spherical's sYlm at the
            # quaternion of the spherical coordinates, with no change of sign or
            # conjugation; both are zero for l < |s|.
            ref = w.sYlm(s, r)
            err = (np.abs(got[i] - ref) / bound).max()
            worst_all = max(worst_all, err)
            if i < 5:
                worst_pole = max(worst_pole, err)
    # Relative to the bound sqrt((2l+1)/(4 pi)) (6.3 at l = 500): measured 2.2e-14
    # overall (1e-8 from the poles) and the same at and near the poles; rounding of the
    # recursions in l grows like l eps = 1.1e-13, the tolerance.
    measure = "max abs error / sqrt((2l+1)/4pi)"
    record("spherical: sYlm s = -3..3, l <= 500, 8 directions", "spherical",
           worst_all, lmax * EPS, measure)
    record("spherical: sYlm at the poles, 1e-300 and 1e-8 from them", "spherical",
           worst_pole, lmax * EPS, measure)
