"""psh's Fresnel Mueller matrices and linear polarizer (psh::optics) against Mitsuba 3's
mueller module and conductor BSDF (variant scalar_spectral_polarized: single precision;
scalar_mono_polarized is not in the wheels)."""

import drjit as dr
import mitsuba as mi
import numpy as np
import pytest

from mappings import mitsuba_to_psh_frames

mi.set_variant("scalar_spectral_polarized")

F32 = float(np.finfo(np.float32).eps)  # Mitsuba's scalar variants compute in float32

CONDUCTORS = {  # eta = n + i k (k >= 0), roughly gold, aluminium, copper, iron at 550 nm
    "gold": (0.43, 2.45),
    "aluminium": (0.96, 6.69),
    "copper": (1.02, 2.58),
    "iron": (2.87, 3.05),
}
DIELECTRICS = {  # relative index eta_t / eta_i
    "glass from outside": 1.5,
    "water from outside": 1.333,
    "glass from inside (TIR beyond 41.8 deg)": 1 / 1.5,
}
COSINES = [1.0, 0.95, 0.8, 0.6, 0.5, 0.3, 0.1, 0.02]


def psh_fresnel(psh, n, k, cosines):
    out = psh.run("eval", "fresnel", "--n", repr(n), "--k", repr(k),
                  "--cos-i", ",".join(repr(float(c)) for c in cosines))["results"]
    return [(np.array(r["mueller_travel"]), np.array(r["mueller"])) for r in out]


def mitsuba_reflection(cos_i, n, k):
    """mi.mueller.specular_reflection in its s/p basis: travel frames [s, d x s, d] of the
    incident and the reflected ray (z along the direction of travel d)."""
    return np.array(mi.mueller.specular_reflection(cos_i, dr.scalar.Complex2f(n, k)))


def compare(psh, record, label, media):
    worst_travel = worst_psh = 0.0
    for name, (n, k) in media.items():
        cosines = list(COSINES)
        if k == 0 and n > 1:
            cosines.append(float(np.cos(np.arctan(n))))  # Brewster's angle
        for c, (travel, frames) in zip(cosines, psh_fresnel(psh, n, k, cosines)):
            m = mitsuba_reflection(c, n, k)
            worst_travel = max(worst_travel, np.abs(travel - m).max())
            worst_psh = max(worst_psh, np.abs(frames - mitsuba_to_psh_frames(m)).max())
    # Entries are bounded by 1; Mitsuba's Fresnel equations run in float32 (a complex
    # square root, divisions, products): measured 2.5e-7 (conductors) and 1.5e-7
    # (dielectrics), about 2 float32 eps = 2.4e-7; tolerance 8 float32 eps = 9.5e-7.
    record(f"Mitsuba: specular_reflection, {label}, travel frames (identity map)",
           "mitsuba", worst_travel, 8 * F32)
    record(f"Mitsuba: specular_reflection, {label}, psh frames (M diag(1,1,-1,-1))",
           "mitsuba", worst_psh, 8 * F32)


def test_conductors(psh, record):
    compare(psh, record, "4 conductors x 8 angles", CONDUCTORS)


def test_dielectrics(psh, record):
    compare(psh, record, "3 dielectrics x 9 angles", {k: (v, 0.0) for k, v in DIELECTRICS.items()})


def test_linear_polarizer(psh, record):
    """psh's LinearPolarizer(varphi) is Mitsuba's horizontal polarizer turned
    counterclockwise by varphi (mueller.rotated_element): in a frame [x, y, z] with z along
    the travel, y = z x x, counterclockwise as seen by the sensor facing the beam is the
    turn from x towards y; no change of sign."""
    worst = 0.0
    for phi in [0.0, 0.3, np.pi / 4, 1.0, np.pi / 2, 2.5, -0.7]:
        got = np.array(psh.run("eval", "polarizer", "--angle-deg", repr(float(np.degrees(phi))))["mueller"])
        ref = np.array(mi.mueller.rotated_element(phi, mi.mueller.linear_polarizer(1.0)))
        worst = max(worst, np.abs(got - ref).max())
    # float32 sines and cosines of 2 phi and their products: measured 4.4e-8
    # (0.4 float32 eps); tolerance 4 float32 eps.
    record("Mitsuba: linear_polarizer rotated by varphi, 7 angles", "mitsuba", worst, 4 * F32)


def local(theta, phi):
    return np.array([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)])


@pytest.mark.parametrize("name", ["gold", "iron"])
def test_conductor_bsdf_frames(psh, record, name):
    """End to end through Mitsuba's conductor BSDF: its sampled Mueller weight is expressed
    in Mitsuba's implicit Stokes bases (mueller.stokes_basis) of the incident travel
    direction -wo and of the outgoing wi; re-expressed with mueller.rotate_mueller_basis in
    the s/p travel frames (x = s = n x d normalized) it must be psh's mueller_travel, and
    with diag(1, 1, -1, -1) psh's mueller (frames z = w_i towards the source, z = w_o)."""
    n, k = CONDUCTORS[name]
    bsdf = mi.load_dict({"type": "conductor", "eta": n, "k": k})
    ctx = mi.BSDFContext()
    worst_travel = worst_psh = 0.0
    normal = np.array([0.0, 0.0, 1.0])
    for theta, phi in [(0.3, 0.2), (0.9, 2.0), (1.4, -1.0), (0.05, 0.7)]:
        wi = local(theta, phi)  # towards the camera: the reflected light travels along wi
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(*wi)
        si.wavelengths = mi.UnpolarizedSpectrum(550.0)
        bs, weight = bsdf.sample(ctx, si, 0.5, mi.Point2f(0.5, 0.5))
        wo = np.array(bs.wo)  # towards the light: the incident light travels along -wo
        d_in, d_out = -wo, wi
        s = np.cross(normal, d_in)
        s /= np.linalg.norm(s)
        m = mi.mueller.rotate_mueller_basis(
            weight, mi.Vector3f(*d_in), mi.mueller.stokes_basis(mi.Vector3f(*d_in)), mi.Vector3f(*s),
            mi.Vector3f(*d_out), mi.mueller.stokes_basis(mi.Vector3f(*d_out)), mi.Vector3f(*s))
        m = np.array(m)[..., 0] if np.array(m).ndim == 3 else np.array(m)
        travel, frames = psh_fresnel(psh, n, k, [float(wo[2])])[0]
        worst_travel = max(worst_travel, np.abs(travel - m).max())
        worst_psh = max(worst_psh, np.abs(frames - mitsuba_to_psh_frames(m)).max())
    # As specular_reflection, plus float32 frame rotations: measured 2.3e-7 (gold) and
    # 1.1e-7 (iron); tolerance 8 float32 eps.
    record(f"Mitsuba: conductor BSDF ({name}) in s/p travel frames, 4 directions", "mitsuba",
           worst_travel, 8 * F32)
    record(f"Mitsuba: conductor BSDF ({name}) in psh frames", "mitsuba", worst_psh, 8 * F32)


ROUGH = {  # (Mitsuba plugin, its parameters, psh's n, k). Mitsuba's roughdielectric is
    # not polarized (its eval is M00 alone); its polarized GGX dielectric reflection is
    # pplastic without the diffuse term.
    "gold roughconductor": ("roughconductor", {"eta": 0.43, "k": 2.45}, 0.43, 2.45),
    "glass pplastic, diffuse 0": ("pplastic", {
        "int_ior": 1.5, "ext_ior": 1.0,
        "diffuse_reflectance": {"type": "spectrum", "value": 0.0}}, 1.5, 0.0),
}


@pytest.mark.parametrize("name", sorted(ROUGH))
def test_rough_bsdf_masking(psh, record, name):
    """psh's GGX microfacet pBRDF (`psh eval microfacet`) against Mitsuba's rough BSDFs'
    eval: psh's `separable` masking is Mitsuba's G1 G1 (Mueller matrices within float32),
    while the height-correlated default differs at grazing angles. Mitsuba's eval is in the
    implicit Stokes bases of -wo (incident travel) and wi (outgoing); turned to psh's s/p
    frames (s = w_i x w_o normalized, psh's frame_in_x) and by diag(1, 1, -1, -1) on the
    input side (mitsuba_to_psh_frames). Values are scaled by the largest |M00|."""
    plugin, params, n, k = ROUGH[name]
    alpha = 0.3
    bsdf = mi.load_dict({"type": plugin, "distribution": "ggx", "alpha": alpha, **params})
    ctx = mi.BSDFContext()
    pairs = [((0.3, 0.2), (0.5, 2.9)), ((1.2, 0.0), (1.3, 2.6)), ((1.45, 1.0), (1.5, -1.9)),
             ((0.05, 0.7), (0.9, 0.4)), ((1.55, 0.3), (0.2, 3.0))]
    worst = {"separable": 0.0, "height-correlated": 0.0}
    for (ti, pi_), (to, po) in pairs:
        w_i, w_o = local(ti, pi_), local(to, po)  # psh: towards the source, the viewer
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(*w_o)
        si.wavelengths = mi.UnpolarizedSpectrum(550.0)
        m = np.array(bsdf.eval(ctx, si, mi.Vector3f(*w_i)))
        m = m[..., 0] if m.ndim == 3 else m
        d_in, d_out = -w_i, w_o
        for masking in worst:
            out = psh.run("eval", "microfacet", "--alpha", alpha, "--n", n, "--k", k,
                          "--masking", masking, "--wi", ",".join(repr(float(x)) for x in w_i),
                          "--wo", ",".join(repr(float(x)) for x in w_o))
            s = mi.Vector3f(*out["frame_in_x"])
            turned = np.array(mi.mueller.rotate_mueller_basis(
                mi.Matrix4f(m), mi.Vector3f(*d_in), mi.mueller.stokes_basis(mi.Vector3f(*d_in)), s,
                mi.Vector3f(*d_out), mi.mueller.stokes_basis(mi.Vector3f(*d_out)), s))
            got = np.array(out["mueller"])
            scale = max(abs(got[0, 0]), abs(turned[0, 0]), 1e-30)
            worst[masking] = max(worst[masking],
                                 np.abs(got - mitsuba_to_psh_frames(turned)).max() / scale)
    # float32 Fresnel, GGX and frame rotations relative to M00: 16 float32 eps.
    record(f"Mitsuba: {name} eval vs psh separable masking, 5 pairs (relative to M00)",
           "mitsuba", worst["separable"], 16 * F32,
           detail=f"height-correlated differs by {worst['height-correlated']:.2e}")
    assert worst["height-correlated"] > 100 * worst["separable"], \
        "the comparison must tell the two masking forms apart"
