//! Criterion benches of the PPRT planner: `plan/unpolarized_scene/planned` (the planner on,
//! which reduces the scene to scalar SH) against `plan/unpolarized_scene/scalar_only`, the
//! same transfer and frame written directly with scalar SH (real Gaunt products, real
//! Wigner rotations, the dense `s0 -> s0` block of each material, real SH evaluation).
//! Both time precomputation plus one frame; the plan and the materials' projection are
//! built once, outside (the plan's own cost is printed). `plan/unpolarized_scene/full`
//! is the same with everything computed ([`Plan::full`]): the saving.

use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::Vector3;
use psh::geometry::direction_angles;
use psh::pprt::stages::{direct_light, primary_hits, render_frame};
use psh::pprt::stages::{precompute_planned, ray_visibility, VisibilityRays};
use psh::pprt::Plan;
use psh::pprt::TransferSettings;
use psh::pprt::{Hit, Scene};
use psh::sh::num_coeffs;
use psh::sh::RealWignerD;
use psh::sh::ShEvaluator;
use psh::sh::{GauntBasis, GauntTable};
use rayon::prelude::*;
use std::time::Instant;

const SETTINGS: TransferSettings = TransferSettings::new(6, None, 64, psh::pprt::Visibility::Rays);

/// Scalar PRT of `scene`: per vertex the ray-cast visibility's Gaunt product with the
/// environment's `s0`, rotated to the shading frame and multiplied by `blocks[material]`
/// (RGB dense `s0 -> s0` blocks); the frame evaluates it at the view direction and
/// interpolates. Returns `s0` per pixel and channel.
fn scalar_only(scene: &Scene, blocks: &[Vec<Vec<f64>>], hits: &[Option<Hit>]) -> Vec<[f64; 3]> {
    let l = SETTINGS.l_low;
    let n = num_coeffs(l);
    let rays = VisibilityRays::new(SETTINGS.rays, 2 * l).unwrap();
    let gaunt = GauntTable::new(GauntBasis::Real, 2 * l, l, l).unwrap();
    let env = scene.environment();
    let env0: Vec<Vec<f64>> = (0..3)
        .map(|c| {
            (0..n)
                .map(|j| {
                    let (lj, m) = psh::sh::lm_of_index(j);
                    env.get(c, lj, m, 0).unwrap()
                })
                .collect()
        })
        .collect();
    let eye = Vector3::from(scene.camera().position);
    let eval = ShEvaluator::new(l).unwrap();
    let vertex_s0: Vec<Vec<[f64; 3]>> = scene
        .objects()
        .iter()
        .map(|o| {
            let mats = &blocks[o.material];
            o.mesh
                .positions()
                .par_iter()
                .zip(o.mesh.normals())
                .map(|(p, nrm)| {
                    let v = ray_visibility(scene, *p, *nrm, &rays).unwrap();
                    let rotation = psh::geometry::Frame::from_z(*nrm).unwrap().rotation();
                    let to_local = RealWignerD::new(&rotation.inverse(), l).unwrap();
                    let view = rotation.inverse() * (eye - Vector3::from(*p)).normalize();
                    let (t, ph) = direction_angles([view.x, view.y, view.z]).unwrap();
                    let mut y = vec![0.0; n];
                    eval.real(t, ph, &mut y).unwrap();
                    std::array::from_fn(|c| {
                        let shadowed = gaunt.product(v.data(), &env0[c]).unwrap();
                        let local = to_local.rotate(&shadowed).unwrap();
                        let out: Vec<f64> = mats[c]
                            .chunks_exact(n)
                            .map(|row| row.iter().zip(&local).map(|(a, b)| a * b).sum())
                            .collect();
                        out.iter().zip(&y).map(|(a, b)| a * b).sum()
                    })
                })
                .collect()
        })
        .collect();
    hits.par_iter()
        .map(|h| match h {
            Some(h) => {
                let t = scene.objects()[h.object].mesh.triangles()[h.triangle];
                let w = [1.0 - h.u - h.v, h.u, h.v];
                let vs = &vertex_s0[h.object];
                std::array::from_fn(|c| (0..3).map(|i| w[i] * vs[t[i] as usize][c]).sum())
            }
            None => [0.0; 3],
        })
        .collect()
}

fn plan(c: &mut Criterion) {
    let scene = psh::pprt::builtin_unpolarized_scene(SETTINGS.l_low, 96, 72).unwrap();
    let t0 = Instant::now();
    let plan = Plan::new(&scene, SETTINGS, psh::pprt::Planning::Tolerance(1e-3)).unwrap();
    eprintln!(
        "plan/unpolarized_scene: plan built in {:.3} s: {:?}",
        t0.elapsed().as_secs_f64(),
        plan.reasons
    );
    let blocks: Vec<Vec<Vec<f64>>> = scene
        .materials()
        .iter()
        .map(|m| {
            let n = num_coeffs(SETTINGS.l_low);
            m.matrices(SETTINGS.l_low)
                .unwrap()
                .iter()
                .map(|p| (0..n * n).map(|k| p.get(k / n, k % n, 0, 0)).collect())
                .collect()
        })
        .collect();
    let hits = primary_hits(&scene);
    let bg = direct_light(&scene, &hits).unwrap();
    let hidden = psh::progress::Silent;
    let planned = || {
        let t = precompute_planned(&scene, &plan, &hidden).unwrap();
        render_frame(&scene, &t, &plan.high_fields(), &hits, &bg).unwrap()
    };
    // The two compute the same picture.
    let (a, b) = (planned(), scalar_only(&scene, &blocks, &hits));
    let top = b.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    for (k, s) in b.iter().enumerate() {
        if hits[k].is_some() {
            for (ch, x) in s.iter().enumerate() {
                let d = (a.channels[ch][k][0] - x).abs();
                assert!(d <= 1e-10 * top, "pixel {k} channel {ch}: {d:e}");
            }
        }
    }
    let mut grp = c.benchmark_group("plan/unpolarized_scene");
    grp.sample_size(10);
    grp.bench_function("planned", |bch| bch.iter(planned));
    grp.bench_function("scalar_only", |bch| {
        bch.iter(|| scalar_only(&scene, &blocks, &hits))
    });
    // The saving: everything computed (s0..s3, dense storage).
    let full = Plan::new(&scene, SETTINGS, psh::pprt::Planning::Full).unwrap();
    grp.bench_function("full", |bch| {
        bch.iter(|| {
            let t = precompute_planned(&scene, &full, &hidden).unwrap();
            render_frame(&scene, &t, &full.high_fields(), &hits, &bg).unwrap()
        })
    });
    grp.finish();
}

criterion_group!(benches, plan);
criterion_main!(benches);
