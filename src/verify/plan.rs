//! Checks of the PPRT planner (`psh::pprt::plan`): the planned render against the full
//! one, and the tangent-plane visibility against its closed form.

use super::Check;
use crate::error::{Error, Result};
use crate::polarized::Codomain;
use crate::pprt::mesh::Mesh;
use crate::pprt::plan::{tangent_plane_visibility, Plan};
use crate::pprt::render::vertex_stokes;
use crate::pprt::scene::{Camera, Scene, SceneMaterial, SceneObject};
use crate::pprt::sky::RayleighSky;
use crate::pprt::transfer::precompute_planned;
use crate::pprt::TransferSettings;
use crate::pprt::Visibility;
use crate::sh::lm_index;
use std::f64::consts::PI;

pub fn checks() -> Vec<Check> {
    vec![
        Check {
            id: "plan.tangent_plane_visibility",
            source: "PSH (12), (54)",
            description: "zonal SH coefficients l <= 40 of the hemisphere H(z > 0) by Gauss-Legendre on [0, 1] vs 2 pi sqrt((2l+1)/(4 pi)) (P_{l-1}(0) - P_{l+1}(0)) / (2l+1) (max absolute)",
            tolerance: 1e-14,
            proof: Some("proofs/tangent-plane-visibility.md"),
            run: tangent_plane_closed_form,
        },
        Check {
            id: "plan.unpolarized_vs_full",
            source: "PSH (41), Sec. 7",
            description: "the built-in geometry with Lambertian materials under the sky's s0 (l_low 4, l_high 9, 64 rays): planned at tolerance 1e-3 (scalar SH, sparse storage, high orders cut by band energy) vs everything computed, vertex Stokes vectors in the camera's frames (max difference relative to the largest s0; fails if the plan is not scalar)",
            tolerance: 1e-3,
            proof: None,
            run: || unpolarized_vs_full(64),
        },
        Check {
            id: "plan.tangent_plane_vs_rays",
            source: "PSH (54)-(56)",
            description: "one convex sphere (glossy plastic, polarized sky, l_low 6): the plan's fixed tangent-plane shadowing (no rays, s3 dropped) vs 16,384 ray-cast visibility directions per vertex, vertex Stokes vectors (max difference relative to the largest s0; the rays' quadrature error of the horizon; fails if the plan keeps rays or s3)",
            tolerance: 2e-3,
            proof: Some("proofs/tangent-plane-visibility.md"),
            run: || tangent_plane_vs_rays(16384),
        },
    ]
}

/// `h_l0` against the closed form `2 pi sqrt((2l+1)/(4 pi)) int_0^1 P_l`, with
/// `int_0^1 P_l = (P_{l-1}(0) - P_{l+1}(0)) / (2l+1)` (`l >= 1`) and `P_k(0)` by
/// `P_{k+1}(0) = -k/(k+1) P_{k-1}(0)`; the `m != 0` coefficients must be zero.
pub fn tangent_plane_closed_form() -> Result<f64> {
    let lv = 40;
    let h = tangent_plane_visibility(lv)?;
    let h = h.data();
    let mut p0 = vec![0.0; lv + 2];
    p0[0] = 1.0;
    for k in 1..=lv {
        p0[k + 1] = -(k as f64) / (k + 1) as f64 * p0[k - 1];
    }
    let mut worst = 0.0f64;
    for l in 0..=lv {
        let integral = if l == 0 {
            1.0
        } else {
            (p0[l - 1] - p0[l + 1]) / (2 * l + 1) as f64
        };
        let want = 2.0 * PI * ((2 * l + 1) as f64 / (4.0 * PI)).sqrt() * integral;
        worst = worst.max((h[lm_index(l, 0)] - want).abs());
        for m in 1..=l as i64 {
            worst = worst.max(h[lm_index(l, m)].abs().max(h[lm_index(l, -m)].abs()));
        }
    }
    Ok(worst)
}

/// Max difference of the vertex Stokes vectors of `planned` and `full`, relative to the
/// largest `s0` of `full`.
fn vertex_difference(scene: &Scene, planned: &Plan, full: &Plan) -> Result<f64> {
    let hidden = crate::progress::Silent;
    let a = vertex_stokes(
        scene,
        &precompute_planned(scene, planned, &hidden)?,
        &planned.high_fields(),
    )?;
    let b = vertex_stokes(
        scene,
        &precompute_planned(scene, full, &hidden)?,
        &full.high_fields(),
    )?;
    let (mut diff, mut scale) = (0.0f64, 0.0f64);
    for (x, y) in a.iter().flatten().zip(b.iter().flatten()) {
        for c in 0..3 {
            scale = scale.max(y[c][0].abs());
            for q in 0..4 {
                diff = diff.max((x[c][q] - y[c][q]).abs());
            }
        }
    }
    Ok(diff / scale)
}

fn wrong_plan(what: &str, plan: &Plan) -> Error {
    Error::invalid(
        "plan",
        format!("{:?}, {:?}", plan.codomain, plan.visibility),
        format!("expected {what}"),
    )
}

/// `vertex_difference` of the unpolarized built-in scene, planned at `1e-3` and full,
/// with `rays` visibility directions.
pub fn unpolarized_vs_full(rays: usize) -> Result<f64> {
    let scene = crate::pprt::builtin::builtin_unpolarized_scene(9, 16, 12)?;
    let settings = TransferSettings {
        l_low: 4,
        l_high: Some(9),
        rays,
        visibility: crate::pprt::Visibility::Rays,
    };
    let planned = Plan::new(&scene, settings, crate::pprt::Planning::Tolerance(1e-3))?;
    if planned.codomain != Codomain::Intensity || planned.visibility != Visibility::Rays {
        return Err(wrong_plan("scalar SH with rays", &planned));
    }
    vertex_difference(
        &scene,
        &planned,
        &Plan::new(&scene, settings, crate::pprt::Planning::Full)?,
    )
}

/// One glossy plastic sphere under the polarized sky, `l_low = 6`, no high orders.
pub fn convex_scene(lmax: usize) -> Result<Scene> {
    let sky = RayleighSky::new(35f64.to_radians(), 2.4)?;
    let camera = Camera::look_at([0.0, -4.0, 1.5], [0.0, 0.0, 0.0], 0.6, 16, 12)?;
    Scene::new(
        vec![SceneObject {
            mesh: Mesh::sphere([0.0, 0.0, 0.0], 1.0, 12, 24)?,
            material: 0,
        }],
        vec![SceneMaterial::Plastic(
            crate::optics::PolarizedPlastic::new(0.3, 1.5, 0.5)?,
        )],
        sky.project(lmax)?,
        camera,
    )
}

/// `vertex_difference` of [`convex_scene`]: the plan's tangent-plane shadowing against
/// `rays` ray-cast directions.
pub fn tangent_plane_vs_rays(rays: usize) -> Result<f64> {
    let scene = convex_scene(6)?;
    let settings = TransferSettings {
        l_low: 6,
        l_high: None,
        rays,
        visibility: crate::pprt::Visibility::Rays,
    };
    let planned = Plan::new(&scene, settings, crate::pprt::Planning::Tolerance(1e-3))?;
    if planned.codomain != Codomain::NoCircular || planned.visibility != Visibility::TangentPlane {
        return Err(wrong_plan("s0..s2 with the tangent plane", &planned));
    }
    vertex_difference(
        &scene,
        &planned,
        &Plan::new(&scene, settings, crate::pprt::Planning::Full)?,
    )
}
