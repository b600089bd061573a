//! Precomputation of polarized radiance transfer (PSH Sec. 7) for the vertices of a scene:
//! visibility by ray casting (directions below the vertex's tangent plane count as
//! occluded by the surface itself, without a ray), its scalar SH vector, the shadowed environment by the triple
//! product PSH (54)-(56), turned into the vertex's shading frame (PSH (35)-(37)) and
//! reflected by the pBRDF's coefficient matrix PSH (41).
//!
//! The result per vertex is the outgoing radiance field `P V f` as PSH coefficients in the
//! vertex's shading frame (normal `+z`), so a frame costs one evaluation per vertex.
//! Equivalently `D P D^T V f` in world coordinates (PSH (59)): the pBRDF rotated to the
//! vertex. The environment is fixed at precomputation; a new environment re-runs the
//! products, not the ray casting (the visibility vectors are kept).

use super::plan::Plan;
use super::scene::Scene;
use super::settings::{Planning, TransferSettings, Visibility};
use crate::error::{check_len, Error, Result};
use crate::geometry::fibonacci_directions;
use crate::geometry::frame::Frame;
use crate::polarized::{PshVector, TripleTable};
use crate::progress::{Progress, Silent};
use crate::sh::evaluation::harmonics::ShEvaluator;
use crate::sh::num_coeffs;
use nalgebra::Rotation3;
use rayon::prelude::*;

/// The transfer of one vertex.
#[derive(Clone, Debug, PartialEq)]
pub struct VertexTransfer {
    /// Shading frame to world (`R z = n`).
    pub rotation: Rotation3<f64>,
    /// Visibility as a scalar field of real SH (`l <= 2 l_low`, indexed by the direction
    /// towards the source), `None` without shadow rays.
    pub visibility: Option<PshVector>,
    /// Outgoing radiance (RGB, `s0..s3`, `l <= l_low`, indexed by the direction of
    /// travel) in the shading frame.
    pub radiance: PshVector,
}

/// The visibility rays of the transfer: `n` Fibonacci directions and their real SH of
/// degree `<= lv`, built once per precomputation.
#[derive(Clone, Debug)]
pub struct VisibilityRays {
    lv: usize,
    dirs: Vec<[f64; 3]>,
    /// `[direction][l*l + l + m]`.
    basis: Vec<f64>,
}

impl VisibilityRays {
    /// `n` directions, SH to degree `lv`. Errors: `lv` out of range; the directions and
    /// their SH over the memory budget ([`crate::budget`]).
    pub fn new(n: usize, lv: usize) -> Result<Self> {
        let eval = ShEvaluator::new(lv)?;
        crate::budget::check(
            "the visibility rays with their SH",
            &[n, num_coeffs(lv) + 3],
            8,
        )?;
        let dirs = fibonacci_directions(n);
        let mut basis = vec![0.0; dirs.len() * num_coeffs(lv)];
        eval.real_batch(&dirs, &mut basis)?;
        Ok(Self { lv, dirs, basis })
    }
}

/// The visibility at the point `p` of unit normal `n` as a scalar field of real SH
/// (`l <= lv`, indexed by the direction towards the source): the equal-weight
/// (`4 pi / n`) quadrature over the rays, a ray counting when it leaves above the tangent
/// plane (below, the surface itself occludes) from `p` offset by `1e-4` of the scene's
/// size along `n`, and hits nothing. Error: no rays.
pub fn ray_visibility(
    scene: &Scene,
    p: [f64; 3],
    n: [f64; 3],
    rays: &VisibilityRays,
) -> Result<PshVector> {
    if rays.dirs.is_empty() {
        return Err(Error::invalid("visibility rays", "0", "at least one ray"));
    }
    let nv = num_coeffs(rays.lv);
    let origin = scene.shadow_origin(p, n);
    let mut v = vec![0.0; nv];
    let w = 4.0 * std::f64::consts::PI / rays.dirs.len() as f64;
    for (d, y) in rays.dirs.iter().zip(rays.basis.chunks_exact(nv)) {
        let above = d[0] * n[0] + d[1] * n[1] + d[2] * n[2] > 0.0;
        if above && !scene.occluded(origin, *d, 0.0) {
            v.iter_mut().zip(y).for_each(|(a, b)| *a += w * b);
        }
    }
    PshVector::scalar(rays.lv, v)
}

/// Transfer of every vertex of every object, `[object][vertex]`, with everything computed
/// ([`Planning::Full`]). Errors: as [`TransferSettings::check`].
pub fn precompute(scene: &Scene, settings: TransferSettings) -> Result<Vec<Vec<VertexTransfer>>> {
    precompute_planned(scene, &Plan::new(scene, settings, Planning::Full)?, &Silent)
}

/// The transfer as `plan` says ([`super::Plan`]): its Stokes components, its visibility and
/// its sparse material operators, reporting the vertices done to `progress` (stage
/// "precompute"). Error: a plan
/// of another scene (another number of materials).
pub fn precompute_planned(
    scene: &Scene,
    plan: &Plan,
    progress: &dyn Progress,
) -> Result<Vec<Vec<VertexTransfer>>> {
    let settings = plan.settings;
    let rays = VisibilityRays::new(
        if plan.visibility == Visibility::Rays {
            settings.rays
        } else {
            0
        },
        2 * settings.l_low,
    )?;
    transfer_with(scene, plan, progress, &|_, _, p, n| {
        ray_visibility(scene, p, n, &rays)
    })
}

/// The transfer of `scene` as `plan` says with the visibility of `kept` (a transfer of
/// the same scene and plan: the vertices' visibility vectors are taken, no ray is cast):
/// after a change of the environment alone ([`Scene::with_environment_turned`]), the
/// products PSH (54)-(56), the turn into the shading frames PSH (35)-(37) and the pBRDF
/// PSH (41) again, as [`precompute_planned`] computes them. Errors: as
/// [`precompute_planned`], and `kept` not of this scene and plan (per vertex, a
/// visibility vector where the plan casts rays).
pub fn retransfer(
    scene: &Scene,
    plan: &Plan,
    kept: &[Vec<VertexTransfer>],
    progress: &dyn Progress,
) -> Result<Vec<Vec<VertexTransfer>>> {
    check_len("kept transfer objects", scene.objects().len(), kept.len())?;
    for (o, t) in scene.objects().iter().zip(kept) {
        check_len("kept vertex transfers", o.mesh.positions().len(), t.len())?;
    }
    transfer_with(scene, plan, progress, &|o, k, _, _| {
        kept[o][k].visibility.clone().ok_or_else(|| {
            Error::invalid(
                "kept transfer",
                format!("object {o}, vertex {k}: no visibility"),
                "a transfer precomputed with visibility rays under the same plan",
            )
        })
    })
}

/// The visibility of vertex `k` of object `o` at position `p`, normal `n`.
type VisibilityOf<'a> = dyn Fn(usize, usize, [f64; 3], [f64; 3]) -> Result<PshVector> + Sync + 'a;

/// [`precompute_planned`] with the visibility of each vertex from `visibility` (asked only
/// where the plan casts rays).
fn transfer_with(
    scene: &Scene,
    plan: &Plan,
    progress: &dyn Progress,
    visibility: &VisibilityOf,
) -> Result<Vec<Vec<VertexTransfer>>> {
    check_len(
        "planned materials",
        scene.materials().len(),
        plan.materials.len(),
    )?;
    let settings = plan.settings;
    let (l, codomain) = (settings.l_low, plan.codomain);
    let table = if plan.visibility == Visibility::Rays {
        Some(TripleTable::for_codomain(2 * l, l, codomain)?)
    } else {
        None
    };
    let env = scene.environment().truncated(l)?.with_codomain(codomain);
    let vertices = scene
        .objects()
        .iter()
        .map(|o| o.mesh.positions().len())
        .sum::<usize>();
    progress.start("precompute", vertices as u64);
    let transfer = scene
        .objects()
        .iter()
        .enumerate()
        .map(|(o, object)| {
            let ops = &plan.materials[object.material].operators;
            object
                .mesh
                .positions()
                .par_iter()
                .zip(object.mesh.normals())
                .enumerate()
                .map(|(k, (p, n))| {
                    progress.check_cancelled("the precomputation")?;
                    let rotation = Frame::from_z(*n)?.rotation();
                    let to_local = rotation.inverse();
                    let (visibility, local) = match (&table, &plan.horizon) {
                        (Some(t), _) => {
                            let v = visibility(o, k, *p, *n)?;
                            let local = t.shadow(&v, &env)?.rotated(&to_local)?;
                            (Some(v), local)
                        }
                        (None, Some(h)) => (None, h.apply(&env.rotated(&to_local)?)?),
                        (None, None) => (None, env.rotated(&to_local)?),
                    };
                    let parts = ops
                        .iter()
                        .enumerate()
                        .map(|(c, m)| m.apply(&local.channel(c)?))
                        .collect::<Result<Vec<_>>>()?;
                    progress.advance(1);
                    Ok(VertexTransfer {
                        rotation,
                        visibility,
                        radiance: PshVector::from_channels(&parts)?,
                    })
                })
                .collect::<Result<Vec<_>>>()
        })
        .collect();
    progress.finish();
    transfer
}

/// The high orders per material ([`super::stages::reflected_radiance`], [`Planning::Full`]): the environment
/// convolved with the kernel of the material's reflected pBRDF over the bands
/// `l_low < l <= l_high` (RGB); `None` for every material when `l_high <= l_low`. Error: an
/// environment below `l_high`.
pub fn high_order_fields(
    scene: &Scene,
    settings: TransferSettings,
) -> Result<Vec<Option<PshVector>>> {
    Ok(Plan::new(scene, settings, Planning::Full)?.high_fields())
}
