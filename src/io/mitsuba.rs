//! Scenes as Mitsuba 3 scene files (`psh export-mitsuba`): `scene.xml` (format 3.0.0)
//! with one binary PLY mesh per object, the environment (an unpolarized one's intensity
//! as a lat-long EXR in the layout of Mitsuba's `envmap`, or a `constant` emitter; a
//! polarized one as psh's four component files with the emitter plugin
//! `psh_stokes_envmap` written beside, [`PLUGIN_FILE`]), directional lights, materials and
//! the camera, so that Mitsuba renders the scene psh's reference renders
//! (`docs/mitsuba.md`, the convention map). What Mitsuba cannot say is listed, never
//! dropped silently ([`MitsubaExport::differences`]).
//!
//! Conventions (`docs/mitsuba.md`):
//! - **camera**: psh's frame `[right, down, forward]` is Mitsuba's `to_world` with columns
//!   `[-right, -down, forward]` (Mitsuba's camera space is x left, y up, z forward);
//! - **envmap**: Mitsuba looks a direction `v` (in the emitter's space) up at
//!   `u = atan2(v_x, -v_z) / 2 pi`, `v = acos(v_y) / pi`, texel column `k` centred at
//!   `u = (k + 1/2)/W` and row `r` at `v = r/(H - 1)`; with `to_world` taking `v` to
//!   `(-v_z, v_x, v_y)`, texel `(r, k)` is psh's direction at `theta = pi r/(H - 1)`,
//!   `phi = 2 pi (k + 1/2)/W`;
//! - **polarized environment**: `psh_stokes_envmap` reads psh's map files (stored frames
//!   `[e_theta, -e_phi, -w]`, texels piecewise constant) and emits each texel's Stokes
//!   vector in Mitsuba's frame of the travel direction (`proofs/mitsuba-stokes-environment.md`);
//!   its `to_world` is the map's rotation to psh's world, which is Mitsuba's;
//! - **materials**: psh's plastic is `0.5 pplastic(specular 2, diffuse 0) + 0.5
//!   diffuse(2 albedo)` (a `blendbsdf`: psh adds the depolarizing Lambertian without
//!   Fresnel factors, Mitsuba's `pplastic` diffuse term has them); the conductor is
//!   `roughconductor`; both GGX, and Mitsuba's masking is the separable form
//!   ([`crate::optics::Masking::Separable`]).

use super::exr::write_rgb_exr;
use super::io_error;
use super::output::{all_or_nothing, write_file, write_text};
use crate::error::{Error, Result};
use crate::geometry::PixelGrid;
use crate::map::{MapLayout, StokesMap};
use crate::optics::{Masking, MicrofacetSpecular, KAIST_BANDS_NM};
use crate::polarized::{PshEvaluator, PshVector};
use crate::pprt::{EnvironmentSource, Scene, SceneMaterial};
use nalgebra::Rotation3;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// Rows of the environment's lat-long image unless asked otherwise (512 x 256).
pub const ENVMAP_ROWS: usize = 256;

/// The files an export wrote and the ways Mitsuba's scene differs from psh's.
#[derive(Clone, Debug)]
pub struct MitsubaExport {
    /// `scene.xml` first, then the meshes and the environment map.
    pub files: Vec<PathBuf>,
    /// One sentence per difference (a material's masking, a polarized environment, ...).
    pub differences: Vec<String>,
}

/// Writes `scene` into the directory `dir` (created if missing) as a Mitsuba 3 scene
/// rendered with `spp` samples per pixel, the environment map `env_rows x 2 env_rows`.
/// All files appear together or none ([`all_or_nothing`]). Errors: `spp` or `env_rows`
/// out of range, a material Mitsuba cannot express (measured coefficient matrices), a
/// file that cannot be written.
pub fn export_mitsuba(
    scene: &Scene,
    dir: &Path,
    spp: usize,
    env_rows: usize,
) -> Result<MitsubaExport> {
    if spp == 0 {
        return Err(Error::invalid(
            "samples per pixel",
            spp.to_string(),
            "at least 1",
        ));
    }
    if env_rows < 2 {
        return Err(Error::invalid(
            "environment rows",
            env_rows.to_string(),
            "at least 2",
        ));
    }
    // The image (f32 RGB) and its f64 evaluation.
    crate::budget::check(
        "the environment map",
        &[env_rows, env_rows.saturating_mul(2)],
        48,
    )?;
    std::fs::create_dir_all(dir).map_err(|e| io_error(dir, e))?;
    let mut differences = Vec::new();
    let mut xml = String::from(
        "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n\
         <!-- Written by psh export-mitsuba: psh's scene for Mitsuba 3 (docs/mitsuba.md).\n     \
         Direct light only, as psh renders it: path with max_depth 2 under stokes. -->\n\
         <scene version=\"3.0.0\">\n",
    );
    let _ = write!(
        xml,
        "    <integrator type=\"stokes\">\n        <integrator type=\"path\">\n            \
         <integer name=\"max_depth\" value=\"2\"/>\n        </integrator>\n    </integrator>\n"
    );
    xml.push_str(&sensor(scene, spp));
    for (k, m) in scene.materials().iter().enumerate() {
        xml.push_str(&material(k, m, &mut differences)?);
    }
    let files = all_or_nothing(&[], || {
        let mut files = vec![dir.join("scene.xml")];
        for (k, o) in scene.objects().iter().enumerate() {
            let name = format!("mesh_{k}.ply");
            write_ply(&dir.join(&name), &o.mesh)?;
            let _ = write!(
                xml,
                "    <shape type=\"ply\">\n        <string name=\"filename\" value=\"{name}\"/>\n        \
                 <ref id=\"material_{}\"/>\n    </shape>\n",
                o.material
            );
            files.push(dir.join(name));
        }
        for (k, m) in scene.materials().iter().enumerate() {
            if let SceneMaterial::Tabulated(t) = m {
                let path = dir.join(table_file(k));
                super::write_pbsdf(&path, t.bands())?;
                files.push(path);
            }
        }
        match environment(scene.source(), dir, env_rows, &mut differences)? {
            Environment::Map(path) => {
                files.push(path);
                let _ = write!(
                    xml,
                    "    <emitter type=\"envmap\">\n        <string name=\"filename\" value=\"environment.exr\"/>\n        \
                     <transform name=\"to_world\">\n            <matrix value=\"0 0 -1 0  1 0 0 0  0 1 0 0  0 0 0 1\"/>\n        \
                     </transform>\n    </emitter>\n"
                );
            }
            Environment::Stokes {
                files: maps,
                to_world,
            } => {
                files.extend(maps);
                let plugin = dir.join(PLUGIN_FILE);
                write_text(&plugin, PLUGIN)?;
                files.push(plugin);
                let m = to_world.matrix();
                let _ = write!(
                    xml,
                    "    <!-- A polarized environment: register the plugin written beside this file\n         \
                     first (import psh_stokes_envmap; psh_stokes_envmap.register()), and after\n         \
                     loading give it the scene (emitter.set_scene(scene)) for its shadow rays. -->\n    \
                     <emitter type=\"psh_stokes_envmap\">\n        \
                     <string name=\"filename\" value=\"{STOKES_MAP}\"/>\n        \
                     <transform name=\"to_world\">\n            \
                     <matrix value=\"{} {} {} 0  {} {} {} 0  {} {} {} 0  0 0 0 1\"/>\n        \
                     </transform>\n    </emitter>\n",
                    m[(0, 0)], m[(0, 1)], m[(0, 2)], m[(1, 0)], m[(1, 1)], m[(1, 2)], m[(2, 0)], m[(2, 1)], m[(2, 2)]
                );
            }
            Environment::Constant([r, g, b]) => {
                let _ = write!(
                    xml,
                    "    <emitter type=\"constant\">\n        <rgb name=\"radiance\" value=\"{r}, {g}, {b}\"/>\n    </emitter>\n"
                );
            }
        }
        for light in scene.source().directional_lights() {
            let [x, y, z] = light.direction().map(|c| -c);
            let [r, g, b] = light.irradiance();
            let _ = write!(
                xml,
                "    <emitter type=\"directional\">\n        <vector name=\"direction\" x=\"{x}\" y=\"{y}\" z=\"{z}\"/>\n        \
                 <rgb name=\"irradiance\" value=\"{r}, {g}, {b}\"/>\n    </emitter>\n"
            );
        }
        xml.push_str("</scene>\n");
        write_text(&files[0], &xml)?;
        Ok(files)
    })?;
    Ok(MitsubaExport { files, differences })
}

/// The perspective sensor: psh's camera frame as `to_world` (columns `-right, -down,
/// forward`, then the position), vertical field of view, box-filtered pixels.
fn sensor(scene: &Scene, spp: usize) -> String {
    let cam = scene.camera();
    let (x, y, z) = (-cam.frame.x(), -cam.frame.y(), cam.frame.z());
    let p = cam.position;
    let matrix = format!(
        "{} {} {} {}  {} {} {} {}  {} {} {} {}  0 0 0 1",
        x[0], y[0], z[0], p[0], x[1], y[1], z[1], p[1], x[2], y[2], z[2], p[2]
    );
    format!(
        "    <sensor type=\"perspective\">\n        <float name=\"fov\" value=\"{}\"/>\n        \
         <string name=\"fov_axis\" value=\"y\"/>\n        <transform name=\"to_world\">\n            \
         <matrix value=\"{matrix}\"/>\n        </transform>\n        <sampler type=\"independent\">\n            \
         <integer name=\"sample_count\" value=\"{spp}\"/>\n        </sampler>\n        <film type=\"hdrfilm\">\n            \
         <integer name=\"width\" value=\"{}\"/>\n            <integer name=\"height\" value=\"{}\"/>\n            \
         <string name=\"pixel_format\" value=\"rgb\"/>\n            <rfilter type=\"box\"/>\n        </film>\n    </sensor>\n",
        cam.fov_y.to_degrees(),
        cam.width,
        cam.height
    )
}

/// A spectrum property: one value when the three channels agree (exact in every
/// variant), else RGB.
fn spectrum(name: &str, rgb: [f64; 3]) -> String {
    if rgb[0] == rgb[1] && rgb[1] == rgb[2] {
        format!("<spectrum name=\"{name}\" value=\"{}\"/>", rgb[0])
    } else {
        format!(
            "<rgb name=\"{name}\" value=\"{}, {}, {}\"/>",
            rgb[0], rgb[1], rgb[2]
        )
    }
}

/// The GGX parameters of a microfacet term, and a difference if its masking is not
/// Mitsuba's.
fn ggx(k: usize, s: &MicrofacetSpecular, differences: &mut Vec<String>) -> String {
    if s.ggx().masking() != Masking::Separable {
        differences.push(format!(
            "material {k}: psh's masking is {}, Mitsuba's separable (scene file: masking = \"separable\")",
            s.ggx().masking().name()
        ));
    }
    format!(
        "<string name=\"distribution\" value=\"ggx\"/><float name=\"alpha\" value=\"{}\"/>",
        s.ggx().alpha()
    )
}

/// Material `k` as a Mitsuba BSDF with id `material_k` (a table: `measured_polarized`
/// reading it from [`table_file`]). Errors: measured coefficient matrices (no Mitsuba
/// equivalent), a table of other wavelengths than the five KAIST bands.
fn material(k: usize, m: &SceneMaterial, differences: &mut Vec<String>) -> Result<String> {
    let body = match m {
        SceneMaterial::Plastic(p) => {
            let s = p.specular();
            let specular = |scale: f64, d: &mut Vec<String>| {
                format!(
                    "<bsdf type=\"pplastic\">{}<float name=\"int_ior\" value=\"{}\"/>\
                     <float name=\"ext_ior\" value=\"1\"/>{}{}</bsdf>",
                    ggx(k, s, d),
                    s.ior().n(),
                    spectrum("diffuse_reflectance", [0.0; 3]),
                    spectrum("specular_reflectance", [scale; 3]),
                )
            };
            let albedo = p.diffuse().albedo();
            if albedo == 0.0 {
                specular(1.0, differences)
            } else {
                format!(
                    "<bsdf type=\"blendbsdf\"><float name=\"weight\" value=\"0.5\"/>{}\
                     <bsdf type=\"diffuse\">{}</bsdf></bsdf>",
                    specular(2.0, differences),
                    spectrum("reflectance", [2.0 * albedo; 3])
                )
            }
        }
        SceneMaterial::Conductor(c) => {
            let eta = c.each_ref().map(|c| c.specular().ior().n());
            let kappa = c.each_ref().map(|c| c.specular().ior().k());
            let same = c
                .iter()
                .all(|x| x.specular().ggx() == c[0].specular().ggx());
            if !same {
                return Err(unsupported(
                    k,
                    "a roughness or masking differing per channel",
                ));
            }
            if !(eta.iter().all(|&n| n == eta[0]) && kappa.iter().all(|&x| x == kappa[0])) {
                differences.push(format!(
                    "material {k}: an index differing per channel is an RGB value in Mitsuba, \
                     upsampled to a spectrum in its spectral variants"
                ));
            }
            format!(
                "<bsdf type=\"roughconductor\">{}{}{}</bsdf>",
                ggx(k, c[0].specular(), differences),
                spectrum("eta", eta),
                spectrum("k", kappa)
            )
        }
        SceneMaterial::Diffuse(d) => format!(
            "<bsdf type=\"diffuse\">{}</bsdf>",
            spectrum("reflectance", d.each_ref().map(|d| d.albedo()))
        ),
        SceneMaterial::Matrices(_) => {
            return Err(unsupported(k, "measured coefficient matrices"));
        }
        SceneMaterial::Tabulated(t) => {
            if t.bands().wavelengths_nm() != KAIST_BANDS_NM {
                return Err(unsupported(
                    k,
                    "a table of other wavelengths than the five KAIST bands (measured_polarized reads five)",
                ));
            }
            format!(
                "<bsdf type=\"measured_polarized\"><string name=\"filename\" value=\"{}\"/></bsdf>",
                table_file(k)
            )
        }
    };
    Ok(format!(
        "    <!-- material {k} -->\n    {}\n",
        body.replacen("<bsdf ", &format!("<bsdf id=\"material_{k}\" "), 1)
    ))
}

/// The file material `k`'s table is exported to.
fn table_file(k: usize) -> String {
    format!("material_{k}.pbsdf")
}

fn unsupported(k: usize, what: &str) -> Error {
    Error::invalid(
        "material",
        k.to_string(),
        format!("{what}: no Mitsuba 3 equivalent to export"),
    )
}

/// The environment as Mitsuba's emitter: a constant radiance per channel, a lat-long
/// map of its intensity written to a file (`envmap`), or a polarized map written as psh's
/// four component files with the plugin that emits it (`psh_stokes_envmap`) and the
/// rotation from the map's coordinates to the world.
enum Environment {
    Constant([f64; 3]),
    Map(PathBuf),
    Stokes {
        files: Vec<PathBuf>,
        to_world: Rotation3<f64>,
    },
}

/// The Mitsuba 3 emitter plugin of polarized maps (`src/io/psh_stokes_envmap.py`, also the
/// Python package's `psh.mitsuba_envmap`),
/// written beside a scene that needs it as [`PLUGIN_FILE`].
const PLUGIN: &str = include_str!("psh_stokes_envmap.py");

/// The name the plugin is written under beside `scene.xml` (imported as a module).
pub const PLUGIN_FILE: &str = "psh_stokes_envmap.py";

/// The pattern of the polarized map's component files beside `scene.xml`.
const STOKES_MAP: &str = "environment_s%d.exr";

/// The radiance per channel of coefficients that are `f_00` of `s0` alone (a constant
/// environment, `L = f_00 Y_00`), or `None`.
fn constant_radiance(v: &PshVector) -> Option<[f64; 3]> {
    let n = v.codomain().components().len();
    let per = v.data().len() / v.channels();
    let only_f00 = v.channels() == 3
        && v.codomain().components()[0] == 0
        && v.data()
            .iter()
            .enumerate()
            .all(|(i, &x)| x == 0.0 || i % per == 0);
    // Y_00 = 1/sqrt(4 pi).
    (only_f00 && n > 0)
        .then(|| [0, 1, 2].map(|c| v.data()[c * per] / (4.0 * std::f64::consts::PI).sqrt()))
}

/// Whether the source has polarized light (any coefficient of `s1`, `s2`, `s3`).
fn polarized(source: &EnvironmentSource) -> bool {
    match source {
        EnvironmentSource::Sky(sky) => sky.is_polarized(),
        EnvironmentSource::Map { map, .. } => map
            .channels()
            .iter()
            .flatten()
            .any(|s| s[1..].iter().any(|&x| x != 0.0)),
        EnvironmentSource::Coefficients(v) => {
            let components = v.codomain().components();
            let n = components.len();
            v.data()
                .iter()
                .enumerate()
                .any(|(i, &x)| x != 0.0 && components[i % n] != 0)
        }
    }
}

/// The source's emitter: constant coefficients as they are, else `environment.exr` in
/// `dir` (the source's `s0` on Mitsuba's lat-long texels; negative values of a
/// band-limited source set to 0 and counted as a difference).
fn environment(
    source: &EnvironmentSource,
    dir: &Path,
    rows: usize,
    differences: &mut Vec<String>,
) -> Result<Environment> {
    if polarized(source) {
        return stokes_environment(source, dir, rows);
    }
    if let EnvironmentSource::Coefficients(v) = source {
        if let Some(radiance) = constant_radiance(v) {
            return Ok(Environment::Constant(radiance));
        }
    }
    let evaluator = PshEvaluator::new(source.lmax())?;
    let cols = 2 * rows;
    let texels: Vec<[f64; 3]> = (0..rows * cols)
        .into_par_iter()
        .map_init(
            || evaluator.clone(),
            |evaluator, t| -> Result<[f64; 3]> {
                let (r, k) = (t / cols, t % cols);
                let theta = std::f64::consts::PI * r as f64 / (rows - 1) as f64;
                let phi = 2.0 * std::f64::consts::PI * (k as f64 + 0.5) / cols as f64;
                let light = source.incident(evaluator, crate::geometry::direction(theta, phi))?;
                Ok([0, 1, 2].map(|c| light[c].s0()))
            },
        )
        .collect::<Result<_>>()?;
    let negative = texels.iter().flatten().filter(|&&x| x < 0.0).count();
    if negative > 0 {
        differences.push(format!(
            "environment: {negative} texel values below 0 (the band-limited environment's \
             ringing) set to 0 for Mitsuba"
        ));
    }
    let path = dir.join("environment.exr");
    let rgb = [0, 1, 2].map(|c| texels.iter().map(|t| t[c].max(0.0) as f32).collect());
    write_rgb_exr(&path, cols, rows, rgb)?;
    Ok(Environment::Map(path))
}

/// A polarized source as psh's map files for `psh_stokes_envmap`: an equirectangular map
/// as it is (with its rotation to the world), any other source at the texel centres of an
/// equirectangular map `rows x 2 rows` in the world's coordinates (components in the
/// theta-phi frames there, piecewise constant over texels as psh reads maps).
fn stokes_environment(source: &EnvironmentSource, dir: &Path, rows: usize) -> Result<Environment> {
    let pattern = dir.join(STOKES_MAP);
    if let EnvironmentSource::Map { map, to_world } = source {
        if let MapLayout::Equirect(_) = map.layout() {
            let files = super::write_stokes_map(map, &pattern)?;
            return Ok(Environment::Stokes {
                files,
                to_world: *to_world,
            });
        }
    }
    let layout = MapLayout::from_image_size(rows, 2 * rows)?;
    let field = layout.frame_field();
    let evaluator = PshEvaluator::new(source.lmax())?;
    let texels: Vec<Vec<[f64; 4]>> = (0..layout.len())
        .into_par_iter()
        .map_init(
            || evaluator.clone(),
            |evaluator, t| -> Result<Vec<[f64; 4]>> {
                source
                    .incident(evaluator, layout.direction(t))?
                    .iter()
                    .map(|s| Ok(s.components_in_field(&field)?.to_array()))
                    .collect()
            },
        )
        .collect::<Result<_>>()?;
    let channels = (0..3)
        .map(|c| texels.iter().map(|t| t[c]).collect())
        .collect();
    let map = StokesMap::new(layout, channels)?;
    let files = super::write_stokes_map(&map, &pattern)?;
    Ok(Environment::Stokes {
        files,
        to_world: Rotation3::identity(),
    })
}

/// Writes a mesh as binary little-endian PLY: float positions and normals, int faces.
fn write_ply(path: &Path, mesh: &crate::pprt::Mesh) -> Result<()> {
    write_file(path, |out| {
        let header = format!(
            "ply\nformat binary_little_endian 1.0\nelement vertex {}\n\
             property float x\nproperty float y\nproperty float z\n\
             property float nx\nproperty float ny\nproperty float nz\n\
             element face {}\nproperty list uchar int vertex_indices\nend_header\n",
            mesh.positions().len(),
            mesh.triangles().len()
        );
        let mut bytes = header.into_bytes();
        for (p, n) in mesh.positions().iter().zip(mesh.normals()) {
            for x in p.iter().chain(n) {
                bytes.extend_from_slice(&(*x as f32).to_le_bytes());
            }
        }
        for t in mesh.triangles() {
            bytes.push(3);
            for i in t {
                bytes.extend_from_slice(&(*i as i32).to_le_bytes());
            }
        }
        out.write_all(&bytes).map_err(|e| io_error(path, e))
    })
}
