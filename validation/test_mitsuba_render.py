"""psh's renders against Mitsuba 3 (PSH Sec. 7, Fig. 19): the scene of
`scenes/mitsuba_sphere.toml` (a GGX conductor sphere of one complex index under a constant
unpolarized environment, a scene both renderers express identically) rendered by
Mitsuba 3 (`scalar_spectral_polarized`, `stokes` over `path` with max_depth 2: one bounce),
by psh's reference renderer (`psh render --reference`) and by PPRT at a ladder of band
limits. Writes docs/mitsuba.md (the series of PSH Fig. 19 against Mitsuba 3).

Conventions: both write Stokes components in the camera's frames with x image-right,
y image-up and z along the light's travel towards the camera (psh: docs/conventions.md;
Mitsuba 3: the `stokes` integrator turns its result to the sensor's x axis and up vector,
`mueller.h` observes the ellipse looking back along the propagation). Mitsuba's constant
emitter is an RGB-upsampled spectrum: its images are divided per channel by the mean of
their background pixels, where psh's environment is exactly 1. The comparison is over the
pixels whose centre ray meets the sphere at least two pixels inside its silhouette
(Mitsuba filters each pixel over its area, psh samples its centre). Masking: psh's GGX
uses the height-correlated Smith term, Mitsuba's `roughconductor` the separable G1 G1; the
test of the mean bounds their difference together with any other bias.
"""

import pathlib
import time
import tomllib

import drjit as dr
import mitsuba as mi
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
SCENE = ROOT / "scenes" / "mitsuba_sphere.toml"
SPP = 1024
LADDER = [2, 3, 4, 6, 8, 10]

mi.set_variant("scalar_spectral_polarized")


def mitsuba_scene(spec, spp):
    cam, mat, mesh = spec["camera"], spec["material"][0], spec["mesh"][0]
    assert len(set(mat["eta"])) == 1 and len(set(mat["k"])) == 1, "one index in every channel"
    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": "stokes", "nested": {"type": "path", "max_depth": 2}},
        "sensor": {
            "type": "perspective", "fov": cam["fov_deg"], "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(
                origin=cam["position"], target=cam["target"], up=[0, 0, 1]),
            "sampler": {"type": "independent", "sample_count": spp},
            "film": {"type": "hdrfilm", "width": cam["width"], "height": cam["height"],
                     "pixel_format": "rgb", "rfilter": {"type": "box"}},
        },
        "sphere": {
            "type": "sphere", "center": mesh["center"], "radius": mesh["radius"],
            "bsdf": {"type": "roughconductor", "distribution": "ggx", "alpha": mat["alpha"],
                     "eta": mat["eta"][0], "k": mat["k"][0]},
        },
        "env": {"type": "constant", "radiance": {"type": "rgb", "value": 1.0}},
    })


def mitsuba_stokes(spec, seed):
    """[component][row][column][channel], and the seconds the render took."""
    dr.set_thread_count(2)
    scene = mitsuba_scene(spec, SPP)
    t = time.time()
    mi.render(scene, seed=seed)
    seconds = time.time() - t
    layers = dict(scene.sensors()[0].film().bitmap().split())
    return np.stack([np.array(layers[f"S{p}"], dtype=np.float64) for p in range(4)]), seconds


def psh_stokes(out):
    return np.stack([np.array(mi.Bitmap(str(out / f"render_s{p}.exr")), dtype=np.float64)
                     for p in range(4)])


def masks(spec):
    """Pixels whose centre ray passes 2 pixels inside the sphere's silhouette, and those
    2 pixels outside it (psh's camera: pixel centres, vertical field of view)."""
    cam, mesh = spec["camera"], spec["mesh"][0]
    h, w = cam["height"], cam["width"]
    pos, target = np.array(cam["position"]), np.array(cam["target"])
    f = (target - pos) / np.linalg.norm(target - pos)
    r = np.cross(f, [0, 0, 1])
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    t = np.tan(np.radians(cam["fov_deg"]) / 2)
    ys, xs = np.mgrid[0:h, 0:w]
    px = ((xs + 0.5) / w * 2 - 1) * t * w / h
    py = (1 - (ys + 0.5) / h * 2) * t
    d = f + px[..., None] * r + py[..., None] * u
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    c = np.array(mesh["center"]) - pos
    dist = np.linalg.norm(np.cross(d, c), axis=-1)
    pixel = 2 * t / h * np.linalg.norm(c)
    return dist < mesh["radius"] - 2 * pixel, dist > mesh["radius"] + 2 * pixel


def rmse(a, b, mask):
    return [float(np.sqrt(((a[p] - b[p])[mask] ** 2).mean())) for p in range(4)]


def test_fig19_against_mitsuba(psh, record):
    spec = tomllib.loads(SCENE.read_text())
    interior, background = masks(spec)
    assert interior.sum() > 500
    m1, t_mi = mitsuba_stokes(spec, 1)
    m2, _ = mitsuba_stokes(spec, 7)
    white = m1[0][background].mean(axis=0)
    m1, m2 = m1 / white, m2 / white
    # Mitsuba's own noise: two independent renders differ by sqrt(2) sigma.
    sigma = [x / np.sqrt(2) for x in rmse(m1, m2, interior)]

    ref = psh.path("mitsuba_reference")
    meta = psh.run("render", "--scene", SCENE, "--reference", SPP, "--json", "--out", ref)
    r = psh_stokes(ref)
    to_ref = rmse(r, m1, interior)
    for p in range(3):
        # Two independent estimates, psh's no noisier than Mitsuba's: sqrt(2) sigma,
        # with half again of margin. A sign or frame error of s1, s2 is 40x over.
        record(f"psh reference vs Mitsuba 3: s{p}, sphere interior", "mitsuba",
               to_ref[p], 1.5 * np.sqrt(2) * sigma[p], measure="RMSE",
               detail=f"Mitsuba's noise sigma {sigma[p]:.2e} at {SPP} spp")
    mean_psh, mean_mi = r[0][interior].mean(), m1[0][interior].mean()
    record("psh reference vs Mitsuba 3: mean s0 over the sphere (bias)", "mitsuba",
           abs(mean_psh / mean_mi - 1), 5e-3, measure="relative difference",
           detail="Smith G: height-correlated (psh) vs separable (Mitsuba)")

    # Fig. 19's two series: the transfer alone at l_low = l ("low only"; the sphere is
    # convex, its visibility the tangent plane), and l_low = min(l, 4) with the high
    # orders by convolution to l ("full").
    rows = []
    for setting in ["low_only", "full"]:
        for l in LADDER:
            l_low, l_high = (l, 0) if setting == "low_only" else (min(l, 4), l if l > 4 else 0)
            out = psh.path(f"mitsuba_pprt_{setting}_{l}")
            report = psh.run("render", "--scene", SCENE, "--l-low", l_low, "--l-high", l_high,
                             "--json", "--out", out)
            e = rmse(psh_stokes(out), m1, interior)
            times = report["times_s"]
            rows.append((setting, l, l_low, l_high, e, times["frame"],
                         times["precompute"] + times["plan"]))
    total = {(r[0], r[1]): float(np.sqrt(sum(x * x for x in r[4]))) for r in rows}
    # Fig. 19: the error of the transfer falls with its band limit (over even l: a
    # truncation at odd l adds the odd part of the horizon's step, see docs/mitsuba.md).
    even = [l for l in LADDER if l % 2 == 0]
    rises = max(total[("low_only", b)] / total[("low_only", a)] for a, b in zip(even, even[1:]))
    record("PPRT low-only vs Mitsuba 3: largest ratio of total RMSE between successive even l",
           "mitsuba", rises, 1.0, measure="ratio")
    record("PPRT low-only vs Mitsuba 3: total RMSE at l = 10 over l = 2", "mitsuba",
           total[("low_only", 10)] / total[("low_only", 2)], 0.5, measure="ratio")

    lines = [
        "# psh against Mitsuba 3 (PSH Fig. 19)",
        "",
        "Written by `validation/test_mitsuba_render.py` (in `validation/run.sh`, so in `.ci/run`).",
        f"Scene `scenes/mitsuba_sphere.toml`: a GGX conductor sphere (alpha "
        f"{spec['material'][0]['alpha']}, eta {spec['material'][0]['eta'][0]} + "
        f"{spec['material'][0]['k'][0]} i) under a constant unpolarized environment, "
        f"{spec['camera']['width']} x {spec['camera']['height']} pixels. Mitsuba "
        f"{mi.__version__} `scalar_spectral_polarized`, `stokes(path, max_depth 2)`, {SPP} spp, "
        f"{t_mi:.1f} s on 2 threads. RMSE over the {int(interior.sum())} pixels inside the "
        "sphere's silhouette, RGB, each Stokes component in the camera's frames (x "
        "image-right, y image-up, z towards the camera in both).",
        "",
        "| renderer | l | s0 | s1 | s2 | s3 | frame s | precompute s |",
        "|---|---|---|---|---|---|---|---|",
        "| Mitsuba 3 (its own noise, sigma) | | " + " | ".join(f"{x:.4f}" for x in sigma[:3])
        + " | 0 | | |",
        f"| psh reference, {SPP} spp | | " + " | ".join(f"{x:.4f}" for x in to_ref)
        + f" | {meta['seconds']:.2f} | |",
    ]
    for setting, l, l_low, l_high, e, frame, pre in rows:
        lines.append(f"| PPRT {setting} (l_low {l_low}, l_high {l_high or '-'}) | {l} | "
                     + " | ".join(f"{x:.4f}" for x in e) + f" | {frame:.3f} | {pre:.2f} |")
    lines += [
        "",
        f"Mean s0 over the sphere: psh reference {mean_psh:.4f}, Mitsuba {mean_mi:.4f}.",
        "s3 is zero in both (one bounce of unpolarized light on a conductor creates "
        "none), so this scene does not test the sign of s3.",
        "",
        "Under a constant environment only the degree 0 of the light is non-zero, so the "
        "high orders by convolution (degrees above l_low) add nothing: PPRT's error is the "
        "band limit of the outgoing radiance in the view direction, set by l_low, and it "
        "falls with l_low (the `low_only` rows). A truncation at odd l_low is worse than at "
        "the even degree below it: the outgoing field vanishes below the shading plane, a "
        "step at its equator whose expansion beyond degree 0 is odd, and an odd partial sum "
        "overshoots it. The `full` rows stay near the l_low = 4 figure; they differ from it "
        "because the materials are projected once at max(l_low, l_high) on the grid of "
        "band 2 lmax + 2, and the GGX lobe (alpha 0.2) is not band-limited there, so its "
        "degrees up to 4 alias differently on each grid. Measured at l_low = 4 with the "
        "grid's band forced to 10, 20 and 40: s0 RMSE 0.0557, 0.0465, 0.0588 (not "
        "monotone; `l_low` 6, 8, 10 on the default grid: 0.0352, 0.0315, 0.0241): the limit "
        "is the band limit, with an aliasing spread of about 20% on top.",
        "",
        "Not yet compared here (issue 24): a dielectric, a non-constant environment, a rolled "
        "camera, shadows (buddha on the plane under sponza), `psh export-mitsuba`, and "
        "Mitsuba's separable Smith term as a psh option.",
        "",
    ]
    (ROOT / "docs" / "mitsuba.md").write_text("\n".join(lines))
