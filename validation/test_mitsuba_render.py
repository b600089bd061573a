"""psh's renders against Mitsuba 3 (PSH Sec. 7, Fig. 19). Each scene of SCENES is written
as a Mitsuba scene by `psh export-mitsuba` (scene.xml, PLY meshes, the environment as a
lat-long EXR, directional lights, the camera; the export must report no difference),
rendered by Mitsuba 3 (`scalar_spectral_polarized`, `stokes` over `path` with max_depth 2:
direct light, as psh), by psh's reference renderer (`psh render --reference`, box-filtered
pixels as Mitsuba's `box` filter) and by PPRT at a ladder of band limits. Writes
docs/mitsuba.md.

Scenes: `scenes/mitsuba_sphere.toml` (a GGX conductor sphere under a constant
environment) and `scenes/mitsuba_sky.toml` (a GGX dielectric sphere and a plastic sphere
on a diffuse plane under the analytic sky's intensity, the sun a directional light
casting shadows, a rolled camera); Smith masking separable in both, as Mitsuba's.

Conventions (docs/mitsuba.md): both write Stokes components in the camera's frames with
x image-right, y image-up and z along the light's travel towards the camera (psh:
docs/conventions.md; Mitsuba 3: the `stokes` integrator turns its result to the sensor's
axes). Mitsuba's RGB emitters are upsampled to spectra and its film integrates them back
to RGB: the background's ratio Mitsuba/psh measures that round trip (no normalization).
PPRT samples pixel centres: its rows are compared over the pixels whose neighbours
within 2 pixels see the same object (`render_object.exr`).
"""

import os
import pathlib
import time
import tomllib

import drjit as dr
import mitsuba as mi
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
SCENES = {"sphere": ROOT / "scenes" / "mitsuba_sphere.toml",
          "sky": ROOT / "scenes" / "mitsuba_sky.toml",
          "buddha": ROOT / "scenes" / "mitsuba_buddha.toml"}
SPP = 1024  # Mitsuba's samples per pixel
DIRECTIONS, GRID = 64, 4  # psh's reference: 64 directions at 4 x 4 positions per pixel
# Buddha: the reference's BSDF-sampled estimate is noisier than Mitsuba's (which samples
# the bright opening of the environment map too), so 256 directions; the cube map exported
# at 1024 rows (its 64-texel faces within a fifth of a texel; at 256 rows the background's
# mean is 1.3% off).
SETTINGS = {"buddha": dict(directions=256, env_rows=1024)}
DATA = pathlib.Path(os.environ.get("PSH_DATA_DIR") or ROOT.parent / "shared" / "data")
LADDER = [2, 3, 4, 6, 8, 10]

mi.set_variant("scalar_spectral_polarized")


def mitsuba_stokes(xml, seed, exr=None):
    """[component][row][column][channel], and the seconds the render took; the film
    written to `exr` when given (layers S0..S3, as Mitsuba writes them)."""
    dr.set_thread_count(2)
    scene = mi.load_file(str(xml))
    t = time.time()
    mi.render(scene, seed=seed)
    seconds = time.time() - t
    bitmap = scene.sensors()[0].film().bitmap()
    if exr is not None:
        bitmap.write(str(exr))
    layers = dict(bitmap.split())
    return np.stack([np.array(layers[f"S{p}"], dtype=np.float64) for p in range(4)]), seconds


def psh_stokes(out):
    return np.stack([np.array(mi.Bitmap(str(out / f"render_s{p}.exr")), dtype=np.float64)
                     for p in range(4)])


def objects(out):
    """Per pixel the index of the object its centre sees plus one, 0 for the environment."""
    return np.array(mi.Bitmap(str(out / "render_object.exr")), dtype=np.float64)[..., 0]


def interior(obj, reach=2):
    """Pixels whose neighbours within `reach` pixels see the same object."""
    h, w = obj.shape
    padded = np.pad(obj, reach, constant_values=-1)
    same = np.ones_like(obj, dtype=bool)
    for dy in range(-reach, reach + 1):
        for dx in range(-reach, reach + 1):
            same &= padded[reach + dy:reach + dy + h, reach + dx:reach + dx + w] == obj
    return same


def rmse(a, b, mask):
    return [float(np.sqrt(((a[p] - b[p])[mask] ** 2).mean())) for p in range(4)]


def compare_scene(psh, record, key):
    path = SCENES[key]
    directions = SETTINGS.get(key, {}).get("directions", DIRECTIONS)
    env_rows = SETTINGS.get(key, {}).get("env_rows", 256)
    export = psh.run("export-mitsuba", "--scene", path, "--spp", SPP, "--env-rows", env_rows,
                     "--out", psh.path(f"mitsuba_{key}"))
    assert export["differences"] == [], export["differences"]
    xml = pathlib.Path(export["files"][0])
    mitsuba_exr = psh.path(f"mitsuba_{key}.exr")
    m1, t_mi = mitsuba_stokes(xml, 1, mitsuba_exr)
    m2, _ = mitsuba_stokes(xml, 7)
    everywhere = np.ones(m1.shape[1:3], dtype=bool)
    # Mitsuba's own noise: two independent renders differ by sqrt(2) sigma.
    sigma = [x / np.sqrt(2) for x in rmse(m1, m2, everywhere)]

    ref = psh.path(f"mitsuba_{key}_reference")
    meta = psh.run("render", "--scene", path, "--reference", directions, "--pixel-grid", GRID,
                   "--json", "--out", ref)
    r = psh_stokes(ref)
    obj = objects(ref)
    to_ref = rmse(r, m1, everywhere)
    for p in range(3):
        # Two independent estimates, psh's no noisier than Mitsuba's: sqrt(2) sigma, with
        # half again of margin. A sign or frame error of s1, s2 is far over.
        record(f"{key}: psh reference vs Mitsuba 3, s{p}, every pixel", "mitsuba",
               to_ref[p], 1.5 * np.sqrt(2) * sigma[p], measure="RMSE",
               detail=f"Mitsuba's noise sigma {sigma[p]:.2e} at {SPP} spp")
    means = {}
    for k in np.unique(obj).astype(int):
        mask = obj == k
        a, b = r[0][mask].mean(axis=0), m1[0][mask].mean(axis=0)
        means[k] = (a, b)
        what = "the environment" if k == 0 else f"object {k - 1}"
        # Background: Mitsuba's RGB -> spectrum -> RGB round trip of its emitters.
        record(f"{key}: psh reference vs Mitsuba 3, mean s0 over {what} (bias, worst channel)",
               "mitsuba", float(np.abs(a / b - 1).max()), 1e-2, measure="relative difference")

    rows = []
    inner = interior(obj)
    assert inner.sum() > 300
    for setting in ["low_only", "full"]:
        for l in LADDER:
            l_low, l_high = (l, 0) if setting == "low_only" else (min(l, 4), l if l > 4 else 0)
            out = psh.path(f"mitsuba_{key}_pprt_{setting}_{l}")
            # The transport's own output, as bench-error's rows (no valid-range projection).
            report = psh.run("render", "--scene", path, "--l-low", l_low, "--l-high", l_high,
                             "--no-valid-range", "--json", "--out", out)
            pprt = psh_stokes(out)
            e = rmse(pprt, m1, inner)
            times = report["times_s"]
            # Per object (green channel): PPRT's mean s0 over Mitsuba's.
            bias = [float(pprt[0][inner & (obj == k)][:, 1].mean()
                          / m1[0][inner & (obj == k)][:, 1].mean())
                    for k in range(1, int(obj.max()) + 1)]
            rows.append((setting, l, l_low, l_high, e, times["frame"],
                         times["precompute"] + times["plan"], bias))
    total = {(row[0], row[1]): float(np.sqrt(sum(x * x for x in row[4]))) for row in rows}
    # psh bench-error reads Mitsuba's EXR as its ground truth: its PPRT low-only row at
    # l = 4 (surface pixels) is the RMSE computed here from the same render.
    spec = tomllib.loads(path.read_text())
    camera = spec["camera"]
    bench = psh.run("bench-error", "--scene", path, "--ground-truth", mitsuba_exr,
                    "--size", f"{camera['width']}x{camera['height']}",
                    "--rays", spec["settings"]["rays"], "--lmax", 4, "--spp", 1, "--ground-truth-spp", 4,
                    "--out", psh.path(f"mitsuba_{key}_bench"))
    row = next(x for x in bench["rows"] if x["setting"] == "low_only" and x["l_max"] == 4)
    # bench-error's rows keep everything (no plan: the convex sphere keeps its rays).
    same = psh.path(f"mitsuba_{key}_pprt_no_plan_4")
    psh.run("render", "--scene", path, "--l-low", 4, "--l-high", 0, "--no-plan",
            "--no-valid-range", "--json", "--out", same)
    here = rmse(psh_stokes(same), m1, obj > 0)
    record(f"{key}: psh bench-error --ground-truth on Mitsuba's EXR vs the same RMSE here, "
           "PPRT low-only l = 4, s0..s2 (relative)", "mitsuba",
           max(abs(a / b - 1) for a, b in zip(row["rmse"][:3], here[:3])), 1e-5,
           measure="relative difference",
           detail="layers S0..S3 read in psh's camera frames, rows top first")
    return dict(key=key, export=export, sigma=sigma, to_ref=to_ref, meta=meta, rows=rows,
                directions=directions,
                total=total, means=means, t_mi=t_mi, inner=int(inner.sum()),
                pixels=int(everywhere.sum()), ref_inner=rmse(r, m1, inner))


def table(result):
    lines = [
        "| renderer | l | s0 | s1 | s2 | s3 | frame s | precompute s | mean s0 / Mitsuba's per object (G) |",
        "|---|---|---|---|---|---|---|---|---|",
        "| Mitsuba 3 (its own noise, sigma; every pixel) | | "
        + " | ".join(f"{x:.4f}" for x in result["sigma"][:3]) + " | 0 | | | |",
        f"| psh reference, {result['directions']} x {GRID * GRID} samples (every pixel) | | "
        + " | ".join(f"{x:.4f}" for x in result["to_ref"])
        + f" | {result['meta']['seconds']:.2f} | | |",
        "| psh reference (interior pixels) | | "
        + " | ".join(f"{x:.4f}" for x in result["ref_inner"]) + " | | | |",
    ]
    for setting, l, l_low, l_high, e, frame, pre, bias in result["rows"]:
        lines.append(f"| PPRT {setting} (l_low {l_low}, l_high {l_high or '-'}) | {l} | "
                     + " | ".join(f"{x:.4f}" for x in e) + f" | {frame:.3f} | {pre:.2f} | "
                     + ", ".join(f"{b:.3f}" for b in bias) + " |")
    lines.append("")
    lines.append("Mean s0 (R, G, B), psh reference / Mitsuba: " + "; ".join(
        ("environment" if k == 0 else f"object {k - 1}") + ": "
        + ", ".join(f"{a:.4f}/{b:.4f}" for a, b in zip(*result["means"][k]))
        for k in sorted(result["means"])) + ".")
    return lines


def test_fig19_against_mitsuba(psh, record):
    sphere = compare_scene(psh, record, "sphere")
    t = sphere["total"]
    # Fig. 19: the error of the transfer falls with its band limit (over even l: a
    # truncation at odd l adds the odd part of the horizon's step, see docs/mitsuba.md).
    even = [l for l in LADDER if l % 2 == 0]
    rises = max(t[("low_only", b)] / t[("low_only", a)] for a, b in zip(even, even[1:]))
    record("sphere: PPRT low-only vs Mitsuba 3, largest ratio of total RMSE between "
           "successive even l", "mitsuba", rises, 1.0, measure="ratio")
    record("sphere: PPRT low-only vs Mitsuba 3, total RMSE at l = 10 over l = 2", "mitsuba",
           t[("low_only", 10)] / t[("low_only", 2)], 0.5, measure="ratio")

    # The sky scene's PPRT rows are measurements, not checks: the dielectric sphere's
    # error does not fall with l (docs/mitsuba.md, issue 24 item 5).
    sky = compare_scene(psh, record, "sky")

    lines = [
        "# psh against Mitsuba 3 (PSH Fig. 19)",
        "",
        "Written by `validation/test_mitsuba_render.py` (in `validation/run.sh`, so in "
        "`.ci/run`). Each scene is written for Mitsuba by `psh export-mitsuba` (which reports "
        "no difference for these scenes) and rendered by Mitsuba "
        f"{mi.__version__} (`scalar_spectral_polarized`, `stokes(path, max_depth 2)`, {SPP} "
        "spp, box filter, 2 threads), by psh's reference (`render --reference "
        f"{DIRECTIONS} --pixel-grid {GRID}`: {DIRECTIONS} directions at {GRID} x {GRID} "
        "positions per pixel, a box filter) and by PPRT (pixel centres, the transport's own "
        "output without the valid-range projection, as `psh bench-error`; compared over the "
        "pixels whose neighbours within 2 pixels see the same object). RMSE per Stokes "
        "component, RGB, in the camera's frames (x image-right, y image-up, z towards the "
        "camera in both). No normalization: the environment's mean s0 measures Mitsuba's "
        "RGB-spectrum round trip.",
        "",
        "## Convention map",
        "",
        "| | psh | Mitsuba 3 (`psh export-mitsuba`) |",
        "|---|---|---|",
        "| camera | frame [right, down, forward] | `to_world` columns [-right, -down, forward] |",
        "| image Stokes frames | x image-right, y image-up, z towards the camera | the same "
        "(`stokes` integrator) |",
        "| environment | `w` towards the source, theta from +z, phi from +x | `envmap` with "
        "`to_world` (v_x, v_y, v_z) -> (-v_z, v_x, v_y); texel (r, k) at theta = pi r/(H-1), "
        "phi = 2 pi (k + 1/2)/W |",
        "| environment polarization | s0..s3 | unpolarized (s0; the export lists a polarized "
        "environment as a difference) |",
        "| sun | directional light towards `d`, irradiance E | `directional`, direction -d, "
        "irradiance E |",
        "| GGX conductor | `masking = \"separable\"` | `roughconductor` (G1 G1) |",
        "| GGX dielectric reflection | plastic with albedo 0 | `pplastic`, diffuse 0 "
        "(`roughdielectric` is not polarized in Mitsuba 3) |",
        "| plastic with albedo a | specular + Lambert a (no Fresnel factors) | `blendbsdf` 0.5: "
        "`pplastic` (specular x2, diffuse 0) + `diffuse` (2a) |",
        "| s3 | psh's sign | the same sign: checked in the conductor's Mueller matrix against "
        "`mi.mueller.specular_reflection` (`test_mitsuba.py`; its s2-s3 elements make circular "
        "light of linear light), not in the images (one bounce of unpolarized light creates "
        "none) |",
        "",
        f"## {SCENES['sphere'].name}: GGX conductor sphere, constant environment",
        "",
    ] + table(sphere) + [
        "",
        "Under a constant environment only the degree 0 of the light is non-zero, so the "
        "high orders by convolution (degrees above l_low) add nothing: PPRT's error is the "
        "band limit of the outgoing radiance in the view direction, set by l_low, and it "
        "falls with l_low (the `low_only` rows). The renderer projects its pBRDFs with the "
        "output below the shading plane mirrored (`proofs/mirrored-output.md`): without it "
        "the outgoing field steps to zero at the horizon and its truncation rings (s0 RMSE "
        "0.120, 0.199, 0.056, 0.035, 0.032, 0.024 at l_low 2, 3, 4, 6, 8, 10 before the "
        "change, odd l worse than even). The `full` rows stay near the l_low = 4 figure (the "
        "materials are projected once at max(l_low, l_high), and the GGX lobe's degrees up "
        "to 4 alias differently on each grid).",
        "",
        f"## {SCENES['sky'].name}: dielectric and plastic spheres on a plane, sky and "
        "directional sun, rolled camera",
        "",
    ] + table(sky) + [
        "",
        "Objects: 0 the dielectric sphere, 1 the plastic sphere, 2 the plane. The reference "
        "agrees with Mitsuba within its noise on every object, the background (the exported "
        "envmap) and the shadows. The sun's direct light is exact in PPRT too, so PPRT's "
        "differences are the sky's transfer and its pixel-centre sampling (the reference is "
        "box-filtered: PPRT's rows include the sun's shadow edges on the plane). The "
        "dielectric sphere (alpha 0.15) is far darker at l_low = 4 (its lobe needs higher "
        "degrees; the high orders by convolution, unshadowed and truncated at l_high, "
        "recover part of it): an open finding of issue 24 (item 5). The plane's mean is "
        "within 0.1% since the mirrored outputs (3.5% too bright before).",
        "",
    ]
    if (DATA / "polarsh" / "buddha.obj").exists():
        buddha = compare_scene(psh, record, "buddha")
        lines += [
            f"## {SCENES['buddha'].name}: buddha on the plane under the Sponza cube map",
            "",
        ] + table(buddha) + [
            "",
            "Objects: 0 buddha (a GGX conductor of one index in every channel standing in for "
            "the measured gold), 1 the plane (plastic). The environment is the shared "
            "Sponza cube map (64 x 64 faces, its intensity), which psh's background and "
            "reference sample at its own resolution (`EnvironmentSource::Map`) and the "
            "export writes as a 2048 x 1024 lat-long map. The reference agrees with Mitsuba "
            "pixel by pixel within Mitsuba's noise and on every object's mean. This scene "
            "found a bias in psh: its shadow rays started 1e-4 of the scene's size above the "
            "surface, and light leaked through the statue's crevices (buddha's mean 1.1% "
            "above Mitsuba's, 0.5% under a constant environment where a sphere agreed within "
            "0.04%); they start at 1e-7 now (`pprt::SHADOW_RAY_OFFSET`, in PPRT's visibility, "
            "the directional lights and the reference alike). PPRT's rows stop falling at "
            "l_low = 6: its 64 visibility rays per vertex (this scene's setting, for CI's "
            "time) alias the visibility's degrees up to 2 l_low (256 rays: s0 0.034 instead "
            "of 0.043 at l_low 6 against psh's reference).",
            "",
        ]
    else:
        lines += [f"Buddha under Sponza: skipped, no shared data at {DATA}.", ""]
    lines += [
        "Not compared here: a conductor of an index differing per channel (an RGB index is "
        "upsampled to a spectrum in Mitsuba's spectral variants).",
        "",
    ]
    (ROOT / "docs" / "mitsuba.md").write_text("\n".join(lines))
