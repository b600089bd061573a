//! Scene descriptions and building a [`Scene`] from one: the environment (projected to
//! the band limit), the camera, the settings, the materials (pBRDF models or measured
//! matrices) and the meshes. A scene file (`io::read_scene_spec`, format in
//! `docs/pprt.md`) deserializes into a [`SceneSpec`]; the files it names (coefficient
//! vectors, maps, pBRDF matrices, OBJ meshes) are read through [`SceneFiles`] as the
//! build reaches them. Errors name the file and the field.

use super::mesh::Mesh;
use super::scene::{
    Camera, EnvironmentSource, Scene, SceneMaterial, SceneObject, TabulatedMaterial,
};
use super::settings::{high_orders_from_number, high_orders_number, TransferSettings, Visibility};
use super::sky::{RayleighSky, Sun};
use crate::error::{clip, Error, Result};
use crate::map::StokesMap;
use crate::optics::{
    Channel, ComplexIor, Conductor, Lambertian, Masking, Material, PolarizedPlastic, TabulatedPbrdf,
};
use crate::polarized::{Codomain, FieldArgument, IsotropicMatrix, PshVector};
use crate::sh::Window;
use nalgebra::{Rotation3, Vector3};
use serde::Deserialize;
use std::path::Path;

/// A scene as a scene file describes it, nothing read or projected yet.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneSpec {
    /// The light from every direction.
    pub environment: EnvironmentSpec,
    /// The pinhole camera.
    pub camera: CameraSpec,
    /// The transfer's settings (`[settings]`; the defaults when absent).
    #[serde(default)]
    pub settings: SettingsSpec,
    /// The materials, referred to by name from the meshes.
    pub material: Vec<MaterialSpec>,
    /// The meshes, each with a material.
    pub mesh: Vec<MeshSpec>,
}

/// Reads the files a [`SceneSpec`] names (paths as the scene file writes them).
pub trait SceneFiles {
    /// The scene file itself, named by every error.
    fn origin(&self) -> &Path;
    /// A PSH coefficient vector (polarsh `.npz`, RGB).
    fn coefficients(&self, path: &str) -> Result<PshVector>;
    /// A polarized environment map (EXR per Stokes component, `map_s%d.exr`).
    fn map(&self, path: &str) -> Result<StokesMap>;
    /// A measured pBRDF's isotropic coefficient matrices (polarsh ISOBI2 `.npz`).
    fn pbrdf(&self, path: &str) -> Result<IsotropicMatrix>;
    /// A measured pBRDF table (a Mitsuba 3 `.pbsdf`, or a KAIST MAT data file with the
    /// frames of its `info` file).
    fn table(&self, path: &str, info: Option<&str>) -> Result<TabulatedPbrdf>;
    /// A triangle mesh (OBJ).
    fn mesh(&self, path: &str) -> Result<Mesh>;
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

/// The environment: the analytic sky, coefficients, a map, or a constant.
#[derive(Clone, Debug, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum EnvironmentSpec {
    /// The analytic Rayleigh sky ([`RayleighSky`]) with its sun at an elevation and an
    /// azimuth in degrees, carried as [`Sun`] names it.
    Sky {
        /// Degrees above the horizon.
        sun_elevation_deg: f64,
        /// Degrees from `+x` towards `+y`.
        sun_azimuth_deg: f64,
        /// `lobe` or `directional` ([`Sun`]).
        #[serde(default = "default_sun")]
        sun: String,
    },
    /// A PSH coefficient vector (polarsh `.npz`, RGB).
    Npz {
        /// The file.
        path: String,
        /// The file's up axis.
        #[serde(default)]
        up: Up,
    },
    /// A polarized environment map, one EXR per Stokes component (`map_s%d.exr`): the
    /// background and the reference sample its texels, the transfer its projection.
    Exr {
        /// The files' pattern.
        path: String,
        /// The files' up axis.
        #[serde(default)]
        up: Up,
    },
    /// Unpolarized, the same radiance from every direction.
    Constant {
        /// Radiance per channel (RGB).
        #[serde(deserialize_with = "exactly")]
        radiance: [f64; 3],
    },
}

/// An unpolarized environment of the same radiance per channel from every direction:
/// `f_00 = sqrt(4 pi) L` in `s0` (`Y_00 = 1/sqrt(4 pi)`), band limit `lmax`. Error: a
/// radiance negative or not finite.
fn constant_environment(radiance: [f64; 3], lmax: usize) -> Result<PshVector> {
    if let Some(r) = radiance.iter().find(|r| !(r.is_finite() && **r >= 0.0)) {
        return Err(Error::invalid(
            "constant radiance",
            r.to_string(),
            "finite and non-negative",
        ));
    }
    let n = crate::sh::num_coeffs(lmax) * 4;
    let mut data = vec![0.0; 3 * n];
    for (c, r) in radiance.iter().enumerate() {
        data[c * n] = (4.0 * std::f64::consts::PI).sqrt() * r;
    }
    PshVector::from_data(lmax, Codomain::Full, 3, data)
}

/// The up axis of a file's coordinates (psh's world is `+z` up).
#[derive(Clone, Copy, Debug, Default, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Up {
    /// `+z` up, as psh.
    #[default]
    Z,
    /// `+y` up (turned to `+z`).
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

/// The camera ([`Camera::look_at`], [`Camera::rolled`]).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraSpec {
    /// The eye.
    #[serde(deserialize_with = "exactly")]
    pub position: [f64; 3],
    /// The point looked at.
    #[serde(deserialize_with = "exactly")]
    pub target: [f64; 3],
    /// Vertical field of view in degrees.
    pub fov_deg: f64,
    /// Image width in pixels.
    pub width: usize,
    /// Image height in pixels.
    pub height: usize,
    /// Turn about the view axis in degrees.
    #[serde(default)]
    pub roll_deg: f64,
}

/// A scene file's `[settings]` ([`TransferSettings`]; `l_high = 0`: no high orders).
#[derive(Clone, Debug, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SettingsSpec {
    /// Band limit of the transfer.
    pub l_low: usize,
    /// Band limit of the high orders (0 or `l_low`: none).
    pub l_high: usize,
    /// Visibility rays per vertex.
    pub rays: usize,
    /// Ray-cast shadows (`false`: none).
    pub shadows: bool,
    /// The environment's `s0` alone (`s1..s3` dropped), for the reference too.
    pub unpolarized_environment: bool,
    /// The window tapering the environment's band limit in a render job (`none`, `hann`,
    /// `lanczos`: [`Window`]; a job's own window replaces it).
    pub window: String,
}

impl Default for SettingsSpec {
    fn default() -> Self {
        let d = TransferSettings::default();
        Self {
            l_low: d.l_low,
            l_high: high_orders_number(d.l_high),
            rays: d.rays,
            shadows: d.shadows(),
            unpolarized_environment: false,
            window: Window::None.name().into(),
        }
    }
}

impl SettingsSpec {
    /// The window named by `window`. Error: another name.
    pub fn window(&self) -> Result<Window> {
        Window::from_name(&self.window)
    }

    /// The transfer settings these say.
    pub fn transfer(&self) -> TransferSettings {
        TransferSettings {
            l_low: self.l_low,
            l_high: high_orders_from_number(self.l_high),
            rays: self.rays,
            visibility: if self.shadows {
                Visibility::Rays
            } else {
                Visibility::Off
            },
        }
    }
}

/// A material by model, or measured.
#[derive(Clone, Debug, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum MaterialSpec {
    /// A dielectric coat over a Lambertian base ([`PolarizedPlastic`]).
    Plastic {
        /// The name meshes refer to.
        name: String,
        /// GGX roughness.
        alpha: f64,
        /// Index of refraction of the coat.
        ior: f64,
        /// Albedo of the base.
        albedo: f64,
        /// Smith's masking-shadowing form ([`Masking`] names it).
        #[serde(default)]
        masking: Option<String>,
    },
    /// A rough conductor ([`Conductor`]): a PF Table 1 material or RGB `eta`, `k`.
    Conductor {
        /// The name meshes refer to.
        name: String,
        /// A PF Table 1 name ([`Material`]).
        #[serde(default)]
        table: Option<String>,
        /// Real part of the index per channel.
        #[serde(default, deserialize_with = "exactly_some")]
        eta: Option<[f64; 3]>,
        /// Extinction coefficient per channel.
        #[serde(default, deserialize_with = "exactly_some")]
        k: Option<[f64; 3]>,
        /// GGX roughness.
        alpha: f64,
        /// Smith's masking-shadowing form ([`Masking`] names it).
        #[serde(default)]
        masking: Option<String>,
    },
    /// A depolarizing Lambertian ([`Lambertian`]).
    Diffuse {
        /// The name meshes refer to.
        name: String,
        /// Albedo per channel.
        #[serde(deserialize_with = "exactly")]
        albedo: [f64; 3],
    },
    /// A measured pBRDF: polarsh ISOBI2 coefficient matrices, one per channel.
    Npz {
        /// The name meshes refer to.
        name: String,
        /// The file.
        path: String,
    },
    /// A measured pBRDF table ([`TabulatedMaterial`]): projected at the render's band
    /// limit, evaluated as it is by the reference renderer.
    Table {
        /// The name meshes refer to.
        name: String,
        /// The table: a Mitsuba 3 `.pbsdf`, or a KAIST dataset MAT data file.
        path: String,
        /// A KAIST data file's info file (its per-sample Stokes frames).
        #[serde(default)]
        info: Option<String>,
    },
}

/// A mesh: a primitive or an OBJ file.
#[derive(Clone, Debug, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum MeshSpec {
    /// A UV sphere ([`Mesh::sphere`]).
    Sphere {
        /// Centre.
        #[serde(deserialize_with = "exactly")]
        center: [f64; 3],
        /// Radius.
        radius: f64,
        /// The material's name.
        material: String,
        /// Rings of latitude.
        #[serde(default = "default_rings")]
        rings: usize,
        /// Segments of longitude.
        #[serde(default = "default_segments")]
        segments: usize,
    },
    /// A square in the plane `z = center.z` ([`Mesh::plane`]).
    Plane {
        /// Centre.
        #[serde(deserialize_with = "exactly")]
        center: [f64; 3],
        /// Half the side.
        half_size: f64,
        /// The material's name.
        material: String,
    },
    /// A torus about `+z` ([`Mesh::torus`]).
    Torus {
        /// Centre.
        #[serde(deserialize_with = "exactly")]
        center: [f64; 3],
        /// Radius of the centre circle.
        major_radius: f64,
        /// Radius of the tube.
        minor_radius: f64,
        /// The material's name.
        material: String,
    },
    /// A Wavefront OBJ file.
    Obj {
        /// The file.
        path: String,
        /// The material's name.
        material: String,
        /// The file's up axis.
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

impl SceneSpec {
    /// The files the scene names, as written: the environment's (an EXR map's pattern or
    /// component file once), the measured materials' and the OBJ meshes'.
    pub fn file_names(&self) -> Vec<&str> {
        let environment = match &self.environment {
            EnvironmentSpec::Npz { path, .. } | EnvironmentSpec::Exr { path, .. } => {
                Some(path.as_str())
            }
            _ => None,
        };
        let materials = self.material.iter().flat_map(|m| match m {
            MaterialSpec::Npz { path, .. } => vec![path.as_str()],
            MaterialSpec::Table { path, info, .. } => std::iter::once(path.as_str())
                .chain(info.as_deref())
                .collect(),
            _ => vec![],
        });
        let meshes = self.mesh.iter().filter_map(|m| match m {
            MeshSpec::Obj { path, .. } => Some(path.as_str()),
            _ => None,
        });
        environment
            .into_iter()
            .chain(materials)
            .chain(meshes)
            .collect()
    }
}

/// Band limit of a coefficient environment as the reference renderer's source
/// ([`EnvironmentSource::Coefficients`]; evaluated per sample, so bounded). Maps are
/// sampled at their own resolution ([`EnvironmentSource::Map`]).
pub const SOURCE_LMAX: usize = 32;

impl SceneSpec {
    /// The scene, its environment band-limited to `lmax` (at least the settings'
    /// [`TransferSettings::environment_lmax`]), reading the files it names through `files`;
    /// with its transfer settings. Errors name `files.origin()` and the field.
    pub fn build(&self, lmax: usize, files: &dyn SceneFiles) -> Result<(Scene, TransferSettings)> {
        let malformed = |reason: String| Error::malformed(files.origin().to_path_buf(), reason);
        let field = |name: &str, e: Error| malformed(format!("{name}: {e}"));
        let settings = self.settings.transfer();
        self.settings
            .window()
            .map_err(|e| field("settings.window", e))?;
        let lmax = lmax.max(settings.environment_lmax());
        let source = self.source(lmax, files, &field)?;
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
        for m in &self.material {
            let (name, mat) = material(m, files, &malformed, &field)?;
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
        for (k, m) in self.mesh.iter().enumerate() {
            let (mesh, material) = mesh(m, files)?;
            objects.push(SceneObject {
                mesh: mesh.map_err(|e| field(&format!("mesh {k}"), e))?,
                material: material_index(material)?,
            });
        }
        let c = &self.camera;
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

    /// The reference renderer's environment: the sky itself, or the coefficients to
    /// [`SOURCE_LMAX`] (or `lmax` if higher); only the intensity with
    /// `unpolarized_environment` (the sky stays analytic, its sun as it was).
    fn source(
        &self,
        lmax: usize,
        files: &dyn SceneFiles,
        field: &dyn Fn(&str, Error) -> Error,
    ) -> Result<EnvironmentSource> {
        let source_lmax = lmax.max(SOURCE_LMAX);
        let source = match &self.environment {
            EnvironmentSpec::Sky {
                sun_elevation_deg,
                sun_azimuth_deg,
                sun,
            } => RayleighSky::new(sun_elevation_deg.to_radians(), sun_azimuth_deg.to_radians())
                .and_then(|sky| Ok(EnvironmentSource::Sky(sky.with_sun(Sun::from_name(sun)?))))
                .map_err(|e| field("environment", e))?,
            EnvironmentSpec::Npz { path, up } => {
                let v = files
                    .coefficients(path)?
                    .converted(FieldArgument::TowardsSource);
                let v = v
                    .truncated(source_lmax.min(v.lmax()))
                    .map_err(|e| field("environment.path", e))?;
                EnvironmentSource::Coefficients(v.rotated(&up.rotation())?)
            }
            EnvironmentSpec::Exr { path, up } => EnvironmentSource::Map {
                map: files.map(path)?,
                to_world: up.rotation(),
            },
            EnvironmentSpec::Constant { radiance } => EnvironmentSource::Coefficients(
                constant_environment(*radiance, source_lmax)
                    .map_err(|e| field("environment.radiance", e))?,
            ),
        };
        Ok(match source {
            _ if !self.settings.unpolarized_environment => source,
            EnvironmentSource::Sky(sky) => EnvironmentSource::Sky(sky.unpolarized()),
            EnvironmentSource::Coefficients(v) => EnvironmentSource::Coefficients(
                v.with_codomain(Codomain::Intensity)
                    .with_codomain(Codomain::Full),
            ),
            EnvironmentSource::Map { map, to_world } => EnvironmentSource::Map {
                map: map.unpolarized(),
                to_world,
            },
        })
    }
}

/// One material of a scene and its name.
fn material<'a>(
    m: &'a MaterialSpec,
    files: &dyn SceneFiles,
    malformed: &dyn Fn(String) -> Error,
    field: &dyn Fn(&str, Error) -> Error,
) -> Result<(&'a String, SceneMaterial)> {
    Ok(match m {
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
        MaterialSpec::Npz { name, path } => {
            // The file's input is indexed by travel; the renderer's fields by the
            // direction towards the source.
            let mats = files
                .pbrdf(path)?
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
        MaterialSpec::Table { name, path, info } => {
            let table = files.table(path, info.as_deref())?;
            let m = TabulatedMaterial::new(table)
                .map_err(|e| field(&format!("material '{}'", clip(name)), e))?;
            (name, SceneMaterial::Tabulated(Box::new(m)))
        }
    })
}

/// One mesh of a scene (or the error of making it) and its material's name.
fn mesh<'a>(m: &'a MeshSpec, files: &dyn SceneFiles) -> Result<(Result<Mesh>, &'a String)> {
    Ok(match m {
        MeshSpec::Sphere {
            center,
            radius,
            material,
            rings,
            segments,
        } => {
            // Per vertex: position and normal (48 bytes), two triangles (24), and their
            // two entries in the scene's BVH, checked before the mesh is made.
            crate::budget::check(
                &format!("the sphere mesh of {}", files.origin().display()),
                &[rings.saturating_add(1), segments.saturating_add(1)],
                72 + 2 * super::Scene::TRIANGLE_BYTES,
            )?;
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
        MeshSpec::Obj { path, material, up } => (
            files.mesh(path).map(|m| m.rotated(&up.rotation())),
            material,
        ),
    })
}

/// A material's masking-shadowing form: the default when the file does not say.
fn masking_named(name: &Option<String>) -> Result<Masking> {
    name.as_deref()
        .map_or(Ok(Masking::default()), Masking::from_name)
}
