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


# psh builds D from ZYZ Euler angles taken from the unit quaternion
# (proofs/euler-angles.md), so the small rotation needs no allowance: every rotation is
# held to the same bound (the small one, formerly allowed l eps / sin(beta) for the
# Euler-angle loss, to the edge sweep's 10 l eps; test_edges.py has the full sweep).
WELL_CONDITIONED = ["generic", "beta=pi", "about z"]
EPS = np.finfo(float).eps


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
    for kind in ["complex", "real"]:
        # The edge sweep's bound 10 l eps (test_edges.py).
        record(f"spherical: {kind} Wigner D, l <= 40, small rotation (|v| = 2.3e-3)",
               "spherical", worst["small", kind], 10 * lmax * EPS)


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
            # The edge sweep's bound 10 l eps (test_edges.py).
            record(f"spherical: {kind} Wigner D block l = {l}, small rotation",
                   "spherical", worst["small", kind], 10 * l * EPS)


# Directions (theta, phi): the poles (theta = 0 and the double nearest pi), 1e-300
# from the north pole (the south pole is at pi, whose nearest doubles are pi - 1.2e-16
# and pi - 4.4e-16: no double lies closer), 1e-12, 1e-8 and 1e-4 from the north pole and
# 1e-8 from the south one (the polar angles of the edge sweep, test_edges.py), and
# generic ones.
POINTS = np.array([
    [0.0, 0.4],
    [np.pi, 2.0],
    [1e-300, 1.1],
    [1e-8, -0.7],
    [np.pi - 1e-8, 0.3],
    [1e-12, -0.7],
    [1e-4, 0.3],
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
            if i < 7:
                worst_pole = max(worst_pole, err)
    # Relative to the bound sqrt((2l+1)/(4 pi)) (6.3 at l = 500): measured 2.2e-14
    # overall (1e-8 from the poles) and the same at and near the poles; rounding of the
    # recursions in l grows like l eps = 1.1e-13, the tolerance.
    measure = "max abs error / sqrt((2l+1)/4pi)"
    record(f"spherical: sYlm s = -3..3, l <= 500, {len(POINTS)} directions", "spherical",
           worst_all, lmax * EPS, measure)
    record("spherical: sYlm at the poles, 1e-300, 1e-12, 1e-8 and 1e-4 from them", "spherical",
           worst_pole, lmax * EPS, measure)
