//! Scene files (TOML, `serde`): environment, camera, settings, materials and meshes.
//!
//! ```toml
//! [environment]                 # one of:
//! type = "sky"                  #   the analytic Rayleigh sky
//! sun_elevation_deg = 35.0
//! sun_azimuth_deg = 137.0
//! sun = "directional"           # optional: or "lobe" (the sun in the sky's PSH
//!                               #   coefficients; pprt::Sun)
//! # type = "npz", path = "..."  #   a PSH coefficient vector (polarsh .npz, RGB)
//! # type = "exr", path = "map_s%d.exr"   # a polarized environment map (the background
//!                               #   and the reference sample its texels, the transfer
//!                               #   its projection to l_high)
//! # type = "constant", radiance = [1.0, 1.0, 1.0]   # unpolarized, the same everywhere
//! # up = "y"                    #   optional: the file's up axis is y (turned to +z)
//!
//! [camera]
//! position = [0.0, -4.5, 2.2]
//! target = [0.0, 0.0, 0.5]
//! fov_deg = 43.0
//! width = 480
//! height = 360
//! roll_deg = 0.0                # optional: turn about the view axis (Camera::rolled)
//!
//! [settings]                    # optional, these are the defaults
//! l_low = 4
//! l_high = 9                   # high orders by convolution (none if <= l_low)
//! rays = 256
//! shadows = true
//! unpolarized_environment = false   # true: the environment's s0 alone (s1..s3 dropped)
//!
//! [[material]]
//! name = "glass"
//! type = "plastic"              # or "conductor" (table = "Gold", or eta = [r, g, b] and
//!                               # k = [r, g, b]; alpha), "diffuse"
//! alpha = 0.15                  # (albedo = [r, g, b], depolarizing Lambertian) or
//!                               # "npz" (path: a polarsh ISOBI2 pBRDF matrix)
//! ior = 1.5
//! albedo = 0.2
//! masking = "height-correlated" # optional (plastic, conductor): Smith's G2 form, or
//!                               #   "separable" (Mitsuba 3's G1 G1; optics::Masking)
//!
//! [[mesh]]
//! type = "sphere"               # or "plane" (center, half_size), "torus" (center,
//!                               # major_radius, minor_radius; axis +z) or "obj" (path, up)
//! center = [0.0, 0.0, 0.7]
//! radius = 0.7
//! rings = 32                    # optional: the sphere's tessellation (these defaults)
//! segments = 64
//! material = "glass"
//! ```
//!
//! Paths are relative to the scene file; a path starting with `data:` is relative to the
//! shared data directory (`$PSH_DATA_DIR`, else `../shared/data` from the working
//! directory). Errors name the file and the field.

use crate::error::{clip, Error, Result};
use crate::optics::{
    Channel, ComplexIor, Conductor, Lambertian, Masking, Material, PolarizedPlastic,
};
use crate::polarized::{Codomain, FieldArgument, PshVector};
use crate::pprt::mesh::Mesh;
use crate::pprt::scene::{Camera, EnvironmentSource, Scene, SceneMaterial, SceneObject};
use crate::pprt::settings::{TransferSettings, Visibility};
use crate::pprt::sky::{RayleighSky, Sun};
use nalgebra::{Rotation3, Vector3};
use serde::Deserialize;
use std::path::{Path, PathBuf};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    environment: EnvironmentSpec,
    camera: CameraSpec,
    #[serde(default)]
    settings: SettingsSpec,
    material: Vec<MaterialSpec>,
    mesh: Vec<MeshSpec>,
}

/// A sphere's tessellation when a scene file does not say: rings of latitude and segments
/// of longitude.
fn default_rings() -> usize {
    32
}

fn default_segments() -> usize {
    64
}

/// The sky's sun when a scene file does not say: a directional light (the built-in
/// scene's choice, `docs/pprt.md`).
fn default_sun() -> String {
    Sun::Directional.name().into()
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
enum EnvironmentSpec {
    Sky {
        sun_elevation_deg: f64,
        sun_azimuth_deg: f64,
        #[serde(default = "default_sun")]
        sun: String,
    },
    Npz {
        path: String,
        #[serde(default)]
        up: Up,
    },
    Exr {
        path: String,
        #[serde(default)]
        up: Up,
    },
    Constant {
        #[serde(deserialize_with = "exactly")]
        radiance: [f64; 3],
    },
}

/// An unpolarized environment of the same radiance per channel from every direction:
/// `f_00 = sqrt(4 pi) L` in `s0` (`Y_00 = 1/sqrt(4 pi)`), band limit `lmax`. Error: a
/// radiance negative or not finite.
fn constant_environment(radiance: [f64; 3], lmax: usize) -> Result<PshVector> {
    if let Some(r) = radiance.iter().find(|r| !(r.is_finite() && **r >= 0.0)) {
        return Err(Error::InvalidArgument {
            name: "constant radiance",
            value: r.to_string(),
            reason: "finite and non-negative".into(),
        });
    }
    let n = crate::sh::num_coeffs(lmax) * 4;
    let mut data = vec![0.0; 3 * n];
    for (c, r) in radiance.iter().enumerate() {
        data[c * n] = (4.0 * std::f64::consts::PI).sqrt() * r;
    }
    PshVector::from_data(lmax, Codomain::Full, 3, data)
}

/// The up axis of a file's coordinates (psh's world is `+z` up).
#[derive(Clone, Copy, Default, Deserialize)]
#[serde(rename_all = "lowercase")]
enum Up {
    #[default]
    Z,
    Y,
}

impl Up {
    /// The rotation taking the file's coordinates to psh's (`+y` to `+z` for `y`).
    fn rotation(self) -> Rotation3<f64> {
        match self {
            Up::Z => Rotation3::identity(),
            Up::Y => Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2),
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraSpec {
    #[serde(deserialize_with = "exactly")]
    position: [f64; 3],
    #[serde(deserialize_with = "exactly")]
    target: [f64; 3],
    fov_deg: f64,
    width: usize,
    height: usize,
    #[serde(default)]
    roll_deg: f64,
}

#[derive(Deserialize)]
#[serde(default, deny_unknown_fields)]
struct SettingsSpec {
    l_low: usize,
    l_high: usize,
    rays: usize,
    shadows: bool,
    unpolarized_environment: bool,
}

impl Default for SettingsSpec {
    fn default() -> Self {
        let d = TransferSettings::default();
        Self {
            l_low: d.l_low,
            l_high: d.l_high,
            rays: d.rays,
            shadows: d.shadows(),
            unpolarized_environment: false,
        }
    }
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
enum MaterialSpec {
    Plastic {
        name: String,
        alpha: f64,
        ior: f64,
        albedo: f64,
        #[serde(default)]
        masking: Option<String>,
    },
    Conductor {
        name: String,
        #[serde(default)]
        table: Option<String>,
        #[serde(default, deserialize_with = "exactly_some")]
        eta: Option<[f64; 3]>,
        #[serde(default, deserialize_with = "exactly_some")]
        k: Option<[f64; 3]>,
        alpha: f64,
        #[serde(default)]
        masking: Option<String>,
    },
    Diffuse {
        name: String,
        #[serde(deserialize_with = "exactly")]
        albedo: [f64; 3],
    },
    Npz {
        name: String,
        path: String,
    },
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
enum MeshSpec {
    Sphere {
        #[serde(deserialize_with = "exactly")]
        center: [f64; 3],
        radius: f64,
        material: String,
        #[serde(default = "default_rings")]
        rings: usize,
        #[serde(default = "default_segments")]
        segments: usize,
    },
    Plane {
        #[serde(deserialize_with = "exactly")]
        center: [f64; 3],
        half_size: f64,
        material: String,
    },
    Torus {
        #[serde(deserialize_with = "exactly")]
        center: [f64; 3],
        major_radius: f64,
        minor_radius: f64,
        material: String,
    },
    Obj {
        path: String,
        material: String,
        #[serde(default)]
        up: Up,
    },
}

/// A list of exactly `N` numbers (TOML's reader alone would take the first `N` of a
/// longer list).
fn exactly<'de, D: serde::Deserializer<'de>, const N: usize>(
    d: D,
) -> std::result::Result<[f64; N], D::Error> {
    let v = Vec::<f64>::deserialize(d)?;
    let n = v.len();
    v.try_into()
        .map_err(|_| serde::de::Error::invalid_length(n, &format!("{N} numbers").as_str()))
}

/// As [`exactly`], for an optional field.
fn exactly_some<'de, D: serde::Deserializer<'de>, const N: usize>(
    d: D,
) -> std::result::Result<Option<[f64; N]>, D::Error> {
    exactly(d).map(Some)
}

/// Band limit of a coefficient environment as the reference renderer's source
/// ([`EnvironmentSource::Coefficients`]; evaluated per sample, so bounded). Maps are
/// sampled at their own resolution ([`EnvironmentSource::Map`]).
pub const SOURCE_LMAX: usize = 32;

/// The shared data directory: `$PSH_DATA_DIR`, else `../shared/data`.
pub fn data_dir() -> PathBuf {
    std::env::var_os("PSH_DATA_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("../shared/data"))
}

/// The parsed scene file `path`, nothing loaded or projected yet.
fn read_spec(path: &Path) -> Result<SceneFile> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::Io {
        path: path.to_path_buf(),
        source: e,
    })?;
    // The parser's message quotes the file's line: each line clipped.
    toml::from_str(&text).map_err(|e| {
        let lines: Vec<String> = e.to_string().lines().map(clip).collect();
        Error::MalformedFile {
            path: path.to_path_buf(),
            reason: lines.join("\n"),
        }
    })
}

impl SettingsSpec {
    fn transfer(&self) -> TransferSettings {
        TransferSettings {
            l_low: self.l_low,
            l_high: self.l_high,
            rays: self.rays,
            visibility: if self.shadows {
                Visibility::Rays
            } else {
                Visibility::Off
            },
        }
    }
}

/// The transfer settings of the scene file `path` (its `[settings]`), read without
/// loading meshes or projecting the environment: settings can be checked before any
/// work.
pub fn scene_settings(path: impl AsRef<Path>) -> Result<TransferSettings> {
    Ok(read_spec(path.as_ref())?.settings.transfer())
}

/// Reads a scene file; the environment is band-limited to `l_high` (at least the file's
/// `l_low` and `l_high`).
pub fn load_scene(path: impl AsRef<Path>, l_high: usize) -> Result<(Scene, TransferSettings)> {
    let path = path.as_ref();
    let malformed = |reason: String| Error::MalformedFile {
        path: path.to_path_buf(),
        reason,
    };
    let spec = read_spec(path)?;
    let base = path.parent().unwrap_or(Path::new("."));
    let resolve = |p: &str| -> Result<PathBuf> {
        match p.strip_prefix("data:") {
            Some(_) if !data_dir().is_dir() => Err(malformed(format!(
                "'{p}' needs the shared data directory {}, which is missing (set PSH_DATA_DIR)",
                data_dir().display()
            ))),
            Some(rest) => Ok(data_dir().join(rest)),
            None => Ok(base.join(p)),
        }
    };
    let settings = spec.settings.transfer();
    let lmax = l_high.max(settings.l_low).max(settings.l_high);
    let field = |name: &str, e: Error| malformed(format!("{name}: {e}"));
    // The reference renderer's environment: the sky itself, or the coefficients to
    // SOURCE_LMAX (or lmax if higher).
    let source_lmax = lmax.max(SOURCE_LMAX);
    let source = match &spec.environment {
        EnvironmentSpec::Sky {
            sun_elevation_deg,
            sun_azimuth_deg,
            sun,
        } => RayleighSky::new(sun_elevation_deg.to_radians(), sun_azimuth_deg.to_radians())
            .and_then(|sky| Ok(EnvironmentSource::Sky(sky.with_sun(Sun::from_name(sun)?))))
            .map_err(|e| field("environment", e))?,
        EnvironmentSpec::Npz { path: p, up } => {
            let v =
                crate::io::npz::read_psh_npz(resolve(p)?)?.converted(FieldArgument::TowardsSource);
            let v = v
                .truncated(source_lmax.min(v.lmax()))
                .map_err(|e| field("environment.path", e))?;
            EnvironmentSource::Coefficients(turn(&v, *up)?)
        }
        EnvironmentSpec::Exr { path: p, up } => {
            let map = crate::io::exr::read_stokes_map(resolve(p)?)?;
            EnvironmentSource::Map {
                map,
                to_world: up.rotation(),
            }
        }
        EnvironmentSpec::Constant { radiance } => EnvironmentSource::Coefficients(
            constant_environment(*radiance, source_lmax)
                .map_err(|e| field("environment.radiance", e))?,
        ),
    };
    // Unpolarized: the intensity alone, for the reference too (the sky stays analytic,
    // its sun as it was).
    let source = match source {
        _ if !spec.settings.unpolarized_environment => source,
        EnvironmentSource::Sky(sky) => EnvironmentSource::Sky(sky.unpolarized()),
        EnvironmentSource::Coefficients(v) => EnvironmentSource::Coefficients(
            v.with_codomain(Codomain::Intensity)
                .with_codomain(Codomain::Full),
        ),
        EnvironmentSource::Map { map, to_world } => EnvironmentSource::Map {
            map: map.unpolarized(),
            to_world,
        },
    };
    let environment = match &source {
        EnvironmentSource::Sky(sky) => sky.project(lmax),
        EnvironmentSource::Coefficients(v) => v.truncated(lmax),
        EnvironmentSource::Map { map, to_world } => map
            .project(Codomain::Full, lmax)
            .and_then(|v| v.rotated(to_world)),
    }
    .map_err(|e| field("environment", e))?;
    let mut names = Vec::new();
    let mut materials = Vec::new();
    for m in &spec.material {
        let (name, mat) = match m {
            MaterialSpec::Plastic {
                name,
                alpha,
                ior,
                albedo,
                masking,
            } => {
                let at = |e| field(&format!("material '{}'", clip(name)), e);
                let masking = masking_named(masking).map_err(at)?;
                (
                    name,
                    PolarizedPlastic::new(*alpha, *ior, *albedo)
                        .map(|p| SceneMaterial::Plastic(p.with_masking(masking)))
                        .map_err(at)?,
                )
            }
            MaterialSpec::Conductor {
                name,
                table,
                eta,
                k,
                alpha,
                masking,
            } => {
                let at = |key: &str, e| field(&format!("material '{}'.{key}", clip(name)), e);
                let masking = masking_named(masking).map_err(|e| at("masking", e))?;
                let channels: [Conductor; 3] = match (table, eta, k) {
                    (Some(t), None, None) => {
                        let m = Material::from_name(t).map_err(|e| at("table", e))?;
                        [Channel::Red, Channel::Green, Channel::Blue]
                            .map(|c| Conductor::from_material(*alpha, m, c))
                            .into_iter()
                            .collect::<Result<Vec<_>>>()
                            .map_err(|e| at("alpha", e))?
                    }
                    (None, Some(n), Some(k)) => [0, 1, 2]
                        .map(|c| ComplexIor::new(n[c], k[c]))
                        .into_iter()
                        .collect::<Result<Vec<_>>>()
                        .map_err(|e| at("eta, k", e))?
                        .into_iter()
                        .map(|ior| Conductor::with_ior(*alpha, ior))
                        .collect::<Result<Vec<_>>>()
                        .map_err(|e| at("alpha", e))?,
                    _ => {
                        return Err(malformed(format!(
                            "material '{}': a conductor is given by `table` or by `eta` and `k` (RGB), not both",
                            clip(name)
                        )))
                    }
                }
                .try_into()
                .expect("three channels");
                (
                    name,
                    SceneMaterial::Conductor(channels.map(|c| c.with_masking(masking))),
                )
            }
            MaterialSpec::Diffuse { name, albedo } => {
                let lambert = |c: usize| {
                    Lambertian::new(albedo[c])
                        .map_err(|e| field(&format!("material '{}'.albedo", clip(name)), e))
                };
                (
                    name,
                    SceneMaterial::Diffuse([lambert(0)?, lambert(1)?, lambert(2)?]),
                )
            }
            MaterialSpec::Npz { name, path: p } => {
                // The file's input is indexed by travel; the renderer's fields by the
                // direction towards the source.
                let mats = crate::io::npz::read_isotropic_npz(resolve(p)?)?
                    .with_input(FieldArgument::TowardsSource)?;
                let dense = (0..mats.channels())
                    .map(|c| mats.to_dense(c))
                    .collect::<Result<Vec<_>>>()?;
                let rgb: [_; 3] = dense.try_into().map_err(|d: Vec<_>| {
                    malformed(format!(
                        "material '{}': {} channels, not 3",
                        clip(name),
                        d.len()
                    ))
                })?;
                (name, SceneMaterial::Matrices(Box::new(rgb)))
            }
        };
        if names.contains(name) {
            return Err(malformed(format!(
                "material name '{}' is defined twice",
                clip(name)
            )));
        }
        names.push(name.clone());
        materials.push(mat);
    }
    let material_index = |name: &str| {
        names.iter().position(|n| n == name).ok_or_else(|| {
            malformed(format!(
                "mesh material '{}' is not defined (materials: {})",
                clip(name),
                clip(&format!("{names:?}"))
            ))
        })
    };
    let mut objects = Vec::new();
    for (k, m) in spec.mesh.iter().enumerate() {
        let (mesh, material) = match m {
            MeshSpec::Sphere {
                center,
                radius,
                material,
                rings,
                segments,
            } => {
                // Per vertex: position and normal (48 bytes), two triangles (24).
                crate::budget::check("sphere mesh", &[*rings + 1, *segments + 1], 72)?;
                (Mesh::sphere(*center, *radius, *rings, *segments), material)
            }
            MeshSpec::Plane {
                center,
                half_size,
                material,
            } => (Mesh::plane(*center, *half_size, 24), material),
            MeshSpec::Torus {
                center,
                major_radius,
                minor_radius,
                material,
            } => (
                Mesh::torus(*center, *major_radius, *minor_radius, 64, 24),
                material,
            ),
            MeshSpec::Obj {
                path: p,
                material,
                up,
            } => (
                resolve(p)
                    .and_then(super::obj::read_obj)
                    .map(|m| m.rotated(&up.rotation())),
                material,
            ),
        };
        objects.push(SceneObject {
            mesh: mesh.map_err(|e| field(&format!("mesh {k}"), e))?,
            material: material_index(material)?,
        });
    }
    let c = &spec.camera;
    let camera = Camera::look_at(
        c.position,
        c.target,
        c.fov_deg.to_radians(),
        c.width,
        c.height,
    )
    .and_then(|cam| cam.rolled(c.roll_deg.to_radians()))
    .map_err(|e| field("camera", e))?;
    let scene = Scene::new(objects, materials, environment, camera)
        .and_then(|s| s.with_source(source))
        .map_err(|e| malformed(e.to_string()))?;
    Ok((scene, settings))
}

/// A material's masking-shadowing form: the default when the file does not say.
fn masking_named(name: &Option<String>) -> Result<Masking> {
    name.as_deref()
        .map_or(Ok(Masking::default()), Masking::from_name)
}

/// Coefficients given in a frame with another up axis, turned to psh's world.
fn turn(v: &PshVector, up: Up) -> Result<PshVector> {
    v.rotated(&up.rotation())
}
