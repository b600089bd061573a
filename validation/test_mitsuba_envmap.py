"""The Mitsuba 3 emitter `psh_stokes_envmap` (src/io/psh_stokes_envmap.py: a Stokes
environment map in psh's map-file format; derivation in
proofs/mitsuba-stokes-environment.md) against closed forms computed here from the texels
with plain vector geometry, never with the plugin's own conversion:

- the map seen by a camera: each pixel is its texel's Stokes vector carried from the stored
  frame [e_theta, -e_phi, -w] (docs/conventions.md, "Maps and files") to the `stokes`
  integrator's camera frame (x = ray.d x up, y = -ray.d x x: src/integrators/stokes.cpp);
- a smooth conductor sphere: the texel in the reflected direction through
  `mi.mueller.specular_reflection` in its s/p travel frames (as validation/test_mitsuba.py);
- an unpolarized map renders as Mitsuba's `envmap` given the same texels; a Lambertian
  plane under a bright spot converges to its irradiance summed texel by texel; sampled
  directions are distributed as `pdf_direction` says.

Pixels are deterministic: the `stratified` sampler without jitter at one sample per pixel
puts every camera ray through its pixel's centre and every wavelength sample at 0.5
(src/samplers/stratified.cpp), and the expected values use the rays of `Sensor.sample_ray`
at those positions; only pixels whose ray is at least MARGIN from the edges of its texel are
compared. Stokes frames change through coherency matrices (`restokes`), with psh's and
Mitsuba's `s2 + i s3 = 2 E_x conj(E_y)` (docs/conventions.md).

Variants: scalar_spectral_polarized (psh's validation variant); llvm_ad_mono_polarized and
llvm_ad_spectral_polarized where Dr.Jit's LLVM backend runs (a subprocess probes it: with
LLVM 15 it aborts the process, libLLVM 19 works; skipped otherwise); scalar_rgb for the
unpolarized closed form. In spectral variants the camera and sphere maps have one
chromaticity `BASE` (texel RGB = intensity x factor x BASE), so that every component
upsamples to a multiple of one spectrum; the film's value of that spectrum is measured from
the pixels (it is the RGB round trip of Mitsuba's `envmap` too).
"""

import importlib
import importlib.util
import pathlib

import drjit as dr
import mitsuba as mi
import numpy as np
import pytest

from mitsuba_plugin import PLUGIN, llvm_problem, load_plugin

ROOT = pathlib.Path(__file__).resolve().parent.parent
F32 = float(np.finfo(np.float32).eps)
#: Rec. 709 luminance, Mitsuba's `luminance` (include/mitsuba/core/spectrum.h).
LUMINANCE = np.array([0.212671, 0.715160, 0.072169])
#: The spectral maps' one chromaticity.
BASE = np.array([0.9, 0.55, 0.3])
#: Rays closer than this (radians) to a texel's edge are not compared.
MARGIN = 1e-3
#: A rotated `to_world`: 50 degrees about (1, 2, 3).
ROTATION = (np.array([1.0, 2.0, 3.0]), 50.0)
#: The map of psh's export for Mitsuba's `envmap` (docs/mitsuba.md): (x, y, z) -> (-z, x, y).
ENVMAP_AXES = np.array([[0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
GOLD = (0.43, 2.45)  # eta = n + i k, as validation/test_mitsuba.py
SPECTRAL, MONO, RGB = "scalar_spectral_polarized", "llvm_ad_mono_polarized", "scalar_rgb"
LLVM_SPECTRAL = "llvm_ad_spectral_polarized"


plugin = load_plugin(PLUGIN)


@pytest.fixture
def variant(request):
    """Sets the variant `request.param` (registering the plugin) and restores the one
    before (the other Mitsuba tests run in scalar_spectral_polarized)."""
    name = request.param
    if name.startswith("llvm") and llvm_problem():
        pytest.skip(f"Dr.Jit's LLVM backend does not run here ({llvm_problem()}); "
                    "libLLVM 16 or newer is needed, e.g. apt-get install libllvm19")
    previous = mi.variant()
    mi.set_variant(name)
    dr.set_thread_count(2)
    plugin.register()
    yield name
    if previous is not None:
        mi.set_variant(previous)


# -- maps ------------------------------------------------------------------------------


def write_map(directory, stokes, name="env"):
    """Four EXR files (float32 R, G, B) as psh writes them; the pattern for `filename`."""
    for p in range(4):
        mi.Bitmap(np.ascontiguousarray(stokes[p], dtype=np.float32)).write(
            str(directory / f"{name}_s{p}.exr"))
    return str(directory / f"{name}_s%d.exr")


def polarized_map(rng, height, one_chromaticity):
    """[4, H, 2H, 3], stored components: s0 in [0.5, 2], (s1, s2, s3) = s0 q with
    0.1 <= |q_k|, |q| <= 0.9 (every component non-zero, either sign, varying per texel). With
    `one_chromaticity` s0 = intensity x BASE and q per texel, else everything per channel."""
    shape = (height, 2 * height) + ((1,) if one_chromaticity else (3,))
    q = rng.uniform(0.1, 0.5, (3,) + shape) * rng.choice([-1.0, 1.0], (3,) + shape)
    s0 = rng.uniform(0.5, 2.0, shape) * (BASE if one_chromaticity else 1.0)
    stokes = np.concatenate([s0[None], q * s0], axis=0)
    return np.broadcast_to(stokes, (4, height, 2 * height, 3)).astype(np.float32)


def map_values(s, scale):
    """Stored Stokes vectors [..., 3, 4] (channel, component) as the variant now set renders
    them: luminance in mono ([..., 1, 4]), in spectral variants `s / BASE` times `scale` (the
    film's value of BASE's spectrum, measured), else the triple."""
    s = s.astype(np.float64)
    if mi.is_monochromatic:
        return np.einsum("c,...cp->...p", LUMINANCE, s)[..., None, :]
    if mi.is_spectral:
        return s / BASE[:, None] * scale[:, None]
    return s


# -- geometry (float64) ---------------------------------------------------------------------


def rotation(axis, degrees):
    """The rotation by `degrees` about `axis` (Rodrigues' formula)."""
    k = normalize(np.asarray(axis, dtype=np.float64))
    a = np.radians(degrees)
    cross = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(a) * cross + (1 - np.cos(a)) * cross @ cross


def transform(r):
    m = np.eye(4)
    m[:3, :3] = r
    return mi.ScalarTransform4f(m.tolist())


def normalize(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def texels(w, height):
    """Row and column (psh's Equirect::texel_at) of unit local directions `w` [N, 3], the
    distances in theta and in phi to the texel's nearest edges, and the angular distance."""
    rho = np.hypot(w[:, 0], w[:, 1])
    theta = np.arctan2(rho, w[:, 2])
    phi = np.mod(np.arctan2(w[:, 1], w[:, 0]), 2 * np.pi)
    x, y = theta / np.pi * height, phi / (2 * np.pi) * (2 * height)
    row = np.minimum(np.floor(x), height - 1).astype(int)
    col = np.minimum(np.floor(y), 2 * height - 1).astype(int)
    d_theta = np.abs(x - np.round(x)) * np.pi / height
    d_phi = np.abs(y - np.round(y)) * np.pi / height
    return row, col, d_theta, d_phi, np.minimum(d_theta, d_phi * rho)


def pole_weight(w):
    """min(1, sin theta / 0.25) of local directions `w`: the theta-phi frame turns by
    delta / sin theta for a direction error delta (float32: delta ~ 1e-7), so errors near the
    map's poles are weighted down by this factor."""
    return np.minimum(1.0, np.hypot(w[:, 0], w[:, 1]) / 0.25)


def stored_frame(w):
    """The file's frame at local directions `w` [N, 3]: x = e_theta, y = -e_phi (at the
    poles the limit along phi = 0), z = -w (docs/conventions.md)."""
    rho = np.hypot(w[:, 0], w[:, 1])
    safe = np.where(rho > 0, rho, 1.0)
    cos_phi, sin_phi = np.where(rho > 0, w[:, 0] / safe, 1.0), np.where(rho > 0, w[:, 1] / safe, 0.0)
    e_theta = np.stack([w[:, 2] * cos_phi, w[:, 2] * sin_phi, -rho], axis=1)
    e_phi = np.stack([-sin_phi, cos_phi, np.zeros_like(rho)], axis=1)
    return e_theta, -e_phi


def restokes(s, x0, y0, x1, y1):
    """Stokes vectors `s` [N, C, 4] measured in the frames (x0, y0) re-measured in (x1, y1)
    (same beam): coherency J = [[s0 + s1, s2 + i s3], [s2 - i s3, s0 - s1]] / 2 (J_xy =
    E_x conj(E_y)), field components E' = P E with P_ab = a' . b, J' = P J P^T."""
    j = np.empty(s.shape[:2] + (2, 2), dtype=complex)
    j[..., 0, 0], j[..., 1, 1] = (s[..., 0] + s[..., 1]) / 2, (s[..., 0] - s[..., 1]) / 2
    j[..., 0, 1] = (s[..., 2] + 1j * s[..., 3]) / 2
    j[..., 1, 0] = np.conj(j[..., 0, 1])
    dot = lambda a, b: np.einsum("ni,ni->n", a, b)  # noqa: E731
    p = np.stack([np.stack([dot(x1, x0), dot(x1, y0)], -1),
                  np.stack([dot(y1, x0), dot(y1, y0)], -1)], -2)[:, None]
    j = p @ j @ np.swapaxes(p, -1, -2)
    return np.stack([(j[..., 0, 0] + j[..., 1, 1]).real, (j[..., 0, 0] - j[..., 1, 1]).real,
                     2 * j[..., 0, 1].real, 2 * j[..., 0, 1].imag], axis=-1)


# -- rendering --------------------------------------------------------------------------


def camera(origin, target, up, fov, size):
    return {"type": "perspective", "fov": fov,
            "to_world": mi.ScalarTransform4f().look_at(origin=origin, target=target, up=up),
            "film": {"type": "hdrfilm", "width": size, "height": size, "rfilter": {"type": "box"},
                     "pixel_format": "luminance" if mi.is_monochromatic else "rgb"},
            "sampler": {"type": "stratified", "sample_count": 1, "jitter": False}}


def render(emitter, cameras, shapes=None, max_depth=1, spp=None, seed=0):
    """Per camera the Stokes images [H, W, C, 4] of the `stokes` integrator (in a variant
    without polarization [H, W, C, 1], the `path` integrator's); `spp` (an `independent`
    sampler) instead of the pixel centres. The plugin is given the scene (`set_scene`)."""
    path = {"type": "path", "max_depth": max_depth}
    scene = {"type": "scene", "emitter": emitter,
             "integrator": {"type": "stokes", "nested": path} if mi.is_polarized else path}
    for k, cam in enumerate(cameras):
        scene[f"sensor_{k}"] = dict(cam, **({"sampler": {"type": "independent", "sample_count": spp}}
                                             if spp else {}))
    scene.update(shapes or {})
    scene = mi.load_dict(scene)
    for e in scene.emitters():
        if isinstance(e, plugin.emitter_class()):
            e.set_scene(scene)
    out = []
    for k in range(len(cameras)):
        mi.render(scene, sensor=k, seed=seed)
        bitmap = scene.sensors()[k].film().bitmap()
        if mi.is_polarized:
            layers = dict(bitmap.split())
            out.append(np.stack([np.array(layers[f"S{p}"], dtype=np.float64)
                                 for p in range(4)], -1))
        else:
            out.append(np.array(bitmap, dtype=np.float64)[..., :3, None])
    return scene, out


def pixel_rays(sensor, size):
    """Origins, directions [size * size, 3] (row-major) of the rays through pixel centres."""
    u = (np.arange(size) + 0.5) / size
    xs, ys = np.meshgrid(u, u)
    if dr.is_jit_v(mi.Float):
        ray, _ = sensor.sample_ray(0.0, 0.5, mi.Point2f(mi.Float(xs.ravel()), mi.Float(ys.ravel())),
                                   mi.Point2f(0.5))
        return np.array(ray.o, dtype=np.float64).T, np.array(ray.d, dtype=np.float64).T
    rays = [sensor.sample_ray(0.0, 0.5, mi.Point2f(x, y), mi.Point2f(0.5))[0]
            for x, y in zip(xs.ravel(), ys.ravel())]
    return (np.array([list(r.o) for r in rays], dtype=np.float64),
            np.array([list(r.d) for r in rays], dtype=np.float64))


def camera_frame(sensor, d):
    """The `stokes` integrator's output frame for rays `d`: x = d x up, y = -d x x
    (src/integrators/stokes.cpp, `StokesIntegrator::sample`)."""
    up = np.array(sensor.world_transform().matrix, dtype=np.float64).reshape(4, 4)[:3, 1]
    x = normalize(np.cross(d, up))
    return x, np.cross(-d, x)


def emitter(filename, r):
    return {"type": "psh_stokes_envmap", "filename": filename, "to_world": transform(r)}


SIX_VIEWS = [((1, 0, 0), (0, 0, 1)), ((-1, 0, 0), (0, 0, 1)), ((0, 1, 0), (0, 0, 1)),
             ((0, -1, 0), (0, 0, 1)), ((0, 0, 1), (0, 1, 0)), ((0, 0, -1), (1, 0, 0))]


def spectral_scale(pixels, intensity, keep):
    """The film's value (per channel) of BASE's spectrum: s0 / intensity over the compared
    pixels (one value: the wavelength sample is 0.5 everywhere); and its spread."""
    ratio = pixels[keep][:, :, 0] / intensity[keep][:, None]
    scale = np.median(ratio, axis=0)
    return scale, float(np.abs(ratio / scale - 1).max())


# -- tests ---------------------------------------------------------------------------------


@pytest.mark.parametrize("variant", [SPECTRAL, MONO, LLVM_SPECTRAL], indirect=True)
@pytest.mark.parametrize("rotated", [False, True], ids=["identity", "rotated"])
def test_environment_seen_by_camera(variant, rotated, record, tmp_path):
    """Six 24 x 24 views at 90 degrees cover the sphere; every pixel is its texel's Stokes
    vector in the camera's frame: restokes from [R e_theta, -R e_phi] at w = R^T ray.d."""
    rng = np.random.default_rng(11)
    height, size = 8, 24
    stokes = polarized_map(rng, height, mi.is_spectral)
    r = rotation(*ROTATION) if rotated else np.eye(3)
    cams = [camera((0, 0, 0), t, u, 90, size) for t, u in SIX_VIEWS]
    scene, images = render(emitter(write_map(tmp_path, stokes), r), cams)
    got, want_rgb, intensity, keep, weight = [], [], [], [], []
    for k, image in enumerate(images):
        sensor = scene.sensors()[k]
        _, d = pixel_rays(sensor, size)
        d = normalize(d)
        w = d @ r  # R^T d: the camera looks towards the source
        row, col, _, _, to_edge = texels(w, height)
        a, b = stored_frame(w)
        x, y = camera_frame(sensor, d)
        s = np.moveaxis(stokes[:, row, col, :], 0, -1)  # [N, 3, 4]
        want_rgb.append((s, a @ r.T, b @ r.T, x, y))
        intensity.append(stokes[0, row, col, 0] / (BASE[0] if mi.is_spectral else 1.0))
        got.append(image.reshape(size * size, -1, 4))
        keep.append(to_edge > MARGIN)
        weight.append(pole_weight(w))
    got, keep, intensity = np.concatenate(got), np.concatenate(keep), np.concatenate(intensity)
    weight = np.concatenate(weight)[:, None, None]
    scale = np.ones(3)
    if mi.is_spectral:
        scale, spread = spectral_scale(got, intensity, keep)
        # One wavelength sample for every pixel: s0 / intensity is one number per channel,
        # to float32 rounding of the upsampling and the film (measured up to 7.8e-7).
        record(f"{variant}: envmap plugin, camera view, s0 / texel intensity is one value "
               "per channel", "mitsuba", spread, 16 * F32, measure="max relative spread")
    want = np.concatenate([restokes(map_values(s, scale), a, b, x, y)
                           for s, a, b, x, y in want_rgb])
    err = (weight * np.abs(got - want))[keep].max(axis=(0, 1)) / np.abs(want[keep][..., 0]).max()
    # float32 directions, frames and rotations in the plugin and the integrator, weighted
    # by pole_weight: measured up to 5.9e-7 of the largest s0; tolerance 16 float32 eps.
    # A sign error in s2 or in the turn is O(1).
    for p in range(4):
        record(f"{variant}: envmap plugin, camera view ({'rotated' if rotated else 'identity'} "
               f"to_world), s{p} vs the texel's in camera frames, {int(keep.sum())} pixels",
               "mitsuba", err[p], 16 * F32, measure="max abs error x pole weight / max s0")


@pytest.mark.parametrize("variant", [SPECTRAL, MONO, LLVM_SPECTRAL], indirect=True)
@pytest.mark.parametrize("rotated", [False, True], ids=["identity", "rotated"])
def test_conductor_sphere(variant, rotated, record, tmp_path):
    """A smooth gold sphere (`conductor`, eta 0.43 + 2.45i at every wavelength) seen from
    three sides: the texel in the reflected direction, re-measured in the s/p frame of the
    incident light [s, d_in x s] (s = n x d_in normalized), Mitsuba's
    specular_reflection(cos_i) to the s/p frame of the reflected light [s, d_out x s], then
    the camera's frame. The background pixels give the spectral film's value of BASE."""
    rng = np.random.default_rng(12)
    height, size = 8, 32
    stokes = polarized_map(rng, height, mi.is_spectral)
    r = rotation(*ROTATION) if rotated else np.eye(3)
    cams = [camera(tuple(4 * np.array(o)), (0, 0, 0), u, 35, size)
            for o, u in [((0.3, -1, 0.5), (0, 0, 1)), ((-1, 0.4, -0.2), (0, 0, 1)),
                         ((0.2, 0.3, 1), (0, 1, 0))]]
    sphere = {"type": "sphere", "bsdf": {"type": "conductor", "eta": GOLD[0], "k": GOLD[1]}}
    scene, images = render(emitter(write_map(tmp_path, stokes), r), cams,
                           shapes={"sphere": sphere}, max_depth=2)
    msp = importlib.import_module("mitsuba.scalar_spectral_polarized")
    eta = dr.scalar.Complex2f(*GOLD)
    got, chains, counts, background, intensity, weight = [], [], [], [], [], []
    for k, image in enumerate(images):
        sensor = scene.sensors()[k]
        o, d = pixel_rays(sensor, size)
        d = normalize(d)
        pixels = image.reshape(size * size, -1, 4)
        b = np.einsum("ni,ni->n", o, d)
        disc = b * b - (np.einsum("ni,ni->n", o, o) - 1)
        hit = disc > 0
        n = normalize(o + (-b - np.sqrt(np.where(hit, disc, 0)))[:, None] * d)
        cos_i = -np.einsum("ni,ni->n", d, n)
        source = np.where(hit[:, None], d + 2 * cos_i[:, None] * n, d)  # towards the source
        w = source @ r
        row, col, _, _, to_edge = texels(w, height)
        sphere_px = hit & (cos_i > 0.1) & (to_edge > MARGIN)
        background.append(pixels[~hit & (to_edge > MARGIN)])
        intensity.append(stokes[0, row, col, 0][~hit & (to_edge > MARGIN)]
                         / (BASE[0] if mi.is_spectral else 1.0))
        a, bb = stored_frame(w)
        d_in, d_out = -source, -d  # travel directions of the incident and reflected light
        s_axis = normalize(np.cross(n, d_in))
        x, y = camera_frame(sensor, d)
        m = np.array([np.array(msp.mueller.specular_reflection(float(c), eta))
                      for c in cos_i[sphere_px]])
        idx = np.flatnonzero(sphere_px)
        chains.append((np.moveaxis(stokes[:, row, col, :], 0, -1)[idx], a[idx] @ r.T,
                       bb[idx] @ r.T, s_axis[idx], np.cross(d_in, s_axis)[idx],
                       np.cross(d_out, s_axis)[idx], x[idx], y[idx], m))
        got.append(pixels[idx])
        counts.append(len(idx))
        weight.append(pole_weight(w[idx]))
    scale = np.ones(3)
    if mi.is_spectral:
        bg, inten = np.concatenate(background), np.concatenate(intensity)
        scale, spread = spectral_scale(bg, inten, np.ones(len(inten), dtype=bool))
        # As in the camera views (measured up to 7.8e-7).
        record(f"{variant}: envmap plugin, sphere views' background, s0 / texel intensity is "
               "one value per channel", "mitsuba", spread, 16 * F32, measure="max relative spread")
    want = []
    for s, a, b, s_axis, p_in, p_out, x, y, m in chains:
        incident = restokes(map_values(s, scale), a, b, s_axis, p_in)
        reflected = np.einsum("nij,ncj->nci", m, incident)
        want.append(restokes(reflected, s_axis, p_out, x, y))
    got, want = np.concatenate(got), np.concatenate(want)
    weight = np.concatenate(weight)[:, None, None]
    err = (weight * np.abs(got - want)).max(axis=(0, 1)) / np.abs(want[..., 0]).max()
    # As the camera views, plus Mitsuba's float32 intersection, reflection and Fresnel
    # (8 float32 eps in test_mitsuba.py): measured up to 1.5e-6 of the largest s0;
    # tolerance 32 float32 eps. A sign error in s2 or s3 is O(0.1).
    for p in range(4):
        record(f"{variant}: envmap plugin, gold sphere ({'rotated' if rotated else 'identity'} "
               f"to_world), s{p} vs Mueller calculus, {sum(counts)} pixels", "mitsuba", err[p],
               32 * F32, measure="max abs error x pole weight / max s0")


@pytest.mark.parametrize("variant", [SPECTRAL, MONO, LLVM_SPECTRAL], indirect=True)
def test_unpolarized_map_as_envmap(variant, record, tmp_path):
    """An unpolarized map with a colour per texel and channel, rotated, seen in six views:
    the plugin renders what Mitsuba's `envmap` renders given the same texels on a grid 16
    times finer (texel (r, k) at theta = pi r/(H' - 1), phi = 2 pi (k + 1/2)/W' of the map,
    `to_world` R times psh's export axes), away from the coarse texels' edges by 1.5 fine
    texels (where `envmap` interpolates between equal values); s1, s2, s3 are zero."""
    rng = np.random.default_rng(13)
    height, fine, size = 8, 16, 24
    stokes = polarized_map(rng, height, False)
    stokes[1:] = 0
    r = rotation(*ROTATION)
    rows, cols = fine * height + 1, 2 * fine * height
    theta = np.pi * np.arange(rows) / (rows - 1)
    phi = 2 * np.pi * (np.arange(cols) + 0.5) / cols
    tt, pp = np.meshgrid(theta, phi, indexing="ij")
    nodes = np.stack([np.sin(tt) * np.cos(pp), np.sin(tt) * np.sin(pp), np.cos(tt)], -1)
    row, col, *_ = texels(nodes.reshape(-1, 3), height)
    fine_s0 = stokes[0, row, col, :].reshape(rows, cols, 3)
    cams = [camera((0, 0, 0), t, u, 90, size) for t, u in SIX_VIEWS]
    _, ours = render(emitter(write_map(tmp_path, stokes), r), cams)
    scene, theirs = render({"type": "envmap", "bitmap": mi.Bitmap(np.ascontiguousarray(fine_s0)),
                            "to_world": transform(r @ ENVMAP_AXES)}, cams)
    keep = []
    for k in range(len(cams)):
        _, d = pixel_rays(scene.sensors()[k], size)
        _, _, d_theta, d_phi, _ = texels(normalize(d) @ r, height)
        keep.append((d_theta > 1.5 * np.pi / (rows - 1)) & (d_phi > 1.5 * 2 * np.pi / cols))
    keep = np.concatenate(keep)
    ours = np.concatenate([x.reshape(size * size, -1, 4) for x in ours])[keep]
    theirs = np.concatenate([x.reshape(size * size, -1, 4) for x in theirs])[keep]
    # The same float32 spectrum (the coefficients and scale of envmap's constructor, to the
    # bit), bilinearly interpolated between equal values by envmap: measured 0 (spectral)
    # and 1.2e-7 (mono: the luminance in float64 here, in float32 in envmap); tolerance
    # 8 float32 eps.
    record(f"{variant}: envmap plugin vs Mitsuba's envmap, unpolarized map, s0, "
           f"{int(keep.sum())} pixels", "mitsuba",
           float(np.abs(ours[..., 0] - theirs[..., 0]).max() / np.abs(theirs[..., 0]).max()),
           8 * F32, measure="max abs difference / max s0")
    record(f"{variant}: envmap plugin, unpolarized map, s1..s3", "mitsuba",
           float(np.abs(ours[..., 1:]).max()), 0.0, measure="max abs")


def plane_scene(emitter_dict, spp, seed):
    """A Lambertian plane (reflectance 0.5, normal +z) filling a 16 x 16 view from above."""
    cam = camera((0, 0, 3), (0, 0, 0), (0, 1, 0), 30, 16)
    plane = {"type": "rectangle", "to_world": mi.ScalarTransform4f().scale([10, 10, 1]),
             "bsdf": {"type": "diffuse", "reflectance": 0.5}}
    scene, images = render(emitter_dict, [cam], shapes={"plane": plane}, max_depth=2, spp=spp,
                           seed=seed)
    return scene, images[0][..., 0].reshape(-1, images[0].shape[2])


def bright_spot_map(height, one_chromaticity):
    """A polarized map (`polarized_map`) whose s0, averaged over the channels, is 0.02 but
    for four bright texels above the horizon (50 to 400) and one below (1000)."""
    rng = np.random.default_rng(14)
    stokes = polarized_map(rng, height, one_chromaticity)
    dim = np.full((height, 2 * height, 1), 0.02)
    for (i, j), v in {(0, 3): 400.0, (1, 9): 50.0, (2, 14): 120.0, (3, 5): 80.0,
                      (6, 2): 1000.0}.items():
        dim[i, j] = v
    return (stokes * dim / stokes[0].mean(axis=-1, keepdims=True)).astype(np.float32)


@pytest.mark.parametrize("variant", [SPECTRAL, RGB, MONO, LLVM_SPECTRAL], indirect=True)
def test_lambertian_plane_under_bright_spot(variant, record, tmp_path):
    """Emitter and BSDF sampling (MIS) on a Lambertian plane under a polarized map with a
    few bright texels: the mean pixel converges to 0.5/pi times the irradiance, the sum over
    the texels above the horizon of radiance times (sin^2 t1 - sin^2 t0)/2 2 pi/W (exact).
    In the spectral variant the reference is the same plane under a uniform map of the same
    irradiance (the film's RGB round trip cancels)."""
    height = 8
    stokes = bright_spot_map(height, mi.is_spectral)
    filename = write_map(tmp_path, stokes)
    spp = 4096 if dr.is_jit_v(mi.Float) else 256
    _, pixels = plane_scene(emitter(filename, np.eye(3)), spp, 1)
    t = np.pi * np.arange(height + 1) / height
    projected = (np.sin(t[1:]) ** 2 - np.sin(t[:-1]) ** 2) / 2 * (np.pi / height)
    upper = slice(0, height // 2)
    radiance = map_values(np.moveaxis(stokes[:, upper], 0, -1), np.ones(3))[..., 0]
    irradiance = np.einsum("i,ijc->c", projected[upper], radiance)
    mean, sigma = pixels.mean(axis=0), pixels.std(axis=0) / np.sqrt(len(pixels))
    if mi.is_spectral:
        uniform = np.zeros_like(stokes)
        uniform[0] = irradiance / np.pi * BASE
        _, ref = plane_scene(emitter(write_map(tmp_path, uniform, "uniform"), np.eye(3)), spp, 2)
        want, sigma = ref.mean(axis=0), np.hypot(sigma, ref.std(axis=0) / np.sqrt(len(ref)))
    else:
        want = 0.5 / np.pi * irradiance
    z = float(np.abs(mean - want).max() / sigma.max())
    # Independent samples: within 4 standard errors of the mean (its measured relative
    # standard error is given in the detail).
    record(f"{variant}: envmap plugin, Lambertian plane under a bright-spot map, mean s0 vs "
           f"{'the same plane under a uniform map' if mi.is_spectral else 'closed form'}",
           "mitsuba", z, 4.0, measure="max |difference| / standard error",
           detail=f"{spp} spp, relative standard error {float((sigma / want).max()):.1e}")


def sampled(emitter_obj, u):
    """sample_direction at the sample points u [N, 2]: directions [N, 3], pdfs, s0 of
    weight x pdf, pdf_direction and s0 of eval_direction at the sampled directions."""
    it = dr.zeros(mi.Interaction3f)
    it.wavelengths = dr.full(mi.UnpolarizedSpectrum, 550.0) if mi.is_spectral else it.wavelengths

    def s0(spec):  # at the first wavelength (or the channel), per lane
        a = np.array(mi.unpolarized_spectrum(spec), dtype=np.float64)
        return a.reshape(a.shape[0], -1)[0]

    if dr.is_jit_v(mi.Float):
        ds, weight = emitter_obj.sample_direction(it, mi.Point2f(mi.Float(u[:, 0]), mi.Float(u[:, 1])))
        return (np.array(ds.d, dtype=np.float64).T, np.array(ds.pdf, dtype=np.float64),
                s0(weight) * np.array(ds.pdf), np.array(emitter_obj.pdf_direction(it, ds)),
                s0(emitter_obj.eval_direction(it, ds)))
    out = []
    for a, b in u:
        ds, weight = emitter_obj.sample_direction(it, mi.Point2f(a, b))
        out.append((list(ds.d), ds.pdf, s0(weight)[0] * ds.pdf,
                    emitter_obj.pdf_direction(it, ds), s0(emitter_obj.eval_direction(it, ds))[0]))
    d, pdf, weighted, pdf2, value = zip(*out)
    return np.array(d), np.array(pdf), np.array(weighted), np.array(pdf2), np.array(value)


def stokes_of(spec):
    """The Stokes vectors [N, 4] (first wavelength or channel) in the first column of a
    polarized `Spectrum` of width N (scalar variants: N = 1)."""
    m = np.array(spec, dtype=np.float64)
    m = m if dr.is_jit_v(mi.Float) else m[..., None]
    return m.reshape(4, 4, -1, m.shape[-1])[:, 0, 0].T


def sampled_weights(emitter_obj, u, wavelengths):
    """The Stokes weights [N, 4] of sample_direction at u [N, 2] and the wavelengths of
    `ray_samples` (spectral variant)."""
    it = dr.zeros(mi.Interaction3f)
    if dr.is_jit_v(mi.Float):
        it.wavelengths = wavelengths
        return stokes_of(emitter_obj.sample_direction(
            it, mi.Point2f(mi.Float(u[:, 0]), mi.Float(u[:, 1])))[1])
    out = []
    for (a, b), lam in zip(u, wavelengths):
        it.wavelengths = lam
        out.append(stokes_of(emitter_obj.sample_direction(it, mi.Point2f(a, b))[1]))
    return np.concatenate(out)


def ray_samples(emitter_obj, u, v):
    """sample_ray with direction samples u and disk samples v [N, 2]: directions, origins
    [N, 3], Stokes weights [N, 4] and the rays' wavelengths."""
    if dr.is_jit_v(mi.Float):
        ray, weight = emitter_obj.sample_ray(
            0.0, 0.5, mi.Point2f(mi.Float(v[:, 0]), mi.Float(v[:, 1])),
            mi.Point2f(mi.Float(u[:, 0]), mi.Float(u[:, 1])))
        return (np.array(ray.d, dtype=np.float64).T, np.array(ray.o, dtype=np.float64).T,
                stokes_of(weight), ray.wavelengths)
    out = [emitter_obj.sample_ray(0.0, 0.5, mi.Point2f(*b), mi.Point2f(*a)) for a, b in zip(u, v)]
    return (np.array([list(ray.d) for ray, _ in out]), np.array([list(ray.o) for ray, _ in out]),
            np.concatenate([stokes_of(w) for _, w in out]), [ray.wavelengths for ray, _ in out])


@pytest.mark.parametrize("variant", [SPECTRAL, MONO, LLVM_SPECTRAL], indirect=True)
def test_sampling_density(variant, record, tmp_path):
    """sample_direction against pdf_direction and the closed form P(texel) =
    max(luminance(s0), 0) Omega / sum (rotated map, colour per channel; luminance over three
    decades; four texels dark or negative): histogram over texels halved in cos theta and
    phi, the pdf of each sample, the weight times pdf against eval_direction, the pdf
    integrated over texel centres; and sample_ray against sample_direction."""
    rng = np.random.default_rng(15)
    height = 8
    stokes = polarized_map(rng, height, False)
    stokes *= (10.0 ** rng.uniform(-1.5, 1.5, (height, 2 * height, 1))).astype(np.float32)
    for i, j, v in [(0, 0, 0.0), (3, 7, 0.0), (5, 2, -1.0), (7, 15, -0.5)]:
        stokes[:, i, j] = v
    r = rotation(*ROTATION)
    scene = mi.load_dict({"type": "scene", "e": emitter(write_map(tmp_path, stokes), r)})
    e = scene.emitters()[0]
    n = 400_000 if dr.is_jit_v(mi.Float) else 40_000
    u = rng.random((n, 2))
    d, pdf, weighted, pdf2, value = sampled(e, u)
    t = np.pi * np.arange(height + 1) / height
    omega = (np.cos(t[:-1]) - np.cos(t[1:])) * np.pi / height
    lum = np.maximum(stokes[0].astype(np.float64) @ LUMINANCE, 0) * omega[:, None]
    prob = lum / lum.sum()
    w = normalize(d) @ r
    row, col, *_ = texels(w, height)
    sub_t = np.minimum((2 * (np.cos(t[row]) - w[:, 2]) / (np.cos(t[row]) - np.cos(t[row + 1]))
                        ).astype(int), 1)
    phi = np.mod(np.arctan2(w[:, 1], w[:, 0]), 2 * np.pi) / (2 * np.pi) * (2 * height)
    sub_p = np.minimum(((phi - col) * 2).astype(int), 1)
    counts = np.zeros((height, 2 * height, 2, 2))
    np.add.at(counts, (row, col, sub_t, sub_p), 1)
    expect = np.repeat(np.repeat((n * prob / 4)[..., None], 2, -1)[..., None], 2, -1)
    # Cells expecting at least 25 samples one by one, the others pooled (Poisson counts
    # near normal): for a correct sampler the largest of at most 513 |z| exceeds 5 with
    # probability about 3e-4.
    big = expect >= 25
    z = np.append(np.abs(counts - expect)[big] / np.sqrt(expect[big]),
                  abs(counts[~big].sum() - expect[~big].sum()) / np.sqrt(expect[~big].sum()))
    record(f"{variant}: envmap plugin, sampled directions per half-texel cell vs "
           f"P(texel)/4, {n} samples, {int(big.sum())} cells and the rest pooled", "mitsuba",
           float(z.max()), 5.0, measure="max |count - expected| / sqrt(expected)")
    record(f"{variant}: envmap plugin, samples in texels of s0 <= 0", "mitsuba",
           float(counts[expect == 0].sum()), 0.0, measure="count")
    want_pdf = prob[row, col] / omega[row]
    record(f"{variant}: envmap plugin, ds.pdf and pdf_direction vs P(texel) / Omega",
           "mitsuba", float(max(np.abs(pdf / want_pdf - 1).max(), np.abs(pdf2 / want_pdf - 1).max())),
           16 * F32, measure="max relative error")
    # weight = eval / pdf: float32 division and product.
    record(f"{variant}: envmap plugin, sample_direction weight x pdf vs eval_direction, s0",
           "mitsuba", float(np.abs(weighted / value - 1).max()), 4 * F32,
           measure="max relative error")
    # The pdf over the sphere: pdf_direction at every texel's centre times Omega, summed.
    tc, pc = np.meshgrid((t[:-1] + t[1:]) / 2, np.pi * (np.arange(2 * height) + 0.5) / height,
                         indexing="ij")
    centres = np.stack([np.sin(tc) * np.cos(pc), np.sin(tc) * np.sin(pc), np.cos(tc)], -1)
    directions = centres.reshape(-1, 3) @ r.T
    it = dr.zeros(mi.Interaction3f)
    if dr.is_jit_v(mi.Float):
        ds = dr.zeros(mi.DirectionSample3f, len(directions))
        ds.d = mi.Vector3f(*[mi.Float(directions[:, k]) for k in range(3)])
        pdfs = np.array(e.pdf_direction(it, ds), dtype=np.float64)
    else:
        pdfs = []
        for v in directions:
            ds = mi.DirectionSample3f()
            ds.d = mi.Vector3f(*v)
            pdfs.append(e.pdf_direction(it, ds))
        pdfs = np.array(pdfs)
    total = float((pdfs.reshape(height, 2 * height) * omega[:, None]).sum())
    record(f"{variant}: envmap plugin, pdf_direction integrated over the sphere (texel "
           "centres x Omega)", "mitsuba", abs(total - 1), 16 * F32, measure="|sum - 1|")
    # sample_ray with the same direction samples, after set_scene: a ray along -ds.d from
    # the disk of radius r facing the source at distance r from the centre, weighted by
    # pi r^2 / pdf (in the spectral variant the Stokes ratios at the ray's wavelengths: its
    # weight divides by their pdf).
    scene = mi.load_dict({"type": "scene", "e": emitter(str(tmp_path / "env_s%d.exr"), r),
                          "ball": {"type": "sphere", "center": [1, 2, 3], "radius": 2}})
    e = scene.emitters()[0]
    e.set_scene(scene)
    m = 2000
    d, pdf, *_ = sampled(e, u[:m])
    rays = ray_samples(e, u[:m], rng.random((m, 2)))
    centre = np.array([1.0, 2.0, 3.0])
    # The bounding sphere of the bounding box, enlarged as envmap::set_scene does.
    radius = np.linalg.norm(np.array(scene.bbox().max) - centre) * (1 + mi.math.RayEpsilon)
    weights = sampled_weights(e, u[:m], rays[3])
    along = np.einsum("ni,ni->n", rays[1] - centre, d)
    geometry = max(np.abs(rays[0] + d).max(), np.abs(along / radius - 1).max(),
                   (np.linalg.norm(rays[1] - centre - along[:, None] * d, axis=1) / radius - 1).max())
    record(f"{variant}: envmap plugin, sample_ray direction and origin (set_scene's sphere)",
           "mitsuba", float(geometry), 16 * F32, measure="max abs error (unit vectors, / r)")
    if mi.is_spectral:
        got, want = rays[2][:, 1:] / rays[2][:, :1], weights[:, 1:] / weights[:, :1]
    else:
        got, want = rays[2], weights * np.pi * radius ** 2
    record(f"{variant}: envmap plugin, sample_ray weight vs sample_direction's x pi r^2"
           + (" (Stokes ratios)" if mi.is_spectral else ""), "mitsuba",
           float(np.abs(got - want).max() / np.abs(want).max()), 16 * F32,
           measure="max abs error / max")


@pytest.mark.parametrize("variant", [SPECTRAL], indirect=True)
def test_file_forms_and_dark_map(variant, record, tmp_path, monkeypatch):
    """The same map as four files named by %d or by one of them (_s2), as one EXR with
    layers S0..S3, grey as one Y channel per file, and named relative to a scene file loaded
    from elsewhere emits the same, and twice that with `scale` 2; a cube cross and two %d
    are refused; a map without light samples nothing and renders black."""
    rng = np.random.default_rng(16)
    height = 4
    stokes = polarized_map(rng, height, True)
    grey = np.repeat(stokes[..., :1], 3, axis=-1)
    write_map(tmp_path, stokes)
    layered = tmp_path / "layers.exr"
    mi.Bitmap(np.ascontiguousarray(np.concatenate(list(stokes), axis=-1)),
              mi.Bitmap.PixelFormat.MultiChannel,
              [f"S{p}.{c}" for p in range(4) for c in "RGB"]).write(str(layered))
    for p in range(4):
        mi.Bitmap(np.ascontiguousarray(grey[p, ..., :1]), mi.Bitmap.PixelFormat.Y).write(
            str(tmp_path / f"y_s{p}.exr"))
    write_map(tmp_path, grey, "grey")
    si = dr.zeros(mi.SurfaceInteraction3f)
    si.wavelengths = dr.full(mi.UnpolarizedSpectrum, 550.0)
    directions = normalize(rng.normal(size=(20, 3)))

    def radiance(filename, scale=1.0):
        e = mi.load_dict({"type": "scene", "e": {"type": "psh_stokes_envmap", "scale": scale,
                                                 "filename": str(filename)}}).emitters()[0]
        return evaluate(e)

    def evaluate(e):
        out = []
        for v in directions:
            si.wi = mi.Vector3f(*v)
            out.append(np.array(e.eval(si)))
        return np.array(out)

    four = radiance(tmp_path / "env_s%d.exr")
    worst = max(np.abs(radiance(tmp_path / "env_s2.exr") - four).max(),
                np.abs(radiance(layered) - four).max(),
                np.abs(radiance(tmp_path / "y_s%d.exr") - radiance(tmp_path / "grey_s%d.exr")).max())
    xml = tmp_path / "scene.xml"
    xml.write_text('<scene version="3.0.0"><emitter type="psh_stokes_envmap">'
                   '<string name="filename" value="env_s%d.exr"/></emitter></scene>')
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    worst = max(worst, np.abs(evaluate(mi.load_file(str(xml)).emitters()[0]) - four).max(),
                np.abs(radiance(tmp_path / "env_s%d.exr", 2.0) - 2 * four).max())
    record(f"{variant}: envmap plugin, file forms (%d, _s2, layers S0..S3, Y channel, "
           "relative to scene.xml; scale 2 doubles)",
           "mitsuba", float(worst), 0.0, measure="max abs difference")
    cross = np.zeros((4, 6, 8, 3), dtype=np.float32)
    refused = 0
    for name in [write_map(tmp_path, cross, "cross"), str(tmp_path / "a_%d_%d.exr")]:
        with pytest.raises(RuntimeError, match="equirectangular|exactly one %d"):
            mi.load_dict({"type": "psh_stokes_envmap", "filename": name})
        refused += 1
    record(f"{variant}: envmap plugin, a cube cross and a pattern with two %d refused",
           "mitsuba", 2 - refused, 0, measure="files accepted")
    dark = np.zeros_like(stokes)
    scene, pixels = plane_scene(emitter(write_map(tmp_path, dark, "dark"), np.eye(3)), 4, 3)
    ds, weight = scene.emitters()[0].sample_direction(dr.zeros(mi.Interaction3f),
                                                      mi.Point2f(0.3, 0.7))
    record(f"{variant}: envmap plugin, a map without light: pdf, weight and the plane",
           "mitsuba", float(max(ds.pdf, np.abs(np.array(weight)).max(), np.abs(pixels).max())),
           0.0, measure="max abs")
