//! A polarized reference renderer: the same scene, camera and frames as PPRT, with the
//! rendering equation `L_o(w_o) = int P(w_i, w_o) V(w_i) L(w_i) dw_i` (PSH (39) with
//! visibility) integrated per shading point by quasi-Monte Carlo, Stokes vectors and
//! Mueller transforms carried in explicit frames ([`crate::stokes`]).
//!
//! Directions come from the `R_3` low-discrepancy sequence (Roberts 2018: `frac(1/2 + n a)`,
//! `a = (1/g, 1/g^2, 1/g^3)`, `g` the real root of `x^4 = x + 1`), shifted per shading point
//! by a hash (Cranley-Patterson rotation). The first coordinate picks a lobe of a
//! one-sample mixture, the other two sample it; the estimator divides by the mixture's
//! density (the balance heuristic):
//!
//! - cosine-weighted about the shading normal, `p = cos(theta_i) / pi`;
//! - the GGX lobe of the material's microfacet term by its distribution of normals,
//!   `p = D(h) cos(theta_h) / (4 |w_o . h|)` (Walter et al. 2007 (38)), `w_i` the mirror of
//!   `w_o` about the sampled `h`;
//! - for [`Fidelity::BandLimited`], uniform on the sphere, `p = 1 / (4 pi)`: the
//!   band-limited pBRDF does not vanish below the horizon, and PPRT without shadows
//!   integrates over the whole sphere.
//!
//! What the integrand is made of is the [`Fidelity`]: the source environment (analytic sky
//! or the file's coefficients) and the pBRDF models with ray-cast visibility (the ground
//! truth), the same with the environment band-limited (so that band-limit and transfer
//! errors can be told apart), or exactly what unshadowed PPRT integrates (to check it).

use super::direct::DirectLights;
use super::lobe::{material_lobe, reflected, Lobe};
use super::render::{camera_travel_frame, seen_through, StokesImage};
use super::scene::{Hit, Scene};
use crate::error::{check_len, Error, Result};
use crate::geometry::frame::{Frame, PerspectiveFrameField};
use crate::polarized::{PshEvaluator, PshVector};
use crate::stokes::StokesVector;
use nalgebra::Vector3;
use rayon::prelude::*;
use std::f64::consts::PI;

/// What the reference integrates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fidelity {
    /// The scene's source environment ([`super::EnvironmentSource`]), the materials' pBRDF models
    /// and ray-cast visibility above the shading tangent plane: the ground truth.
    Exact,
    /// As [`Fidelity::Exact`] with the environment's PSH coefficients cut at `l`.
    BandLimitedEnvironment(usize),
    /// What PPRT without shadows integrates: the environment cut at `l`, the materials'
    /// coefficient matrices at `l` as Mueller fields, no visibility, the whole sphere.
    BandLimited(usize),
}

/// Settings of the reference ([`ReferenceSettings::new`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct ReferenceSettings {
    /// Directions per shading point.
    pub samples: usize,
    /// What is integrated: the ground truth or a band-limited part of PPRT's integrand.
    pub fidelity: Fidelity,
    /// Seeds the per-point shifts of the sequence.
    pub seed: u64,
}

impl ReferenceSettings {
    /// `samples` directions per shading point of `fidelity`, the sequence seeded by `seed`.
    pub const fn new(samples: usize, fidelity: Fidelity, seed: u64) -> Self {
        Self {
            samples,
            fidelity,
            seed,
        }
    }
}

/// Per-thread evaluators: the environment's coefficients and the materials' bases.
pub struct Workspace {
    environment: PshEvaluator,
    basis: PshEvaluator,
}

/// The reference integrator of a scene (materials and environment prepared once).
pub struct Reference<'a> {
    scene: &'a Scene,
    settings: ReferenceSettings,
    lobes: Vec<Lobe>,
    /// The band-limited environment, `None` for the source's.
    environment: Option<PshVector>,
    /// The source's directional lights, reflected exactly at every fidelity (as PPRT does).
    direct: Option<DirectLights<'a>>,
}

impl<'a> Reference<'a> {
    /// Errors: samples not in `1..=`[`MAX_REFERENCE_SAMPLES`]; a band limit above the
    /// environment's, or (for [`Fidelity::BandLimited`]) one the materials cannot be
    /// projected at.
    pub fn new(scene: &'a Scene, settings: ReferenceSettings) -> Result<Self> {
        check_samples(settings.samples)?;
        let lobes = scene
            .materials()
            .iter()
            .map(|m| match settings.fidelity {
                Fidelity::BandLimited(l) => Lobe::band_limited(m, l),
                _ => Lobe::exact(m),
            })
            .collect::<Result<Vec<_>>>()?;
        let environment = match settings.fidelity {
            Fidelity::Exact => None,
            Fidelity::BandLimitedEnvironment(l) | Fidelity::BandLimited(l) => {
                Some(scene.environment().truncated(l)?)
            }
        };
        Ok(Self {
            scene,
            settings,
            lobes,
            environment,
            direct: DirectLights::new(scene)?,
        })
    }

    /// Evaluators for one thread.
    pub fn workspace(&self) -> Result<Workspace> {
        let basis = self
            .lobes
            .iter()
            .map(Lobe::basis_lmax)
            .chain(self.direct.as_ref().map(DirectLights::basis_lmax))
            .max()
            .unwrap_or(0);
        Ok(Workspace {
            environment: PshEvaluator::new(match &self.environment {
                Some(v) => v.lmax(),
                None => self.scene.source().lmax(),
            })?,
            basis: PshEvaluator::new(basis)?,
        })
    }

    /// The light arriving from `w` (towards its source), per channel, in the theta-phi
    /// frame at `w`.
    fn incident(&self, ws: &mut Workspace, w: [f64; 3]) -> Result<Vec<StokesVector>> {
        match &self.environment {
            Some(v) => ws.environment.evaluate_all(v, w),
            None => self.scene.source().incident(&mut ws.environment, w),
        }
    }

    /// The Stokes vectors (RGB) leaving the point `p` of unit shading normal `n` with
    /// material `material` along `w_o`, components in `out` (a frame on the ray `w_o`);
    /// `stream` decorrelates the sequence's shift between points. Errors: a material out of
    /// range, a non-finite point, a normal that is not a unit vector, a workspace of
    /// another reference with lower band limits.
    pub fn outgoing(
        &self,
        ws: &mut Workspace,
        material: usize,
        p: [f64; 3],
        n: [f64; 3],
        out: &Frame,
        stream: u64,
    ) -> Result<[[f64; 4]; 3]> {
        let lobe = material_lobe(&self.lobes, material)?;
        if let Some(x) = p.iter().find(|x| !x.is_finite()) {
            return Err(Error::NonFinite {
                name: "shading point",
                value: *x,
            });
        }
        let rot = Frame::from_z(n)?.rotation();
        let wo = out.direction();
        let wo_l = rot.inverse() * Vector3::from(wo);
        let shift = shifts(self.settings.seed ^ stream.wrapping_mul(0x9E37_79B9_7F4A_7C15));
        let origin = self.scene.shadow_origin(p, n);
        let band_limited = matches!(self.settings.fidelity, Fidelity::BandLimited(_));
        let wo_a = [wo_l.x, wo_l.y, wo_l.z];
        let at = lobe.at(&mut ws.basis, wo_a)?;
        let mut acc = [[0.0; 4]; 3];
        for j in 0..self.settings.samples {
            let u = r3(j, shift);
            let Some((wi_l, pdf)) = sample(lobe, band_limited, &wo_l, u) else {
                continue;
            };
            let wi_v = rot * wi_l;
            let wi = [wi_v.x, wi_v.y, wi_v.z];
            if !band_limited && self.scene.occluded(origin, wi, 0.0) {
                continue;
            }
            let incident = self.incident(ws, wi)?;
            let transforms = at.transforms(&mut ws.basis, [wi_l.x, wi_l.y, wi_l.z], wo_a)?;
            for ((a, s), m) in acc.iter_mut().zip(&incident).zip(&transforms) {
                let x = reflected(m, &rot, s, out)?;
                a.iter_mut().zip(x).for_each(|(a, x)| *a += x / pdf);
            }
        }
        let n_inv = 1.0 / self.settings.samples as f64;
        let mut acc = acc.map(|s| s.map(|x| x * n_inv));
        if let Some(direct) = &self.direct {
            let d = direct.outgoing(&mut ws.basis, material, p, n, out)?;
            for (a, d) in acc.iter_mut().zip(d) {
                a.iter_mut().zip(d).for_each(|(a, d)| *a += d);
            }
        }
        Ok(acc)
    }

    /// The Stokes vectors (RGB) leaving the vertices `(object, vertex)` towards the camera,
    /// in its frames (as [`super::render::vertex_stokes`], for comparison with PPRT).
    pub fn vertex_stokes(&self, vertices: &[(usize, usize)]) -> Result<Vec<[[f64; 4]; 3]>> {
        let cam = self.scene.camera();
        let field = PerspectiveFrameField::new(cam.frame);
        let eye = Vector3::from(cam.position);
        let mut ws = self.workspace()?;
        vertices
            .iter()
            .map(|&(o, v)| {
                let object = self
                    .scene
                    .objects()
                    .get(o)
                    .ok_or_else(|| vertex_error(o, v))?;
                let mesh = &object.mesh;
                let (p, n) = mesh
                    .positions()
                    .get(v)
                    .zip(mesh.normals().get(v))
                    .ok_or_else(|| vertex_error(o, v))?;
                let w = (eye - Vector3::from(*p)).normalize();
                let out = camera_travel_frame(&field, [w.x, w.y, w.z])?;
                let stream = ((o as u64) << 32) | v as u64;
                self.outgoing(&mut ws, object.material, *p, *n, &out, stream)
            })
            .collect()
    }

    /// The image through the pixels' primary hits (shading point and normal interpolated
    /// with the hit's barycentric coordinates, the light towards the camera in its frames,
    /// as [`super::stages::render_frame`]); pixels without a hit see the integrand's environment.
    /// Error: `hits` not one per pixel of the scene's camera ([`super::render::primary_hits`]).
    pub fn render(&self, hits: &[Option<Hit>]) -> Result<StokesImage> {
        let cam = self.scene.camera();
        check_len("primary hits", cam.width * cam.height, hits.len())?;
        let pixels = self.per_pixel(|ws, k| {
            let d = cam.pixel_direction(k % cam.width, k / cam.width);
            self.through(ws, hits[k].as_ref(), d, k as u64)
        })?;
        Ok(StokesImage::from_pixels(cam, &pixels, hits))
    }

    /// The image with each pixel the mean over `grid x grid` positions spread evenly over
    /// its area (the centres of a `grid x grid` split), [`Self::render`]'s estimate at each:
    /// a box-filtered pixel, as Mitsuba 3's `box` filter (its `samples` directions per
    /// position, so `grid^2` times the work). The object mask is that of the pixels'
    /// centres. Error: `grid` 0 or above [`MAX_PIXEL_GRID`].
    pub fn render_antialiased(&self, grid: usize) -> Result<StokesImage> {
        if !(1..=MAX_PIXEL_GRID).contains(&grid) {
            return Err(Error::invalid(
                "pixel grid",
                grid.to_string(),
                format!("positions per pixel side in 1..={MAX_PIXEL_GRID}"),
            ));
        }
        let cam = self.scene.camera();
        let positions = grid * grid;
        let pixels = self.per_pixel(|ws, k| {
            let (i, j) = ((k % cam.width) as f64, (k / cam.width) as f64);
            let mut sum = [[0.0; 4]; 3];
            for q in 0..positions {
                let x = i + ((q % grid) as f64 + 0.5) / grid as f64;
                let y = j + ((q / grid) as f64 + 0.5) / grid as f64;
                let d = cam.direction_at(x, y);
                let hit = self.scene.intersect(cam.position, d, 0.0);
                let v = self.through(ws, hit.as_ref(), d, (k * positions + q) as u64)?;
                for (a, v) in sum.iter_mut().zip(v) {
                    a.iter_mut()
                        .zip(v)
                        .for_each(|(a, v)| *a += v / positions as f64);
                }
            }
            Ok(sum)
        })?;
        Ok(StokesImage::from_pixels(
            cam,
            &pixels,
            &super::render::primary_hits(self.scene),
        ))
    }

    /// `pixel(workspace, k)` for every pixel `k` of the camera, in parallel.
    fn per_pixel(
        &self,
        pixel: impl Fn(&mut Workspace, usize) -> Result<[[f64; 4]; 3]> + Sync,
    ) -> Result<Vec<[[f64; 4]; 3]>> {
        let cam = self.scene.camera();
        (0..cam.width * cam.height)
            .into_par_iter()
            .map_init(
                || self.workspace(),
                |ws, k| {
                    let ws = ws.as_mut().map_err(|e| {
                        Error::invalid(
                            "reference evaluators",
                            e.to_string(),
                            "band limits the SH tables accept",
                        )
                    })?;
                    pixel(ws, k)
                },
            )
            .collect()
    }

    /// The light reaching the camera along the ray of unit direction `d` whose first hit is
    /// `hit`, in the camera's frames; `stream` decorrelates the shading point's samples.
    fn through(
        &self,
        ws: &mut Workspace,
        hit: Option<&Hit>,
        d: [f64; 3],
        stream: u64,
    ) -> Result<[[f64; 4]; 3]> {
        let cam = self.scene.camera();
        let field = PerspectiveFrameField::new(cam.frame);
        match hit {
            Some(h) => {
                let (p, n) = self.scene.shading_point(h);
                let v = (Vector3::from(cam.position) - Vector3::from(p)).normalize();
                let out = camera_travel_frame(&field, [v.x, v.y, v.z])?;
                let material = self.scene.objects()[h.object].material;
                self.outgoing(ws, material, p, n, &out, stream)
            }
            None => {
                let s = self.incident(ws, d)?;
                let mut x = [[0.0; 4]; 3];
                for (x, s) in x.iter_mut().zip(&s) {
                    *x = seen_through(&field, d, s)?;
                }
                Ok(x)
            }
        }
    }
}

/// Largest [`Reference::render_antialiased`] grid (1024 positions per pixel).
pub const MAX_PIXEL_GRID: usize = 32;

/// The most directions per shading point the reference takes (2^20: a ground truth
/// converges far below it, and at the reference's pace of about 10^7 directions per
/// second and core, a 480 x 360 image at this count takes days).
pub const MAX_REFERENCE_SAMPLES: usize = 1 << 20;

/// Checks a count of directions per shading point: in `1..=`[`MAX_REFERENCE_SAMPLES`].
pub fn check_samples(samples: usize) -> Result<()> {
    if (1..=MAX_REFERENCE_SAMPLES).contains(&samples) {
        return Ok(());
    }
    Err(Error::invalid(
        "reference samples",
        samples.to_string(),
        format!("directions per shading point in 1..={MAX_REFERENCE_SAMPLES}"),
    ))
}

fn vertex_error(object: usize, vertex: usize) -> Error {
    Error::invalid(
        "vertex",
        format!("object {object}, vertex {vertex}"),
        "not in the scene",
    )
}

/// A direction in the shading frame and its density under the mixture, or `None` when
/// the GGX sample leaves the hemisphere (a zero contribution).
fn sample(
    lobe: &Lobe,
    band_limited: bool,
    wo: &Vector3<f64>,
    u: [f64; 3],
) -> Option<(Vector3<f64>, f64)> {
    if band_limited {
        let z = 1.0 - 2.0 * u[1];
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * PI * u[2];
        return Some((Vector3::new(r * phi.cos(), r * phi.sin(), z), 0.25 / PI));
    }
    let ggx = lobe.ggx().filter(|_| wo.z > 0.0);
    let pick_ggx = ggx.is_some_and(|(_, q)| u[0] < q);
    let wi = if let (true, Some((g, _))) = (pick_ggx, ggx) {
        let a = g.alpha();
        let tan2 = a * a * u[1] / (1.0 - u[1]).max(1e-300);
        let cos_h = 1.0 / (1.0 + tan2).sqrt();
        let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
        let phi = 2.0 * PI * u[2];
        let h = Vector3::new(sin_h * phi.cos(), sin_h * phi.sin(), cos_h);
        2.0 * wo.dot(&h) * h - wo
    } else {
        let r = u[1].sqrt();
        let phi = 2.0 * PI * u[2];
        Vector3::new(r * phi.cos(), r * phi.sin(), (1.0 - u[1]).max(0.0).sqrt())
    };
    if wi.z <= 0.0 {
        return None;
    }
    let cosine = wi.z / PI;
    let pdf = match ggx {
        Some((g, q)) => {
            let h = (wi + wo).normalize();
            let p_ggx = g.d(&h) * h.z / (4.0 * wo.dot(&h).abs());
            q * p_ggx + (1.0 - q) * cosine
        }
        None => cosine,
    };
    (pdf > 0.0).then_some((wi, pdf))
}

/// The `n`-th point of the `R_3` sequence shifted by `shift` (module docs).
fn r3(n: usize, shift: [f64; 3]) -> [f64; 3] {
    // g: the real root of x^4 = x + 1.
    const G: f64 = 1.220_744_084_605_759_5;
    const A: [f64; 3] = [1.0 / G, 1.0 / (G * G), 1.0 / (G * G * G)];
    std::array::from_fn(|k| (shift[k] + 0.5 + A[k] * n as f64).fract())
}

/// Three shifts in `[0, 1)` from a seed (the crate's generator, [`crate::random`]).
fn shifts(seed: u64) -> [f64; 3] {
    let mut rng = crate::random::Rng::new(seed);
    std::array::from_fn(|_| rng.unit())
}
