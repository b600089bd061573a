//! Scenes: meshes with materials, the environment's PSH coefficients and a camera; ray
//! queries through a bounding volume hierarchy (the `bvh` crate).

use super::light::DirectionalLight;
use super::mesh::Mesh;
use super::mirrored::MirroredBelow;
use super::sky::{vertical_turn, RayleighSky, Sun};
use super::traversal::{first_hit, Wanted};
use crate::error::{Error, Result};
use crate::geometry::frame::{FrameField, ThetaPhiFrameField};
use crate::map::StokesMap;
use crate::optics::{Channel, Conductor, Lambertian, Material, PolarizedPlastic, TabulatedPbrdf};
use crate::polarized::{
    project_operator, FieldArgument, PshEvaluator, PshMatrix, PshVector, SpinBlock22,
};
use crate::stokes::MuellerField;
use crate::stokes::{StokesComponents, StokesVector};
use bvh::aabb::{Aabb, Bounded};
use bvh::bounding_hierarchy::BHShape;
use bvh::bvh::Bvh;
use bvh::ray::Ray;
use nalgebra::{Point3, Rotation3, Vector3};
use std::sync::Arc;

/// A pBRDF of the scene, RGB.
#[derive(Clone, Debug)]
pub enum SceneMaterial {
    /// A dielectric with a depolarizing diffuse base ([`PolarizedPlastic`]), the same in
    /// every channel.
    Plastic(PolarizedPlastic),
    /// A rough conductor per channel (RGB: complex index, GGX roughness and masking form,
    /// [`Conductor`]; [`Self::conductor`] for one of the PF table).
    Conductor([Conductor; 3]),
    /// A depolarizing Lambertian reflector per channel (RGB albedos, [`Lambertian`]).
    Diffuse([Lambertian; 3]),
    /// Coefficient matrices given directly (RGB), e.g. a measured pBRDF read from a
    /// polarsh `.npz`; truncated to the band limit asked for.
    Matrices(Box<[PshMatrix; 3]>),
    /// A measured table, projected at the band limit asked for.
    Tabulated(Box<TabulatedMaterial>),
}

/// A measured pBRDF table as a scene's material: as read (its bands: what Mitsuba 3's
/// `measured_polarized` reads) and in RGB (the five KAIST bands converted as the
/// dataset's code does, [`TabulatedPbrdf::to_rgb`]; three channels taken as R, G, B; one
/// channel as grey).
#[derive(Clone, Debug)]
pub struct TabulatedMaterial {
    bands: Arc<TabulatedPbrdf>,
    rgb: Arc<TabulatedPbrdf>,
}

impl TabulatedMaterial {
    /// The material of `table`. Error: a table of 2, 4 or more than 5 channels, or of 5
    /// other than the KAIST bands.
    pub fn new(table: TabulatedPbrdf) -> Result<Self> {
        let rgb = match table.wavelengths_nm().len() {
            3 => table.clone(),
            1 => {
                let values = table
                    .values()
                    .chunks_exact(16)
                    .flat_map(|m| m.iter().chain(m).chain(m).copied())
                    .collect();
                TabulatedPbrdf::new(
                    table.phi_d().to_vec(),
                    table.theta_d().to_vec(),
                    table.theta_h().to_vec(),
                    vec![table.wavelengths_nm()[0]; 3],
                    values,
                )?
            }
            _ => table.to_rgb()?,
        };
        Ok(Self {
            bands: Arc::new(table),
            rgb: Arc::new(rgb),
        })
    }

    /// The table as read.
    pub fn bands(&self) -> &TabulatedPbrdf {
        &self.bands
    }

    /// The table in R, G, B.
    pub fn rgb(&self) -> &Arc<TabulatedPbrdf> {
        &self.rgb
    }
}

impl SceneMaterial {
    /// The conductor `material` of the PF table (its index per channel) with GGX
    /// roughness `alpha`. Error: `alpha` out of [`crate::optics::Ggx::new`]'s range.
    pub fn conductor(material: Material, alpha: f64) -> Result<Self> {
        let c = |channel| Conductor::from_material(alpha, material, channel);
        Ok(Self::Conductor([
            c(Channel::Red)?,
            c(Channel::Green)?,
            c(Channel::Blue)?,
        ]))
    }

    /// The PSH coefficient matrices (RGB) in the shading frame (normal `+z`), band limit
    /// `lmax`, projected on the exact grid of `2 lmax + 2`; analytic models and tables with
    /// their output below the shading plane mirrored ([`MirroredBelow`],
    /// `proofs/mirrored-output.md`), measured matrices as given.
    pub fn matrices(&self, lmax: usize) -> Result<[PshMatrix; 3]> {
        let project = |field: &dyn MuellerField| {
            project_operator(
                &MirroredBelow(field),
                lmax,
                2 * lmax + 2,
                SpinBlock22::ComplexPair,
            )
        };
        match self {
            Self::Matrices(m) => Ok([
                m[0].truncated(lmax)?,
                m[1].truncated(lmax)?,
                m[2].truncated(lmax)?,
            ]),
            Self::Diffuse(d) => Ok([project(&d[0])?, project(&d[1])?, project(&d[2])?]),
            Self::Plastic(p) => {
                let m = project(p)?;
                Ok([m.clone(), m.clone(), m])
            }
            Self::Conductor(c) => Ok([project(&c[0])?, project(&c[1])?, project(&c[2])?]),
            Self::Tabulated(t) => {
                let c = |k| t.rgb().channel(k);
                Ok([project(&c(0)?)?, project(&c(1)?)?, project(&c(2)?)?])
            }
        }
    }
}

/// A pinhole camera: position, frame (`x` image-right, `y` image-down, `z` forward),
/// vertical field of view and image size.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// The centre of projection, world coordinates.
    pub position: [f64; 3],
    /// `x` image-right, `y` image-down, `z` forward, in world coordinates.
    pub frame: crate::geometry::frame::Frame,
    /// The full vertical field of view, radians.
    pub fov_y: f64,
    /// Image width in pixels.
    pub width: usize,
    /// Image height in pixels.
    pub height: usize,
}

impl Camera {
    /// Bytes a render holds per pixel: the RGB Stokes image, the background, the
    /// primary hit and the pictures, rounded up.
    pub const PIXEL_BYTES: usize = 512;

    /// A camera at `position` looking at `target` with world up `+z`. Errors: a degenerate
    /// view, and an image whose rendering (Stokes components, hits and background per
    /// pixel, [`Self::PIXEL_BYTES`]) exceeds the memory budget ([`crate::budget`]).
    pub fn look_at(
        position: [f64; 3],
        target: [f64; 3],
        fov_y: f64,
        width: usize,
        height: usize,
    ) -> Result<Self> {
        let f = Vector3::from(target) - Vector3::from(position);
        if f.norm() == 0.0 || width == 0 || height == 0 || !(fov_y > 0.0 && fov_y < 3.0) {
            return Err(Error::invalid(
                "camera",
                format!("{position:?} -> {target:?}, fov {fov_y}, {width} x {height}"),
                "distinct position and target, fov in (0, 3) radians, non-empty image",
            ));
        }
        crate::budget::check("the rendered image", &[width, height], Self::PIXEL_BYTES)?;
        let f = f.normalize();
        let frame = crate::geometry::frame::Frame::from_z_and_y([f.x, f.y, f.z], [0.0, 0.0, -1.0])?;
        Ok(Self {
            position,
            frame,
            fov_y,
            width,
            height,
        })
    }

    /// The largest elevation of an orbit's camera above or below the pivot, radians
    /// (89 degrees: the world's up `+z` stays off the view axis).
    pub const MAX_ORBIT_ELEVATION: f64 = 89.0 * std::f64::consts::PI / 180.0;

    /// This camera moved on a sphere about `pivot` and looking at it, `width x height`
    /// pixels, same field of view: the azimuth of `position - pivot` about the world's
    /// vertical `+z` plus `azimuth`, its elevation plus `elevation` (radians), its
    /// distance divided by `zoom` ([`Self::look_at`]). Errors: a non-finite angle, a zoom
    /// outside `(0, 1000]`, a resulting elevation beyond [`Self::MAX_ORBIT_ELEVATION`], a
    /// camera at the pivot, and as [`Self::look_at`].
    pub fn orbited(
        &self,
        pivot: [f64; 3],
        azimuth: f64,
        elevation: f64,
        zoom: f64,
        width: usize,
        height: usize,
    ) -> Result<Self> {
        let offset = Vector3::from(self.position) - Vector3::from(pivot);
        let r = offset.norm();
        let el = (offset.z / r).clamp(-1.0, 1.0).asin() + elevation;
        let az = offset.y.atan2(offset.x) + azimuth;
        let inside = el.abs() <= Self::MAX_ORBIT_ELEVATION && zoom > 0.0 && zoom <= 1000.0;
        if !(azimuth.is_finite() && inside) || r == 0.0 {
            return Err(Error::invalid(
                "camera orbit",
                format!(
                    "azimuth {azimuth}, elevation {elevation} (to {el}), zoom {zoom}, distance {r}"
                ),
                "finite angles, an elevation within 89 degrees of the horizontal, a zoom in (0, 1000], a camera off the pivot",
            ));
        }
        let d = r / zoom;
        let position = [
            pivot[0] + d * el.cos() * az.cos(),
            pivot[1] + d * el.cos() * az.sin(),
            pivot[2] + d * el.sin(),
        ];
        Self::look_at(position, pivot, self.fov_y, width, height)
    }

    /// This camera turned by `angle` (radians) about its forward axis, right-handed about
    /// it (image-right turns towards image-down, so the scene turns the other way in the
    /// image): the frame `R_z(angle) F` of PSH (14). Error: a non-finite angle.
    pub fn rolled(&self, angle: f64) -> Result<Self> {
        Ok(Self {
            frame: self.frame.rotated_about_z(angle)?,
            ..self.clone()
        })
    }

    /// The unit direction into the scene through the centre of pixel `(i, j)` (column,
    /// row from the top).
    pub fn pixel_direction(&self, i: usize, j: usize) -> [f64; 3] {
        self.direction_at(i as f64 + 0.5, j as f64 + 0.5)
    }

    /// The unit direction into the scene through the image point `(x, y)` in pixels from
    /// the top-left corner (`(i + 1/2, j + 1/2)` is pixel `(i, j)`'s centre).
    pub fn direction_at(&self, x: f64, y: f64) -> [f64; 3] {
        let t = (0.5 * self.fov_y).tan();
        let aspect = self.width as f64 / self.height as f64;
        let x = (2.0 * x / self.width as f64 - 1.0) * t * aspect;
        let y = (2.0 * y / self.height as f64 - 1.0) * t;
        let d = (self.frame.x() * x + self.frame.y() * y + self.frame.z()).normalize();
        [d.x, d.y, d.z]
    }
}

/// A mesh with the index of its material.
#[derive(Clone, Debug)]
pub struct SceneObject {
    /// The triangle mesh, world coordinates.
    pub mesh: Mesh,
    /// Index into [`Scene::materials`].
    pub material: usize,
}

/// One triangle for the BVH.
#[derive(Clone)]
struct Tri {
    object: usize,
    index: usize,
    aabb: Aabb<f64, 3>,
    node: usize,
}

impl Bounded<f64, 3> for Tri {
    fn aabb(&self) -> Aabb<f64, 3> {
        self.aabb
    }
}

impl BHShape<f64, 3> for Tri {
    fn set_bh_node_index(&mut self, index: usize) {
        self.node = index;
    }
    fn bh_node_index(&self) -> usize {
        self.node
    }
}

/// A ray hit: object, triangle, distance and barycentric coordinates `(u, v)` of the
/// second and third vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Index into [`Scene::objects`].
    pub object: usize,
    /// Index of the triangle in the object's mesh.
    pub triangle: usize,
    /// Distance from the ray's origin along its (unit) direction, scene units.
    pub distance: f64,
    /// Barycentric weight of the triangle's second vertex.
    pub u: f64,
    /// Barycentric weight of the triangle's third vertex.
    pub v: f64,
}

/// Where the scene's environment comes from, for the reference renderer
/// ([`super::Reference`]): PPRT uses its band-limited coefficients.
#[derive(Clone, Debug)]
pub enum EnvironmentSource {
    /// The analytic sky, evaluated exactly.
    Sky(RayleighSky),
    /// Coefficients only (a `.npz` vector at its own band limit, or a constant).
    Coefficients(PshVector),
    /// A map at its own resolution ([`StokesMap::incident`]), turned into the world by
    /// `to_world` (its direction `w` is the map's `to_world^-1 w`).
    Map {
        /// The map, in its own frame.
        map: StokesMap,
        /// The rotation from the map's frame to the world.
        to_world: Rotation3<f64>,
    },
}

impl EnvironmentSource {
    /// The band limit an evaluator needs for [`Self::incident`] (0 for the sky).
    pub fn lmax(&self) -> usize {
        match self {
            Self::Sky(_) | Self::Map { .. } => 0,
            Self::Coefficients(v) => v.lmax(),
        }
    }

    /// How the analytic sky carries its sun (`None` for coefficients).
    pub fn sun(&self) -> Option<Sun> {
        match self {
            Self::Sky(sky) => Some(sky.sun()),
            Self::Coefficients(_) | Self::Map { .. } => None,
        }
    }

    /// The directional lights that come with the source (the sky's sun with
    /// [`super::Sun::Directional`]), reflected exactly by `src/pprt/direct.rs`.
    pub fn directional_lights(&self) -> Vec<DirectionalLight> {
        match self {
            Self::Sky(sky) => sky.directional_light().into_iter().collect(),
            Self::Coefficients(_) | Self::Map { .. } => Vec::new(),
        }
    }

    /// The source turned by `angle` (radians) about the world's vertical `+z` (PSH (8)):
    /// the sky's sun ([`RayleighSky::turned`]), the coefficients rotated (PSH (35)), the
    /// map's `to_world` followed by the turn. Error: a non-finite angle.
    pub fn turned(&self, angle: f64) -> Result<Self> {
        let turn = vertical_turn(angle)?;
        Ok(match self {
            Self::Sky(sky) => Self::Sky(sky.clone().turned(angle)?),
            Self::Coefficients(v) => Self::Coefficients(v.rotated(&turn)?),
            Self::Map { map, to_world } => Self::Map {
                map: map.clone(),
                to_world: turn * to_world,
            },
        })
    }

    /// The light arriving from the unit direction `w` (towards its source), per channel:
    /// the sky evaluated exactly, coefficients at their own band limit by PSH (30) with
    /// `evaluator` (of band limit at least [`Self::lmax`]), a map's texel holding `w`.
    pub fn incident(&self, evaluator: &mut PshEvaluator, w: [f64; 3]) -> Result<Vec<StokesVector>> {
        match self {
            Self::Coefficients(v) => evaluator.evaluate_all(v, w),
            Self::Map { map, to_world } => {
                let local = to_world.inverse_transform_vector(&Vector3::from(w));
                map.incident(local.into())?
                    .iter()
                    .map(|s| s.rotate(to_world))
                    .collect()
            }
            Self::Sky(sky) => {
                let frame = ThetaPhiFrameField::new().frame(w)?;
                (0..3)
                    .map(|c| {
                        Ok(StokesVector::new(
                            StokesComponents::new(sky.stokes(c, w)?)?,
                            frame,
                        ))
                    })
                    .collect()
            }
        }
    }
}

/// Objects, materials, environment (PSH coefficients, RGB, and their source) and camera,
/// with a BVH over every triangle.
///
/// # Example
///
/// A white sphere under the Rayleigh sky, seen by a small camera: the ray through the
/// image's centre hits the sphere where the geometry says.
///
/// ```
/// use psh::optics::Lambertian;
/// use psh::pprt::{Camera, Mesh, RayleighSky, Scene, SceneMaterial, SceneObject};
/// # fn main() -> psh::Result<()> {
/// let sky = RayleighSky::new(0.6, 1.0)?; // sun elevation and azimuth in radians
/// let white = Lambertian::new(0.8)?;
/// let scene = Scene::new(
///     vec![SceneObject {
///         mesh: Mesh::sphere([0.0, 0.0, 0.0], 1.0, 24, 48)?,
///         material: 0,
///     }],
///     vec![SceneMaterial::Diffuse([white; 3])],
///     sky.project(4)?, // the environment's PSH coefficients, l <= 4
///     Camera::look_at([0.0, -4.0, 0.0], [0.0, 0.0, 0.0], 0.6, 32, 24)?,
/// )?;
/// assert_eq!(scene.triangle_count(), 2 * 24 * 48 - 2 * 48); // caps are fans
/// // Straight at the centre: the sphere's surface, 3 units away (within its tessellation).
/// let hit = scene.intersect([0.0, -4.0, 0.0], [0.0, 1.0, 0.0], 0.0).unwrap();
/// assert!((hit.distance - 3.0).abs() < 0.01);
/// // Beside the sphere: the sky.
/// assert!(scene.intersect([0.0, -4.0, 0.0], [0.6, 0.8, 0.0], 0.0).is_none());
/// # Ok(())
/// # }
/// ```
#[derive(Clone)]
pub struct Scene {
    objects: Vec<SceneObject>,
    materials: Vec<SceneMaterial>,
    environment: PshVector,
    source: EnvironmentSource,
    window: crate::sh::Window,
    camera: Camera,
    tris: Vec<Tri>,
    bvh: Bvh<f64, 3>,
    scale: f64,
}

/// Shadow rays start this fraction of the scene's size above the surface
/// ([`Scene::shadow_origin`]): far above the rounding of the ray-triangle test in `f64`,
/// far below a mesh's features. At `1e-4` light leaked through the crevices of buddha (its
/// mean 1% brighter than Mitsuba 3's, `docs/mitsuba.md`).
pub(crate) const SHADOW_RAY_OFFSET: f64 = 1e-7;

impl Scene {
    /// Bytes per triangle of the ray-query structure: its record with its bounding box,
    /// two BVH nodes and the build's index (336 bytes, measured by a test), with room for
    /// the build's temporaries. Checked against the memory budget before the BVH is
    /// built.
    pub const TRIANGLE_BYTES: usize = 768;

    /// Errors: an object naming a material that does not exist, an environment without 3
    /// channels, more triangles than the memory budget holds ([`Self::TRIANGLE_BYTES`]
    /// each).
    pub fn new(
        objects: Vec<SceneObject>,
        materials: Vec<SceneMaterial>,
        environment: PshVector,
        camera: Camera,
    ) -> Result<Self> {
        if let Some((k, o)) = objects
            .iter()
            .enumerate()
            .find(|(_, o)| o.material >= materials.len())
        {
            return Err(Error::invalid(
                "object material",
                format!("object {k}: material {}", o.material),
                format!("{} materials", materials.len()),
            ));
        }
        if environment.channels() != 3 {
            return Err(Error::invalid(
                "environment",
                format!("{} channels", environment.channels()),
                "RGB (3 channels)",
            ));
        }
        FieldArgument::TowardsSource.expect(
            environment.argument(),
            "environment",
            "a scene's incident light",
        )?;
        let triangles = objects.iter().map(|o| o.mesh.triangles().len()).sum();
        crate::budget::check("the scene's BVH", &[triangles], Self::TRIANGLE_BYTES)?;
        let mut tris = Vec::with_capacity(triangles);
        for (object, o) in objects.iter().enumerate() {
            let p = o.mesh.positions();
            for (index, t) in o.mesh.triangles().iter().enumerate() {
                let mut aabb = Aabb::empty();
                for &i in t {
                    aabb.grow_mut(&Point3::from(p[i as usize]));
                }
                tris.push(Tri {
                    object,
                    index,
                    aabb,
                    node: 0,
                });
            }
        }
        let bvh = Bvh::build(&mut tris);
        Ok(Self {
            scale: Self::diagonal(&objects),
            objects,
            materials,
            source: EnvironmentSource::Coefficients(environment.clone()),
            environment,
            window: crate::sh::Window::None,
            camera,
            tris,
            bvh,
        })
    }

    /// The objects, in the order [`Hit::object`] counts them.
    pub fn objects(&self) -> &[SceneObject] {
        &self.objects
    }

    /// The materials, in the order [`SceneObject::material`] counts them.
    pub fn materials(&self) -> &[SceneMaterial] {
        &self.materials
    }

    /// The environment's PSH coefficients as PPRT uses them: RGB, band-limited, `w`
    /// towards the source.
    pub fn environment(&self) -> &PshVector {
        &self.environment
    }

    /// The environment's source (by default its coefficients).
    pub fn source(&self) -> &EnvironmentSource {
        &self.source
    }

    /// The scene with the environment's source given. Error: a coefficient source with
    /// another number of channels or a lower band limit than the environment.
    pub fn with_source(mut self, source: EnvironmentSource) -> Result<Self> {
        if let EnvironmentSource::Coefficients(v) = &source {
            if v.channels() != 3 || v.lmax() < self.environment.lmax() {
                return Err(Error::invalid(
                    "environment source",
                    format!("{} channels, lmax {}", v.channels(), v.lmax()),
                    format!(
                        "3 channels and lmax >= the environment's {}",
                        self.environment.lmax()
                    ),
                ));
            }
        }
        self.source = source;
        Ok(self)
    }

    /// The scene with its environment's coefficients tapered by `window` over their band
    /// limit ([`PshVector::windowed`], `proofs/windowed-band-limits.md`); the source (the
    /// background, the reference's ground truth) is unchanged.
    /// Meant once: the factors of a second window multiply the first's, and
    /// [`Self::window`] names the last.
    pub fn windowed(mut self, window: crate::sh::Window) -> Self {
        self.environment = self.environment.windowed(window);
        self.window = window;
        self
    }

    /// The window the environment was tapered by ([`Self::windowed`]).
    pub fn window(&self) -> crate::sh::Window {
        self.window
    }

    /// The scene with its environment turned by `angle` (radians) about the world's
    /// vertical `+z`: the coefficients rotated (PSH (35)), the source
    /// [`EnvironmentSource::turned`] likewise; the window stays applied (it commutes with
    /// rotations, acting on whole bands). A transfer precomputed before is of the old
    /// environment ([`super::stages::retransfer`] redoes it). Error: a non-finite angle.
    pub fn with_environment_turned(mut self, angle: f64) -> Result<Self> {
        self.environment = self.environment.rotated(&vertical_turn(angle)?)?;
        self.source = self.source.turned(angle)?;
        Ok(self)
    }

    /// The scene under its analytic sky with the sun carried as `sun` (the environment
    /// projected anew at its band limit, then windowed as before). Error: a source
    /// that is not the analytic sky.
    pub fn with_sun(mut self, sun: Sun) -> Result<Self> {
        let EnvironmentSource::Sky(sky) = &self.source else {
            return Err(Error::invalid(
                "sun",
                sun.name(),
                "a scene under the analytic sky (its source is coefficients)",
            ));
        };
        let sky = sky.clone().with_sun(sun);
        self.environment = sky.project(self.environment.lmax())?.windowed(self.window);
        self.source = EnvironmentSource::Sky(sky);
        Ok(self)
    }

    /// The shading point of a hit: position and unit normal interpolated with its
    /// barycentric coordinates.
    pub fn shading_point(&self, h: &Hit) -> ([f64; 3], [f64; 3]) {
        let mesh = &self.objects[h.object].mesh;
        let t = mesh.triangles()[h.triangle];
        let w = [1.0 - h.u - h.v, h.u, h.v];
        let blend = |a: &[[f64; 3]]| -> Vector3<f64> {
            (0..3).map(|i| w[i] * Vector3::from(a[t[i] as usize])).sum()
        };
        let (p, n) = (blend(mesh.positions()), blend(mesh.normals()).normalize());
        (p.into(), n.into())
    }

    /// The diagonal of the bounding box of every vertex (the scale of ray offsets).
    pub fn bounding_scale(&self) -> f64 {
        self.scale
    }

    /// The point a camera orbits ([`Camera::orbited`]): on the camera's view axis, nearest
    /// to the centre of the objects' bounding box (the camera's position itself when that
    /// centre is behind it).
    pub fn orbit_pivot(&self) -> [f64; 3] {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in self.objects.iter().flat_map(|o| o.mesh.positions()) {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let centre = Vector3::from(std::array::from_fn(|k| 0.5 * (lo[k] + hi[k])));
        let eye = Vector3::from(self.camera.position);
        let forward = self.camera.frame.z();
        let along = (centre - eye).dot(&forward).max(0.0);
        (eye + along * forward).into()
    }

    /// The origin of a shadow ray leaving the surface point `p` of unit normal `n`: `p`
    /// lifted along `n` by `1e-7` (the shadow-ray offset) times [`Self::bounding_scale`].
    pub fn shadow_origin(&self, p: [f64; 3], n: [f64; 3]) -> [f64; 3] {
        let lift = SHADOW_RAY_OFFSET * self.scale;
        std::array::from_fn(|k| p[k] + lift * n[k])
    }

    /// [`Self::bounding_scale`] of `objects`.
    fn diagonal(objects: &[SceneObject]) -> f64 {
        let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
        for o in objects {
            for p in o.mesh.positions() {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
        }
        (0..3)
            .map(|k| (hi[k] - lo[k]).powi(2))
            .sum::<f64>()
            .sqrt()
            .max(1e-12)
    }

    /// The camera.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// Moves the camera (the transfer is view-independent: nothing is recomputed).
    pub fn set_camera(&mut self, camera: Camera) {
        self.camera = camera;
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.tris.len()
    }

    /// The nearest hit along the ray (either side of a triangle), beyond `t_min`.
    pub fn intersect(&self, origin: [f64; 3], direction: [f64; 3], t_min: f64) -> Option<Hit> {
        self.query(origin, direction, t_min, Wanted::Nearest)
    }

    /// Whether anything is hit along the ray beyond `t_min`.
    pub fn occluded(&self, origin: [f64; 3], direction: [f64; 3], t_min: f64) -> bool {
        self.query(origin, direction, t_min, Wanted::Any).is_some()
    }

    /// The hit `wanted` along the ray through the BVH ([`first_hit`]).
    fn query(
        &self,
        origin: [f64; 3],
        direction: [f64; 3],
        t_min: f64,
        wanted: Wanted,
    ) -> Option<Hit> {
        let ray = Ray::new(Point3::from(origin), Vector3::from(direction));
        first_hit(&self.bvh, &ray, t_min, wanted, |k| {
            self.hit_triangle(&ray, &self.tris[k], t_min)
                .map(|h| (h.distance, h))
        })
    }

    fn hit_triangle(&self, ray: &Ray<f64, 3>, tri: &Tri, t_min: f64) -> Option<Hit> {
        let mesh = &self.objects[tri.object].mesh;
        let t = mesh.triangles()[tri.index];
        let [a, b, c] = t.map(|i| Point3::from(mesh.positions()[i as usize]));
        // Both sides: the crate's test culls back faces.
        let front = ray.intersects_triangle(&a, &b, &c);
        let (d, u, v) = if front.distance.is_finite() {
            (front.distance, front.u, front.v)
        } else {
            let back = ray.intersects_triangle(&a, &c, &b);
            (back.distance, back.v, back.u)
        };
        (d.is_finite() && d > t_min).then_some(Hit {
            object: tri.object,
            triangle: tri.index,
            distance: d,
            u,
            v,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The BVH's nearest hit ([`super::super::traversal::first_hit`], which skips boxes)
    /// equals the nearest of every triangle tested one by one, bit for bit in distance,
    /// and `occluded` says whether any is hit: from the camera, from above the ground,
    /// from inside a sphere, from a point on the ground plane; directions spread over the
    /// sphere, along the axes, and in the ground's plane (the flat boxes' edge case).
    #[test]
    fn bvh_queries_equal_every_triangle_tested() {
        let scene = crate::pprt::builtin::builtin_scene(2, 4, 4).unwrap();
        let origins = [
            scene.camera().position,
            [0.4, -0.2, 1.9],
            [-0.8, 0.0, 0.7],
            [0.3, 0.2, 0.0],
            [1.0 / 3.0, -2.0, 0.16],
        ];
        let n = 500;
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        let mut directions: Vec<[f64; 3]> = (0..n)
            .map(|k| {
                let z = 1.0 - (2 * k + 1) as f64 / n as f64;
                let r = (1.0 - z * z).sqrt();
                let a = golden * k as f64;
                [r * a.cos(), r * a.sin(), z]
            })
            .collect();
        let h = std::f64::consts::FRAC_1_SQRT_2;
        directions.extend([
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
            [h, h, 0.0],
            [-h, 0.0, -h],
        ]);
        let (mut hits, mut misses) = (0, 0);
        for o in origins {
            for &d in &directions {
                for t_min in [0.0, 0.5] {
                    let ray = Ray::new(Point3::from(o), Vector3::from(d));
                    let every: Vec<Hit> = scene
                        .tris
                        .iter()
                        .filter_map(|t| scene.hit_triangle(&ray, t, t_min))
                        .collect();
                    let nearest = every.iter().map(|h| h.distance).reduce(f64::min);
                    let got = scene.intersect(o, d, t_min);
                    assert_eq!(got.map(|h| h.distance), nearest, "{o:?} {d:?} {t_min}");
                    assert_eq!(scene.occluded(o, d, t_min), !every.is_empty());
                    if got.is_some() {
                        hits += 1;
                    } else {
                        misses += 1;
                    }
                }
            }
        }
        // Both kinds of answer were tested.
        assert!(hits > 1000 && misses > 1000, "{hits} hits, {misses} misses");
    }

    /// [`Scene::TRIANGLE_BYTES`] covers what the ray queries keep per triangle, with room
    /// to spare for the build.
    #[test]
    fn triangle_bytes_cover_the_bvh() {
        let kept = std::mem::size_of::<Tri>()
            + 2 * std::mem::size_of::<bvh::bvh::BvhNode<f64, 3>>()
            + std::mem::size_of::<usize>();
        assert!(
            2 * kept <= Scene::TRIANGLE_BYTES,
            "{kept} bytes per triangle"
        );
    }
}
