//! The planner of PPRT: inspects a scene, drops the work it does not need within a stated
//! tolerance, says why, and prepares what the transfer ([`super::transfer`]) uses.
//!
//! - **Stokes components.** With an unpolarized environment and materials that do not
//!   polarize unpolarized light (PSH (41): the blocks `p_o = 1, 2, 3` of column `p_i = 0`
//!   vanish), only `s0` is ever nonzero: scalar SH ([`Codomain::Intensity`]). Without
//!   circular light and materials that create it (row `p_o = 3` vanishes on
//!   `p_i = 0, 1, 2`), `s3` is dropped ([`Codomain::NoCircular`]).
//! - **Visibility.** A scene of one convex object occludes nothing above a vertex's tangent
//!   plane: the visibility is the hemisphere `H(z > 0)` in the shading frame, whose shadowing
//!   operator (PSH (54)-(56) with the zonal coefficients of `proofs/tangent-plane-visibility.md`)
//!   is one fixed sparse matrix: no rays, no per-vertex triple products.
//! - **High orders.** The band `l` of the convolved environment `conv_G f` ([`super::reflected`])
//!   holds energy `E_l` (Parseval); the high orders stop at the smallest `l_high` whose
//!   dropped tail holds at most `tolerance` of its L2 norm,
//!   `sqrt(sum_{l > l_high} E_l / sum_l E_l) <= tolerance`.
//! - **Storage.** A material whose matrices are isotropic (PSH (52)-(53), defect at most
//!   `tolerance`) keeps only the entries with `|m_o| = |m_i|` ([`Sparsity::Isotropic`]).
//!
//! [`Plan::full`] keeps everything (`psh render --no-plan`); both prepare the restricted
//! sparse material operators and the high-order fields once.

use super::reflected::reflected_pbrdf;
use super::scene::Scene;
use super::transfer::TransferSettings;
use crate::error::{Error, Result};
use crate::polarized::{
    isotropy_defect, project_to_convolution, Codomain, PshMatrix, PshVector, SparsePshMatrix,
    Sparsity, TripleTable,
};
use crate::sh::grid::GaussLegendre;
use crate::sh::harmonics::ShEvaluator;
use crate::sh::{lm_index, num_coeffs};
use rayon::prelude::*;
use serde_json::json;
use std::f64::consts::PI;

/// How visibility enters the transfer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Visibility {
    /// Ray-cast visibility and its triple product per vertex (PSH (54)-(56)).
    Rays,
    /// Only the tangent plane occludes: one fixed shadowing matrix in the shading frame.
    TangentPlane,
    /// No shadows at all (the settings turn them off).
    Off,
}

/// What the plan keeps of one material.
#[derive(Clone, Debug)]
pub struct MaterialPlan {
    /// The coefficient matrix of each channel (PSH (41), `l <= l_low`) restricted to the
    /// plan's codomain, sparse.
    pub operators: Vec<SparsePshMatrix>,
    /// The storage chosen.
    pub sparsity: Sparsity,
    /// How far the matrices are from isotropic ([`isotropy_defect`], the largest channel).
    pub isotropy_defect: f64,
    /// The band limit of the high orders (`l_low`: none).
    pub l_high: usize,
    /// The high orders (bands `l_low < l <= l_high` of the convolved environment, in the
    /// plan's codomain) and the convolution projection's largest relative residual.
    pub high: Option<(PshVector, f64)>,
    /// The dropped tail of the high orders relative to the convolved environment's L2 norm.
    pub dropped_tail: f64,
}

/// The decisions and the prepared operators of one precomputation.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The settings asked for (`l_high` is the upper limit of the high orders).
    pub settings: TransferSettings,
    /// The tolerance of the decisions (`None`: nothing dropped).
    pub tolerance: Option<f64>,
    /// The Stokes components carried.
    pub codomain: Codomain,
    /// How visibility is computed.
    pub visibility: Visibility,
    /// Per material.
    pub materials: Vec<MaterialPlan>,
    /// The shadowing operator of the tangent plane in the shading frame
    /// ([`Visibility::TangentPlane`]).
    pub horizon: Option<SparsePshMatrix>,
    /// One line per decision, saying why.
    pub reasons: Vec<String>,
}

impl Plan {
    /// Everything computed: full Stokes vectors, ray-cast visibility (when the settings ask
    /// for shadows), every nonzero matrix entry stored and the high orders up to `settings.l_high`. Errors: as
    /// [`TransferSettings::check`], and materials or an environment that cannot be projected
    /// at the band limits.
    pub fn full(scene: &Scene, settings: TransferSettings) -> Result<Plan> {
        Self::build(scene, settings, None)
    }

    /// The plan for `scene` within `tolerance` (module docs). Errors: as [`Self::full`], and
    /// a tolerance outside `(0, 1)`.
    pub fn new(scene: &Scene, settings: TransferSettings, tolerance: f64) -> Result<Plan> {
        if !(tolerance > 0.0 && tolerance < 1.0) {
            return Err(Error::InvalidArgument {
                name: "plan tolerance",
                value: tolerance.to_string(),
                reason: "in (0, 1)".into(),
            });
        }
        Self::build(scene, settings, Some(tolerance))
    }

    fn build(scene: &Scene, settings: TransferSettings, tolerance: Option<f64>) -> Result<Plan> {
        settings.check()?;
        let l = settings.l_low;
        let lh = settings.l_high.max(l);
        let mut reasons = Vec::new();
        let matrices_high = scene
            .materials()
            .par_iter()
            .map(|m| m.matrices(lh))
            .collect::<Result<Vec<_>>>()?;
        let matrices = matrices_high
            .iter()
            .map(|ms| {
                ms.iter()
                    .map(|m| m.truncated(l))
                    .collect::<Result<Vec<_>>>()
            })
            .collect::<Result<Vec<_>>>()?;
        let codomain = match tolerance {
            Some(tol) => {
                // The matrices to l_high: the high orders' kernels come from them too.
                let (c, why) = stokes_components(scene, &matrices_high, tol)?;
                reasons.push(why);
                c
            }
            None => {
                reasons.push("Stokes: s0..s3 (no plan)".into());
                Codomain::Full
            }
        };
        let visibility = if !settings.shadows {
            reasons.push("visibility: off (shadows off in the settings)".into());
            Visibility::Off
        } else if tolerance.is_some() && single_convex_object(scene) {
            reasons.push(
                "visibility: tangent plane only (one convex object occludes nothing above it): \
                 no rays, one fixed shadowing matrix instead of a triple product per vertex"
                    .into(),
            );
            Visibility::TangentPlane
        } else {
            reasons.push(format!(
                "visibility: {} rays per vertex and a triple product (PSH (54)-(56)){}",
                settings.rays,
                if tolerance.is_some() {
                    " (occluders: more than one object, or a non-convex one)"
                } else {
                    ""
                }
            ));
            Visibility::Rays
        };
        let horizon = match visibility {
            Visibility::TangentPlane => {
                let t = TripleTable::new(2 * l, l)?.transfer(&tangent_plane_visibility(2 * l)?)?;
                Some(SparsePshMatrix::new(
                    &t,
                    codomain,
                    codomain,
                    Sparsity::Isotropic,
                ))
            }
            _ => None,
        };
        let env_high = scene
            .environment()
            .truncated(lh)?
            .with_codomain(Codomain::Full);
        let materials = matrices_high
            .par_iter()
            .zip(&matrices)
            .map(|(high, low)| {
                let defect = low.iter().map(isotropy_defect).fold(0.0, f64::max);
                let sparsity = match tolerance {
                    Some(tol) if defect <= tol => Sparsity::Isotropic,
                    _ => Sparsity::General,
                };
                let operators = low
                    .iter()
                    .map(|m| SparsePshMatrix::new(m, codomain, codomain, sparsity))
                    .collect();
                let (l_high, high, dropped_tail) =
                    high_orders(high, &env_high, l, tolerance, codomain)?;
                Ok(MaterialPlan {
                    operators,
                    sparsity,
                    isotropy_defect: defect,
                    l_high,
                    high,
                    dropped_tail,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let dense = 3 * (num_coeffs(l) * codomain.components().len()).pow(2);
        for (k, m) in materials.iter().enumerate() {
            let stored: usize = m.operators.iter().map(SparsePshMatrix::stored).sum();
            reasons.push(format!(
                "material {k}: {} storage ({stored} of {dense} entries, isotropy defect \
                 {:.1e}); high orders {} (dropped tail {:.1e})",
                match m.sparsity {
                    Sparsity::Isotropic => "isotropic sparse",
                    Sparsity::General => "general sparse",
                },
                m.isotropy_defect,
                if m.l_high > l {
                    format!("to l = {}", m.l_high)
                } else {
                    "none".into()
                },
                m.dropped_tail,
            ));
        }
        Ok(Plan {
            settings,
            tolerance,
            codomain,
            visibility,
            materials,
            horizon,
            reasons,
        })
    }

    /// The high-order fields per material (for [`super::render::vertex_stokes`]).
    pub fn high_fields(&self) -> Vec<Option<PshVector>> {
        self.materials
            .iter()
            .map(|m| m.high.as_ref().map(|h| h.0.clone()))
            .collect()
    }

    /// The plan as JSON (for reports).
    pub fn to_json(&self) -> serde_json::Value {
        json!({
            "tolerance": self.tolerance,
            "stokes": self.codomain.components(),
            "visibility": format!("{:?}", self.visibility),
            "materials": self.materials.iter().map(|m| json!({
                "storage": format!("{:?}", m.sparsity),
                "stored_entries": m.operators.iter().map(SparsePshMatrix::stored).sum::<usize>(),
                "isotropy_defect": m.isotropy_defect,
                "l_high": m.l_high,
                "dropped_tail": m.dropped_tail,
            })).collect::<Vec<_>>(),
            "reasons": self.reasons,
        })
    }
}

/// The largest `|entry|` of `m` over the blocks `(p_o, p_i)` in `blocks`.
fn block_max(m: &PshMatrix, blocks: &[(usize, usize)]) -> f64 {
    let n = num_coeffs(m.lmax());
    let mut x = 0.0f64;
    for jo in 0..n {
        for ji in 0..n {
            for &(po, pi) in blocks {
                x = x.max(m.get(jo, ji, po, pi).abs());
            }
        }
    }
    x
}

/// The Stokes components the scene needs within `tol` (module docs), and why.
fn stokes_components(
    scene: &Scene,
    matrices: &[[PshMatrix; 3]],
    tol: f64,
) -> Result<(Codomain, String)> {
    let env = scene.environment();
    let largest = |p: &[usize]| -> Result<f64> {
        let mut x = 0.0f64;
        for c in 0..env.channels() {
            for l in 0..=env.lmax() {
                for m in -(l as i64)..=l as i64 {
                    for &q in p {
                        x = x.max(env.get(c, l, m, q)?.abs());
                    }
                }
            }
        }
        Ok(x)
    };
    let s0 = largest(&[0])?.max(f64::MIN_POSITIVE);
    let (linear, circular) = (largest(&[1, 2])? / s0, largest(&[3])? / s0);
    // Relative to each material's largest entry.
    let worst = |blocks: &[(usize, usize)]| -> f64 {
        matrices
            .iter()
            .flatten()
            .map(|m| {
                let all = m
                    .data()
                    .iter()
                    .fold(f64::MIN_POSITIVE, |a, x| a.max(x.abs()));
                block_max(m, blocks) / all
            })
            .fold(0.0, f64::max)
    };
    let polarizes = worst(&[(1, 0), (2, 0), (3, 0)]);
    let circularizes = worst(&[(3, 0), (3, 1), (3, 2)]);
    Ok(if linear <= tol && circular <= tol && polarizes <= tol {
        (
            Codomain::Intensity,
            format!(
                "Stokes: s0 only, scalar SH (environment polarization {:.1e} <= {tol:.0e}, no \
                 material polarizes unpolarized light: {polarizes:.1e})",
                linear.max(circular)
            ),
        )
    } else if circular <= tol && circularizes <= tol {
        (
            Codomain::NoCircular,
            format!(
                "Stokes: s0, s1, s2 (environment circular {circular:.1e} <= {tol:.0e}, no \
                 material creates circular light: {circularizes:.1e}); kept s1, s2: environment \
                 linear {linear:.1e}, materials polarize {polarizes:.1e}"
            ),
        )
    } else {
        (
            Codomain::Full,
            format!(
                "Stokes: s0..s3 (environment linear {linear:.1e}, circular {circular:.1e}; \
                 materials polarize {polarizes:.1e}, create circular {circularizes:.1e}; \
                 tolerance {tol:.0e})"
            ),
        )
    })
}

/// `(l_high, high orders and residual, dropped tail)` of one material.
type HighOrderCut = (usize, Option<(PshVector, f64)>, f64);

/// The high orders of one material (RGB matrices at the upper band limit `env.lmax()`):
/// the environment convolved with the kernel of the reflected pBRDF ([`super::reflected`]),
/// cut at the tolerance's `l_high` (module docs; the upper limit without a tolerance), the
/// bands `l <= l_low` zeroed, in `codomain`. Returns `(l_high, field and residual, dropped
/// tail)`; no field when `l_high = l_low`.
fn high_orders(
    matrices: &[PshMatrix],
    env: &PshVector,
    l_low: usize,
    tolerance: Option<f64>,
    codomain: Codomain,
) -> Result<HighOrderCut> {
    let lh = env.lmax();
    if lh <= l_low {
        return Ok((l_low, None, 0.0));
    }
    let mut parts = Vec::new();
    let mut residual = 0.0f64;
    for (c, p) in matrices.iter().enumerate() {
        let (k, r) = project_to_convolution(&reflected_pbrdf(p)?)?;
        residual = residual.max(r);
        parts.push(k.convolve(&env.channel(c)?)?);
    }
    let g = PshVector::from_channels(&parts)?;
    let e = g.band_energies();
    let total: f64 = e.iter().sum::<f64>().max(f64::MIN_POSITIVE);
    // abs: an empty sum is -0.
    let tail = |cut: usize| (e[cut + 1..].iter().sum::<f64>().abs() / total).sqrt();
    let cut = match tolerance {
        Some(tol) => (l_low..=lh).find(|&c| tail(c) <= tol).unwrap_or(lh),
        None => lh,
    };
    let field = (cut > l_low).then(|| -> Result<_> {
        Ok((
            g.truncated(cut)?
                .without_bands_through(l_low)
                .with_codomain(codomain),
            residual,
        ))
    });
    Ok((cut, field.transpose()?, tail(cut)))
}

/// The real SH coefficients `l <= lv` of the tangent-plane visibility `H(z > 0)`: zonal,
/// `h_l0 = 2 pi int_0^1 Y_l0(z) dz` (`proofs/tangent-plane-visibility.md`), by the
/// `(lv/2 + 1)`-point Gauss-Legendre rule on `[0, 1]` (exact: the integrand is a
/// polynomial of degree `l` in `z`).
pub fn tangent_plane_visibility(lv: usize) -> Result<PshVector> {
    let gl = GaussLegendre::new(lv / 2 + 1)?;
    let eval = ShEvaluator::new(lv)?;
    let mut y = vec![0.0; num_coeffs(lv)];
    let mut h = vec![0.0; num_coeffs(lv)];
    for (&x, &w) in gl.cos_theta.iter().zip(&gl.weights) {
        // z = (1 + x) / 2 on [0, 1], dz = dx / 2.
        let z: f64 = 0.5 * (1.0 + x);
        eval.real(z.acos(), 0.0, &mut y)?;
        for l in 0..=lv {
            h[lm_index(l, 0)] += 2.0 * PI * 0.5 * w * y[lm_index(l, 0)];
        }
    }
    PshVector::scalar(lv, h)
}

/// Whether the scene is one object whose mesh is convex: every vertex on or behind the
/// plane of every triangle (the triangle's normal turned to agree with its vertex normals;
/// `1e-9` of the scene's size allowed).
fn single_convex_object(scene: &Scene) -> bool {
    let [object] = scene.objects() else {
        return false;
    };
    let mesh = &object.mesh;
    let (p, n) = (mesh.positions(), mesh.normals());
    let eps = 1e-9 * scene.bounding_scale();
    mesh.triangles().par_iter().all(|t| {
        let [a, b, c] = t.map(|i| nalgebra::Vector3::from(p[i as usize]));
        let mut f = (b - a).cross(&(c - a));
        let along: f64 = t
            .iter()
            .map(|&i| f.dot(&nalgebra::Vector3::from(n[i as usize])))
            .sum();
        if along < 0.0 {
            f = -f;
        }
        let f = f.normalize();
        f.iter().all(|x| x.is_finite())
            && p.iter()
                .all(|q| f.dot(&(nalgebra::Vector3::from(*q) - a)) <= eps)
    })
}
