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
//! [`Planning::Full`] keeps everything (`psh render --no-plan`); both prepare the restricted
//! sparse material operators and the high-order fields once.

use super::reflected::reflected_pbrdf;
use super::scene::Scene;
use super::settings::{Planning, TransferSettings, Visibility};
use crate::error::{Error, Result};
use crate::polarized::{
    isotropy_defect, project_to_convolution, Codomain, PshMatrix, PshVector, SparsePshMatrix,
    Sparsity, TripleTable,
};
use crate::sh::evaluation::harmonics::ShEvaluator;
use crate::sh::transform::grid::GaussLegendre;
use crate::sh::{lm_index, num_coeffs};
use rayon::prelude::*;
use std::f64::consts::PI;

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
    /// How much the decisions could drop.
    pub planning: Planning,
    /// The Stokes components carried.
    pub codomain: Codomain,
    /// How visibility is computed.
    pub visibility: Visibility,
    /// Per material.
    pub materials: Vec<MaterialPlan>,
    /// The shadowing operator of the tangent plane in the shading frame
    /// ([`Visibility::TangentPlane`]).
    pub horizon: Option<SparsePshMatrix>,
    /// Each decision with the figures it rests on (`Display`: one line saying why).
    pub reasons: Vec<Reason>,
}

/// The figures behind the choice of Stokes components: the environment's largest linear
/// and circular coefficients relative to its largest `s0` one, and how strongly the
/// materials polarize unpolarized light and create circular light (relative to each
/// material's largest entry).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StokesEvidence {
    /// The environment's largest `|s1|`, `|s2|` coefficient over its largest `|s0|` one.
    pub linear: f64,
    /// The environment's largest `|s3|` coefficient over its largest `|s0|` one.
    pub circular: f64,
    /// The largest entry of the blocks `(p_o, p_i) = (1..=3, 0)` of PSH (41) (unpolarized
    /// light polarized), over every material and channel.
    pub polarizes: f64,
    /// The largest entry of the blocks `(p_o, p_i) = (3, 0..=2)` (circular light created),
    /// over every material and channel.
    pub circularizes: f64,
    /// The tolerance the figures are held against.
    pub tolerance: f64,
}

/// One decision of a plan and what it rests on.
#[derive(Clone, Debug, PartialEq)]
pub enum Reason {
    /// The Stokes components carried (`evidence` is `None` without a tolerance).
    Stokes {
        /// The Stokes components carried.
        codomain: Codomain,
        /// The figures behind the choice.
        evidence: Option<StokesEvidence>,
    },
    /// The visibility computed against the one asked for.
    Visibility {
        /// The visibility the settings asked for.
        asked: Visibility,
        /// The visibility computed.
        chosen: Visibility,
        /// Visibility rays per vertex asked for.
        rays: usize,
        /// Whether a tolerance let the planner choose.
        planned: bool,
    },
    /// The storage and the high orders of material `index`: `stored` of `dense` matrix
    /// entries; `l_high` `None` without high orders.
    Material {
        /// The material's index in the scene.
        index: usize,
        /// The storage chosen.
        sparsity: Sparsity,
        /// Matrix entries stored, over the three channels.
        stored: usize,
        /// Entries of the three dense matrices in the plan's codomain:
        /// `3 (c (l_low + 1)^2)^2` for `c` Stokes components.
        dense: usize,
        /// How far the matrices are from isotropic ([`isotropy_defect`], the largest
        /// channel).
        isotropy_defect: f64,
        /// The band limit of the high orders.
        l_high: Option<usize>,
        /// The dropped tail of the high orders relative to the convolved environment's
        /// L2 norm.
        dropped_tail: f64,
    },
}

impl std::fmt::Display for Reason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Reason::Stokes { evidence: None, .. } => write!(f, "Stokes: s0..s3 (no plan)"),
            Reason::Stokes {
                codomain,
                evidence: Some(e),
            } => {
                let (linear, circular, polarizes, circularizes, tol) = (
                    e.linear,
                    e.circular,
                    e.polarizes,
                    e.circularizes,
                    e.tolerance,
                );
                match codomain {
                    Codomain::Intensity => write!(
                        f,
                        "Stokes: s0 only, scalar SH (environment polarization {:.1e} <= \
                         {tol:.0e}, no material polarizes unpolarized light: {polarizes:.1e})",
                        linear.max(circular)
                    ),
                    Codomain::NoCircular => write!(
                        f,
                        "Stokes: s0, s1, s2 (environment circular {circular:.1e} <= {tol:.0e}, \
                         no material creates circular light: {circularizes:.1e}); kept s1, s2: \
                         environment linear {linear:.1e}, materials polarize {polarizes:.1e}"
                    ),
                    _ => write!(
                        f,
                        "Stokes: s0..s3 (environment linear {linear:.1e}, circular \
                         {circular:.1e}; materials polarize {polarizes:.1e}, create circular \
                         {circularizes:.1e}; tolerance {tol:.0e})"
                    ),
                }
            }
            Reason::Visibility {
                asked,
                chosen,
                rays,
                planned,
            } => match (asked, chosen) {
                (_, Visibility::Off) => write!(f, "visibility: off (shadows off in the settings)"),
                (Visibility::Rays, Visibility::TangentPlane) => write!(
                    f,
                    "visibility: tangent plane only (one convex object occludes nothing above \
                     it): no rays, one fixed shadowing matrix instead of a triple product per \
                     vertex"
                ),
                (_, Visibility::TangentPlane) => write!(
                    f,
                    "visibility: tangent plane only (asked for in the settings): no rays, one \
                     fixed shadowing matrix"
                ),
                (_, Visibility::Rays) => write!(
                    f,
                    "visibility: {rays} rays per vertex and a triple product (PSH (54)-(56)){}",
                    if planned {
                        " (occluders: more than one object, or a non-convex one)"
                    } else {
                        ""
                    }
                ),
            },
            Reason::Material {
                index,
                sparsity,
                stored,
                dense,
                isotropy_defect,
                l_high,
                dropped_tail,
            } => write!(
                f,
                "material {index}: {} storage ({stored} of {dense} entries, isotropy defect \
                 {isotropy_defect:.1e}); high orders {} (dropped tail {dropped_tail:.1e})",
                match sparsity {
                    Sparsity::Isotropic => "isotropic sparse",
                    Sparsity::General => "general sparse",
                },
                l_high.map_or("none".into(), |l| format!("to l = {l}")),
            ),
        }
    }
}

impl Plan {
    /// The plan for `scene` (module docs): [`Planning::Full`] keeps everything (the
    /// visibility asked for, full Stokes vectors, every nonzero matrix entry, the high
    /// orders up to `settings.l_high`). Errors: as [`TransferSettings::check`], a tolerance
    /// outside `(0, 1)`, and materials or an environment that cannot be projected at the
    /// band limits.
    pub fn new(scene: &Scene, settings: TransferSettings, planning: Planning) -> Result<Plan> {
        Self::with_progress(scene, settings, planning, &crate::progress::Silent)
    }

    /// [`Self::new`], reporting the materials projected to `progress` (stage
    /// "materials": the projection of the pBRDFs is most of a plan's time).
    pub fn with_progress(
        scene: &Scene,
        settings: TransferSettings,
        planning: Planning,
        progress: &dyn crate::progress::Progress,
    ) -> Result<Plan> {
        if let Planning::Tolerance(tolerance) = planning {
            if !(tolerance > 0.0 && tolerance < 1.0) {
                return Err(Error::invalid(
                    "plan tolerance",
                    tolerance.to_string(),
                    "in (0, 1)",
                ));
            }
        }
        Self::build(scene, settings, planning, progress)
    }

    fn build(
        scene: &Scene,
        settings: TransferSettings,
        planning: Planning,
        progress: &dyn crate::progress::Progress,
    ) -> Result<Plan> {
        settings.check()?;
        let tolerance = planning.tolerance();
        let l = settings.l_low;
        let lh = settings.environment_lmax();
        let mut reasons = Vec::new();
        progress.start("materials", scene.materials().len() as u64);
        let matrices_high = scene
            .materials()
            .par_iter()
            .map(|m| {
                progress.check_cancelled("the plan's projection of the materials")?;
                let projected = m.matrices(lh);
                progress.advance(1);
                projected
            })
            .collect::<Result<Vec<_>>>()?;
        progress.finish();
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
                let (c, evidence) = stokes_components(scene, &matrices_high, tol)?;
                reasons.push(Reason::Stokes {
                    codomain: c,
                    evidence: Some(evidence),
                });
                c
            }
            None => {
                reasons.push(Reason::Stokes {
                    codomain: Codomain::Full,
                    evidence: None,
                });
                Codomain::Full
            }
        };
        let visibility = match settings.visibility {
            Visibility::Rays if tolerance.is_some() && single_convex_object(scene) => {
                Visibility::TangentPlane
            }
            asked => asked,
        };
        reasons.push(Reason::Visibility {
            asked: settings.visibility,
            chosen: visibility,
            rays: settings.rays,
            planned: tolerance.is_some(),
        });
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
            .map(|(high, low)| material_plan(high, low, &env_high, l, tolerance, codomain))
            .collect::<Result<Vec<_>>>()?;
        let dense = 3 * (num_coeffs(l) * codomain.components().len()).pow(2);
        for (k, m) in materials.iter().enumerate() {
            reasons.push(Reason::Material {
                index: k,
                sparsity: m.sparsity,
                stored: m.operators.iter().map(SparsePshMatrix::stored).sum(),
                dense,
                isotropy_defect: m.isotropy_defect,
                l_high: (m.l_high > l).then_some(m.l_high),
                dropped_tail: m.dropped_tail,
            });
        }
        Ok(Plan {
            settings,
            planning,
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
) -> Result<(Codomain, StokesEvidence)> {
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
    let codomain = if linear <= tol && circular <= tol && polarizes <= tol {
        Codomain::Intensity
    } else if circular <= tol && circularizes <= tol {
        Codomain::NoCircular
    } else {
        Codomain::Full
    };
    Ok((
        codomain,
        StokesEvidence {
            linear,
            circular,
            polarizes,
            circularizes,
            tolerance: tol,
        },
    ))
}

/// The plan of one material: its matrices `low` (`l <= l_low`) stored isotropic sparse
/// when their isotropy defect is within the tolerance, general sparse otherwise; the high
/// orders from its matrices `high` to `l_high` and the environment `env_high`
/// ([`high_orders`]).
fn material_plan(
    high: &[PshMatrix],
    low: &[PshMatrix],
    env_high: &PshVector,
    l: usize,
    tolerance: Option<f64>,
    codomain: Codomain,
) -> Result<MaterialPlan> {
    let defect = low.iter().map(isotropy_defect).fold(0.0, f64::max);
    let sparsity = match tolerance {
        Some(tol) if defect <= tol => Sparsity::Isotropic,
        _ => Sparsity::General,
    };
    let operators = low
        .iter()
        .map(|m| SparsePshMatrix::new(m, codomain, codomain, sparsity))
        .collect();
    let (l_high, high, dropped_tail) = high_orders(high, env_high, l, tolerance, codomain)?;
    Ok(MaterialPlan {
        operators,
        sparsity,
        isotropy_defect: defect,
        l_high,
        high,
        dropped_tail,
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
    let e = g.band_energies()?;
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
