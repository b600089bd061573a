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

use super::render::{camera_travel_frame, seen_through, StokesImage};
use super::scene::{Hit, Scene, SceneMaterial};
use crate::error::{check_len, Error, Result};
use crate::geometry::frame::{Frame, FrameField, PerspectiveFrameField, ThetaPhiFrameField};
use crate::optics::{Channel, Conductor, Ggx, Lambertian, PolarizedPlastic};
use crate::polarized::{PshEvaluator, PshMatrix, PshVector};
use crate::sh::num_coeffs;
use crate::stokes::{MuellerField, MuellerMatrix, MuellerTransform, StokesVector};
use nalgebra::{Rotation3, Vector3};
use num_complex::Complex64;
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

/// Settings of the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReferenceSettings {
    /// Directions per shading point.
    pub samples: usize,
    pub fidelity: Fidelity,
    /// Seeds the per-point shifts of the sequence.
    pub seed: u64,
}

/// A material's pBRDF per channel, as the reference evaluates it.
enum Lobe {
    Diffuse([Lambertian; 3]),
    Plastic(PolarizedPlastic),
    Conductor([Conductor; 3]),
    Matrices(Box<[PshMatrix; 3]>),
}

/// A lobe at one shading point (`w_o` fixed), in the shading frame.
enum AtPoint<'a> {
    Diffuse(&'a [Lambertian; 3]),
    Plastic(&'a PolarizedPlastic),
    Conductor(&'a [Conductor; 3]),
    /// The contraction and the theta-phi frame at `w_o`.
    Matrices(Contracted, Frame),
}

impl AtPoint<'_> {
    /// `P(w_i, w_o)` of every channel (`basis` evaluates the matrices' input basis).
    fn transforms(
        &self,
        basis: &mut PshEvaluator,
        wi: [f64; 3],
        wo: [f64; 3],
    ) -> Result<[MuellerTransform; 3]> {
        Ok(match self {
            AtPoint::Diffuse(d) => [
                d[0].transform(wi, wo)?,
                d[1].transform(wi, wo)?,
                d[2].transform(wi, wo)?,
            ],
            AtPoint::Plastic(p) => {
                let m = p.transform(wi, wo)?;
                [m, m, m]
            }
            AtPoint::Conductor(m) => [
                m[0].transform(wi, wo)?,
                m[1].transform(wi, wo)?,
                m[2].transform(wi, wo)?,
            ],
            AtPoint::Matrices(k, fo) => {
                let fi = ThetaPhiFrameField::new().frame(wi)?;
                let (yr, y2) = basis.basis(wi)?;
                let m = |c| -> Result<MuellerTransform> {
                    let m = MuellerMatrix::from_rows(k.matrix(c, yr, y2))?;
                    Ok(MuellerTransform::new(m, fi, *fo))
                };
                [m(0)?, m(1)?, m(2)?]
            }
        })
    }
}

impl Lobe {
    /// The lobe at a shading point with outgoing direction `wo` (shading frame).
    fn at(&self, basis: &mut PshEvaluator, wo: [f64; 3]) -> Result<AtPoint<'_>> {
        Ok(match self {
            Lobe::Diffuse(d) => AtPoint::Diffuse(d),
            Lobe::Plastic(p) => AtPoint::Plastic(p),
            Lobe::Conductor(m) => AtPoint::Conductor(m),
            Lobe::Matrices(m) => {
                if basis.lmax() < m[0].lmax() {
                    return Err(Error::InvalidArgument {
                        name: "workspace",
                        value: format!("basis band limit {}", basis.lmax()),
                        reason: format!(
                            "the material's matrices need {} (a workspace of this reference)",
                            m[0].lmax()
                        ),
                    });
                }
                let (yr, y2) = basis.basis(wo)?;
                let k = Contracted::new(m, yr, y2);
                AtPoint::Matrices(k, ThetaPhiFrameField::new().frame(wo)?)
            }
        })
    }

    /// The GGX lobe to importance-sample and the probability of picking it.
    fn ggx(&self) -> Option<(Ggx, f64)> {
        match self {
            Lobe::Plastic(p) => Some((*p.specular().ggx(), 0.5)),
            Lobe::Conductor(m) => Some((*m[0].specular().ggx(), 0.9)),
            Lobe::Diffuse(_) | Lobe::Matrices(_) => None,
        }
    }
}

/// Coefficient matrices (RGB) contracted with the output basis at one `w_o`:
/// `A[j_i][p_i][r] = sum_{j_o, p_o} P_{j_o j_i p_o p_i} Y_{j_o p_o}(w_o)[r]`, so that the
/// Mueller matrix at any `w_i` is `M[r][k] = sum_{j_i, p_i} A[j_i][p_i][r] Y_{j_i p_i}(w_i)[k]`
/// (PSH (40) evaluated as [`crate::polarized::MatrixKernel`] does, in the theta-phi frames at `w_i` and
/// `w_o`), `O(n)` per direction instead of `O(n^2)`.
struct Contracted([Vec<[[f64; 4]; 4]>; 3]);

impl Contracted {
    fn new(mats: &[PshMatrix; 3], yr: &[f64], y2: &[Complex64]) -> Self {
        Contracted(std::array::from_fn(|c| {
            let p = &mats[c];
            let n = num_coeffs(p.lmax());
            let mut a = vec![[[0.0; 4]; 4]; n];
            for (jo, rows) in p.data().chunks_exact(16 * n).enumerate() {
                let (y, re, im) = (yr[jo], y2[jo].re, y2[jo].im);
                for (aj, blk) in a.iter_mut().zip(rows.chunks_exact(16)) {
                    for (pi, ap) in aj.iter_mut().enumerate() {
                        let c = |po: usize| blk[po * 4 + pi];
                        // Y_{j p}: p = 0, 3 carry the real SH in s0, s3; p = 1, 2 carry
                        // 2Y and i 2Y in s1 + i s2 (PSH (29)).
                        ap[0] += c(0) * y;
                        ap[1] += c(1) * re - c(2) * im;
                        ap[2] += c(1) * im + c(2) * re;
                        ap[3] += c(3) * y;
                    }
                }
            }
            a
        }))
    }

    /// `M[r][k]` of channel `c` at the input basis `yr`, `y2`.
    fn matrix(&self, c: usize, yr: &[f64], y2: &[Complex64]) -> [[f64; 4]; 4] {
        let mut m = [[0.0; 4]; 4];
        for ((a, &y), z) in self.0[c].iter().zip(yr).zip(y2) {
            for (r, row) in m.iter_mut().enumerate() {
                row[0] += a[0][r] * y;
                row[1] += a[1][r] * z.re - a[2][r] * z.im;
                row[2] += a[1][r] * z.im + a[2][r] * z.re;
                row[3] += a[3][r] * y;
            }
        }
        m
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
    offset: f64,
}

impl<'a> Reference<'a> {
    /// Errors: no samples; a band limit above the environment's, or (for
    /// [`Fidelity::BandLimited`]) one the materials cannot be projected at.
    pub fn new(scene: &'a Scene, settings: ReferenceSettings) -> Result<Self> {
        if settings.samples == 0 {
            return Err(Error::InvalidArgument {
                name: "reference samples",
                value: "0".into(),
                reason: "at least one direction per shading point".into(),
            });
        }
        let lobes = scene
            .materials()
            .iter()
            .map(|m| {
                Ok(match (m, settings.fidelity) {
                    (_, Fidelity::BandLimited(l)) => Lobe::Matrices(Box::new(m.matrices(l)?)),
                    (SceneMaterial::Diffuse(d), _) => Lobe::Diffuse(*d),
                    (SceneMaterial::Plastic(p), _) => Lobe::Plastic(*p),
                    (SceneMaterial::Conductor { material, alpha }, _) => {
                        let c = |ch| Conductor::from_material(*alpha, *material, ch);
                        Lobe::Conductor([c(Channel::Red)?, c(Channel::Green)?, c(Channel::Blue)?])
                    }
                    (SceneMaterial::Matrices(mats), _) => Lobe::Matrices(mats.clone()),
                })
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
            offset: 1e-4 * scene.bounding_scale(),
        })
    }

    /// Evaluators for one thread.
    pub fn workspace(&self) -> Result<Workspace> {
        let basis = self
            .lobes
            .iter()
            .map(|l| match l {
                Lobe::Matrices(m) => m[0].lmax(),
                _ => 0,
            })
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
        let lobe = self
            .lobes
            .get(material)
            .ok_or_else(|| Error::InvalidArgument {
                name: "material",
                value: material.to_string(),
                reason: format!("{} materials", self.lobes.len()),
            })?;
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
        let origin: [f64; 3] = std::array::from_fn(|k| p[k] + self.offset * n[k]);
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
                let m = in_world(m, &rot)?;
                let x = m.apply(s)?.components_in(out)?.to_array();
                a.iter_mut().zip(x).for_each(|(a, x)| *a += x / pdf);
            }
        }
        let n_inv = 1.0 / self.settings.samples as f64;
        Ok(acc.map(|s| s.map(|x| x * n_inv)))
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
    /// as [`super::render_frame`]); pixels without a hit see the integrand's environment.
    /// Error: `hits` not one per pixel of the scene's camera ([`super::render::primary_hits`]).
    pub fn render(&self, hits: &[Option<Hit>]) -> Result<StokesImage> {
        let cam = self.scene.camera();
        check_len("primary hits", cam.width * cam.height, hits.len())?;
        let field = PerspectiveFrameField::new(cam.frame);
        let eye = Vector3::from(cam.position);
        let pixels: Vec<[[f64; 4]; 3]> = hits
            .par_iter()
            .enumerate()
            .map_init(
                || self.workspace(),
                |ws, (k, hit)| {
                    let ws = ws.as_mut().map_err(|e| Error::InvalidArgument {
                        name: "reference evaluators",
                        value: e.to_string(),
                        reason: "band limits the SH tables accept".into(),
                    })?;
                    match hit {
                        Some(h) => {
                            let mesh = &self.scene.objects()[h.object].mesh;
                            let t = mesh.triangles()[h.triangle];
                            let w = [1.0 - h.u - h.v, h.u, h.v];
                            let blend = |a: &[[f64; 3]]| -> Vector3<f64> {
                                (0..3).map(|i| w[i] * Vector3::from(a[t[i] as usize])).sum()
                            };
                            let p = blend(mesh.positions());
                            let n = blend(mesh.normals()).normalize();
                            let v = (eye - p).normalize();
                            let out = camera_travel_frame(&field, [v.x, v.y, v.z])?;
                            let material = self.scene.objects()[h.object].material;
                            self.outgoing(ws, material, p.into(), n.into(), &out, k as u64)
                        }
                        None => {
                            let d = cam.pixel_direction(k % cam.width, k / cam.width);
                            let s = self.incident(ws, d)?;
                            let mut x = [[0.0; 4]; 3];
                            for (x, s) in x.iter_mut().zip(&s) {
                                *x = seen_through(&field, d, s)?;
                            }
                            Ok(x)
                        }
                    }
                },
            )
            .collect::<Result<_>>()?;
        Ok(StokesImage::from_pixels(cam, &pixels, hits))
    }
}

fn vertex_error(object: usize, vertex: usize) -> Error {
    Error::InvalidArgument {
        name: "vertex",
        value: format!("object {object}, vertex {vertex}"),
        reason: "not in the scene".into(),
    }
}

/// A transform given in the shading frame (normal `+z`) carried to world by `rot`.
fn in_world(m: &MuellerTransform, rot: &Rotation3<f64>) -> Result<MuellerTransform> {
    Ok(MuellerTransform::new(
        m.matrix(),
        m.frame_in().rotated(rot)?,
        m.frame_out().rotated(rot)?,
    ))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polarized::MatrixKernel;
    use crate::testing::{random_directions, random_psh_matrix};

    /// The contraction equals the direct double sum of [`MatrixKernel`] (PSH (40)), poles
    /// included.
    #[test]
    fn contraction_matches_the_matrix_kernel() {
        let lmax = 5;
        let mats: [PshMatrix; 3] =
            std::array::from_fn(|c| random_psh_matrix(lmax, c as u64).unwrap());
        let mut basis = PshEvaluator::new(lmax).unwrap();
        let mut dirs = random_directions(6, 3);
        dirs.push([0.0, 0.0, 1.0]);
        let lobe = Lobe::Matrices(Box::new(mats.clone()));
        for &wo in &dirs {
            let at = lobe.at(&mut basis, wo).unwrap();
            let AtPoint::Matrices(..) = at else {
                panic!("a matrix lobe")
            };
            for &wi in &dirs {
                let got = at.transforms(&mut basis, wi, wo).unwrap();
                for c in 0..3 {
                    let want = MatrixKernel(&mats[c]).transform(wi, wo).unwrap();
                    let d = (got[c].matrix().matrix() - want.matrix().matrix())
                        .abs()
                        .max();
                    assert!(d < 1e-12, "{wi:?} {wo:?} {c}: {d}");
                    assert!(got[c].frame_in().approx_eq(want.frame_in(), 1e-15));
                    assert!(got[c].frame_out().approx_eq(want.frame_out(), 1e-15));
                }
            }
        }
    }
}
