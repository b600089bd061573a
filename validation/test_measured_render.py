"""A measured pBRDF table rendered by Mitsuba 3 and by psh (issue "Measured pBRDFs in").

Mitsuba's own polarized `roughconductor` (GGX, alpha 0.3, eta 0.2 + 3i, constant over
wavelength) is sampled through Mitsuba's Python API into a `.pbsdf` table (its Mueller
matrices divided by the cosine and turned into the table frames with Mitsuba's
`rotate_mueller_basis`; zero at and below the horizon). A sphere of that table under a constant environment is then rendered by
Mitsuba 3's `measured_polarized` (the scene written by `psh export-mitsuba`, which copies
the table) and by psh from the same scene file: its reference renderer, which evaluates
the table directly, and PPRT at band limits 2..10 on the table's projection. The
reference and PPRT at l = 10 must agree with Mitsuba per pixel within Mitsuba's noise
(s0..s2), and PPRT's error must fall with the band limit (l = 10 under half of l = 2's).
Mitsuba's analytic `roughconductor` rendered too: the
table's interpolation error, recorded beside them. Writes its rows to docs/validation.md
and the table of docs/measured-pbrdf.md (between its markers).
"""

import pathlib
import re

import mitsuba as mi
import numpy as np

from test_mitsuba_render import interior, mitsuba_stokes, objects, psh_stokes, rmse

ROOT = pathlib.Path(__file__).resolve().parent.parent
SPP = 1024
CONDUCTOR = {"type": "roughconductor", "distribution": "ggx", "alpha": 0.3,
             "eta": 0.2, "k": 3.0}
PLASTIC = {"type": "pplastic", "distribution": "ggx", "alpha": 0.2, "int_ior": 1.5,
           "ext_ior": 1.0, "diffuse_reflectance": 0.3}
BANDS = [450, 500, 550, 600, 650]
LADDER = [2, 4, 6, 8, 10]

mi.set_variant("scalar_spectral_polarized")

SCENE = """
[environment]
type = "constant"
radiance = [1.0, 1.0, 1.0]

[camera]
position = [0.0, -4.0, 1.0]
target = [0.0, 0.0, 0.0]
fov_deg = 40.0
width = 64
height = 48

[settings]
l_low = 4
l_high = 0
rays = 16

[[material]]
name = "table"
type = "table"
path = "{table}"

[[mesh]]
type = "sphere"
center = [0.0, 0.0, 0.0]
radius = 1.0
rings = 128
segments = 256
material = "table"
"""


SKY = """
[environment]
type = "sky"
sun_elevation_deg = 35.0
sun_azimuth_deg = 120.0
sun = "directional"

[camera]
position = [0.0, -5.5, 1.5]
target = [0.0, 0.0, 0.0]
fov_deg = 40.0
width = 64
height = 48

[settings]
l_low = 4
l_high = 0
rays = 16

[[material]]
name = "conductor"
type = "table"
path = "conductor.pbsdf"

[[material]]
name = "plastic"
type = "table"
path = "plastic.pbsdf"

[[mesh]]
type = "sphere"
center = [-1.1, 0.0, 0.0]
radius = 1.0
rings = 128
segments = 256
material = "conductor"

[[mesh]]
type = "sphere"
center = [1.1, 0.0, 0.0]
radius = 1.0
rings = 128
segments = 256
material = "plastic"
"""


def rusinkiewicz_directions(pd, td, th):
    """(towards the light, towards the viewer) of Rusinkiewicz angles, phi_h = 0."""
    h = np.array([np.sin(th), 0, np.cos(th)])
    t = np.array([np.cos(th), 0, -np.sin(th)])
    b = np.array([0.0, 1.0, 0.0])
    light = np.sin(td) * (np.cos(pd) * t + np.sin(pd) * b) + np.cos(td) * h
    return light, 2 * (h @ light) * h - light


def sample_table(bsdf_dict, path, n_phi=73, n_theta=31):
    """Mitsuba's BSDF as a table: f = M / cos(theta_light) in the frames x = normalize(L x V)
    (Mitsuba's measured_polarized), theta_h quadratic as the KAIST dataset's."""
    bsdf = mi.load_dict(bsdf_dict)
    ctx = mi.BSDFContext()
    si = mi.SurfaceInteraction3f()
    si.n = [0, 0, 1]
    si.sh_frame = mi.Frame3f(si.n)
    si.wavelengths = [550.0] * 4
    pd = np.linspace(-np.pi, np.pi, n_phi)
    td = np.linspace(0, np.pi / 2, n_theta)
    th = (np.arange(n_theta) / (n_theta - 1)) ** 2 * np.pi / 2
    m = np.zeros((n_phi, n_theta, n_theta, 4, 4))
    for a, b, c in np.ndindex(n_phi, n_theta, n_theta):
        light, view = rusinkiewicz_directions(pd[a], td[b], th[c])
        if min(light[2], view[2]) < 1e-6:
            continue  # at or below the horizon: zero, as Mitsuba's BSDF gives it
        x = np.cross(light, view)
        if np.linalg.norm(x) < 1e-9:
            x = np.cross([0.0, 0.0, 1.0], view) if view[2] < 1 - 1e-9 else np.array([1.0, 0, 0])
        x /= np.linalg.norm(x)
        si.wi = mi.Vector3f(*view)
        value = bsdf.eval(ctx, si, mi.Vector3f(*light))
        L, V, X = mi.Vector3f(*-light), mi.Vector3f(*view), mi.Vector3f(*x)
        turned = mi.mueller.rotate_mueller_basis(value, L, mi.mueller.stokes_basis(L), X,
                                                 V, mi.mueller.stokes_basis(V), X)
        m[a, b, c] = np.array(turned)[..., 0] / light[2]
    fields = dict(phi_d=pd[None].astype(np.float32), theta_d=td[None].astype(np.float32),
                  theta_h=th[None].astype(np.float32), wvls=np.array(BANDS, dtype=np.uint16),
                  M=np.repeat(m[:, :, :, None], len(BANDS), axis=3).astype(np.float32))
    mi.tensor_io.write(str(path), **fields)


def analytic_scene(xml, out):
    """Mitsuba's exported scene with the table replaced by the BSDF it was sampled from."""
    text = pathlib.Path(xml).read_text()
    bsdf = ('<bsdf id="material_0" type="roughconductor"><string name="distribution" '
            'value="ggx"/><float name="alpha" value="0.3"/><float name="eta" value="0.2"/>'
            '<float name="k" value="3.0"/></bsdf>')
    text, n = re.subn(r'<bsdf id="material_0" type="measured_polarized">.*?</bsdf>', bsdf, text)
    assert n == 1, "the exported scene names its table once"
    out.write_text(text)
    return out


def test_measured_tables_under_the_sky_against_mitsuba(psh, record):
    """Tables of Mitsuba's `roughconductor` and `pplastic` on two spheres under the
    polarized sky (Mitsuba emits it through psh's plugin `psh_stokes_envmap`), the sun a
    directional light (its highlight samples each table's lobe at one pair of directions
    per pixel): psh's reference against Mitsuba's `measured_polarized` per pixel, s0..s3
    (the conductor makes circular light of the sky's linear light), and per object."""
    for name, bsdf in (("conductor", CONDUCTOR), ("plastic", PLASTIC)):
        sample_table(bsdf, psh.path(f"{name}.pbsdf"))
    scene = psh.path("measured_sky.toml")
    scene.write_text(SKY)
    export = psh.run("export-mitsuba", "--scene", scene, "--spp", SPP,
                     "--out", psh.path("mitsuba_measured_sky"))
    assert export["differences"] == [], export["differences"]
    xml = pathlib.Path(export["files"][0])
    assert xml.read_text().count("measured_polarized") == 2
    assert (xml.parent / "psh_stokes_envmap.py").exists()
    m1, _ = mitsuba_stokes(xml, 1)
    m2, _ = mitsuba_stokes(xml, 7)
    everywhere = np.ones(m1.shape[1:3], dtype=bool)
    sigma = [x / np.sqrt(2) for x in rmse(m1, m2, everywhere)]
    ref = psh.path("measured_sky_reference")
    psh.run("render", "--scene", scene, "--reference", 64, "--pixel-grid", 4, "--json",
            "--out", ref)
    r = psh_stokes(ref)
    obj = objects(ref)
    to_ref = rmse(r, m1, everywhere)
    for p in range(4):
        record(f"measured tables under the polarized sky: psh reference vs Mitsuba 3, s{p}, "
               "every pixel",
               "mitsuba", to_ref[p], 1.5 * np.sqrt(2) * sigma[p], measure="RMSE",
               detail=f"Mitsuba's noise sigma {sigma[p]:.2e} at {SPP} spp")
    for k, name in ((1, "conductor"), (2, "plastic")):
        mask = obj == k
        a, b = r[0][mask].mean(axis=0), m1[0][mask].mean(axis=0)
        # The sky's RGB -> spectrum -> RGB round trip in Mitsuba: 1% (as test_mitsuba_render).
        record(f"measured tables under the polarized sky: mean s0 over the {name} sphere "
               "(worst channel)",
               "mitsuba", float(np.abs(a / b - 1).max()), 1e-2, measure="relative difference")


def test_a_measured_table_against_mitsuba(psh, record):
    table = psh.path("conductor.pbsdf")
    sample_table(CONDUCTOR, table)
    info = psh.run("pbrdf", "info", table)
    assert info["wavelengths_nm"] == BANDS
    scene = psh.path("measured_sphere.toml")
    scene.write_text(SCENE.format(table=table.name))
    export = psh.run("export-mitsuba", "--scene", scene, "--spp", SPP,
                     "--out", psh.path("mitsuba_measured"))
    assert export["differences"] == [], export["differences"]
    xml = pathlib.Path(export["files"][0])
    assert "measured_polarized" in xml.read_text()
    m1, t_mi = mitsuba_stokes(xml, 1)
    m2, _ = mitsuba_stokes(xml, 7)
    everywhere = np.ones(m1.shape[1:3], dtype=bool)
    sigma = [x / np.sqrt(2) for x in rmse(m1, m2, everywhere)]

    ref = psh.path("measured_reference")
    meta = psh.run("render", "--scene", scene, "--reference", 64, "--pixel-grid", 4,
                   "--json", "--out", ref)
    r = psh_stokes(ref)
    obj = objects(ref)
    to_ref = rmse(r, m1, everywhere)
    for p in range(3):
        record(f"measured table: psh reference vs Mitsuba 3 measured_polarized, s{p}, every pixel",
               "mitsuba", to_ref[p], 1.5 * np.sqrt(2) * sigma[p], measure="RMSE",
               detail=f"Mitsuba's noise sigma {sigma[p]:.2e} at {SPP} spp")
    sphere = obj == 1
    a, b = r[0][sphere].mean(axis=0), m1[0][sphere].mean(axis=0)
    record("measured table: psh reference vs Mitsuba 3, mean s0 over the sphere (worst channel)",
           "mitsuba", float(np.abs(a / b - 1).max()), 1e-2, measure="relative difference")

    analytic, _ = mitsuba_stokes(analytic_scene(xml, xml.parent / "analytic.xml"), 1)
    interpolation = rmse(analytic, m1, everywhere)

    inner = interior(obj)
    rows = []
    for l in LADDER:
        out = psh.path(f"measured_pprt_{l}")
        report = psh.run("render", "--scene", scene, "--l-low", l, "--l-high", 0,
                         "--no-valid-range", "--json", "--out", out)
        e = rmse(psh_stokes(out), m1, inner)
        rows.append((l, e, report["times_s"]["frame"], report["times_s"]["precompute"]))
    total = {l: float(np.sqrt(sum(x * x for x in e))) for l, e, _, _ in rows}
    record("measured table: PPRT vs Mitsuba 3, total RMSE at l = 10 over l = 2 (interior)",
           "mitsuba", total[10] / total[2], 0.5, measure="ratio",
           detail="the band limit's error falls to Mitsuba's noise")
    # At l = 10 PPRT on the table's projection agrees with Mitsuba's render of the table
    # within Mitsuba's noise.
    for p in range(3):
        record(f"measured table: PPRT l = 10 vs Mitsuba 3 measured_polarized, s{p}, interior",
               "mitsuba", rows[-1][1][p], 1.5 * np.sqrt(2) * sigma[p], measure="RMSE",
               detail=f"Mitsuba's noise sigma {sigma[p]:.2e} at {SPP} spp")

    lines = [
        "| renderer | l | s0 | s1 | s2 | s3 | frame s | precompute s |",
        "|---|---|---|---|---|---|---|---|",
        "| Mitsuba 3 `measured_polarized` (its own noise, sigma; every pixel) | | "
        + " | ".join(f"{x:.4f}" for x in sigma[:3]) + " | 0 | | |",
        "| psh reference, 64 x 16 samples (every pixel) | | "
        + " | ".join(f"{x:.4f}" for x in to_ref) + f" | {meta['seconds']:.2f} | |",
        "| Mitsuba 3 `roughconductor` (the model the table samples; every pixel) | | "
        + " | ".join(f"{x:.4f}" for x in interpolation) + " | | |",
    ]
    for l, e, frame, pre in rows:
        lines.append(f"| PPRT low-only (interior pixels) | {l} | "
                     + " | ".join(f"{x:.4f}" for x in e) + f" | {frame:.3f} | {pre:.2f} |")
    lines.append("")
    lines.append(f"RMSE against Mitsuba 3's render of the table ({SPP} spp, {t_mi:.1f} s); "
                 f"mean s0 over the sphere (R, G, B), psh reference / Mitsuba: "
                 + ", ".join(f"{x:.4f}/{y:.4f}" for x, y in zip(a, b)) + ".")
    doc = ROOT / "docs" / "measured-pbrdf.md"
    text = doc.read_text()
    start, end = "<!-- mitsuba table: start -->", "<!-- mitsuba table: end -->"
    assert start in text and end in text
    head, rest = text.split(start)
    _, tail = rest.split(end)
    doc.write_text(head + start + "\n" + "\n".join(lines) + "\n" + end + tail)
