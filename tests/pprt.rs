//! PPRT against direct numerical integration at sampled vertices: the outgoing Stokes
//! vector of the precomputed transfer equals `int P(w_i, w_o) V(w_i) L(w_i) dw_i` computed
//! in world coordinates on a quadrature grid, with the band-limited environment, pBRDF
//! (the Mueller field of its coefficient matrix, rotated to the vertex) and visibility
//! (the vertex's SH vector). Everything band-limited, so the comparison is exact up to
//! rounding; the band limit itself is the approximation PPRT makes (not measured here).

use psh::geometry::frame::{FrameField, ThetaPhiFrameField};
use psh::polarized::{MatrixKernel, PshTransform};
use psh::pprt::job::builtin_scene;
use psh::pprt::transfer::{precompute, TransferSettings};
use psh::sh::harmonics::sh_real;
use psh::stokes::MuellerField;

fn check(shadows: bool) {
    let l = 3;
    let scene = builtin_scene(l, 8, 6).unwrap();
    let settings = TransferSettings {
        l_low: l,
        rays: 64,
        shadows,
    };
    let transfer = precompute(&scene, settings).unwrap();
    let env = scene.environment();
    let grid = PshTransform::new(4 * l).unwrap();
    let g = grid.grid();
    let tp = ThetaPhiFrameField::new();
    let mut worst = 0.0f64;
    for (object, vertex) in [(1usize, 40usize), (2, 300), (0, 100)] {
        let vt = &transfer[object][vertex];
        let mats = scene.materials()[scene.objects()[object].material]
            .matrices(l)
            .unwrap();
        let r = vt.rotation;
        let rinv = r.inverse();
        let turn = |m: &nalgebra::Rotation3<f64>, w: [f64; 3]| {
            let v = m * nalgebra::Vector3::from(w);
            [v.x, v.y, v.z]
        };
        for wo in [[0.3, -0.5, 0.81], [-0.6, 0.1, 0.79], [0.0, 0.0, 1.0]] {
            let n = nalgebra::Vector3::from(wo).normalize();
            let wo = [n.x, n.y, n.z];
            let wo_world = turn(&r, wo);
            let fo = tp.frame(wo_world).unwrap();
            let pprt = vt.radiance.evaluate_all(wo).unwrap();
            for c in 0..3 {
                let kernel = MatrixKernel(&mats[c]);
                let mut acc = nalgebra::Vector4::zeros();
                for i in 0..g.len() {
                    let wi = g.direction(i).unwrap();
                    let (t, p) = g.angles(i).unwrap();
                    let vis = if shadows {
                        let y = sh_real(2 * l, t, p).unwrap();
                        vt.visibility
                            .iter()
                            .zip(&y)
                            .map(|(a, b)| a * b)
                            .sum::<f64>()
                    } else {
                        1.0
                    };
                    let local = kernel.transform(turn(&rinv, wi), wo).unwrap();
                    let fi = local.frame_in().rotated(&r).unwrap();
                    let fo_local = local.frame_out().rotated(&r).unwrap();
                    let m = psh::stokes::MuellerTransform::new(local.matrix(), fi, fo_local);
                    let s = env.evaluate_all(wi).unwrap().swap_remove(c);
                    let out = m.apply(&s).unwrap().components_in(&fo).unwrap().vector();
                    acc += g.point_weight(i) * vis * out;
                }
                let ours = psh::stokes::StokesVector::new(
                    pprt[c].components(),
                    pprt[c].frame().rotated(&r).unwrap(),
                )
                .components_in(&fo)
                .unwrap()
                .vector();
                let scale = acc.norm().max(1e-3);
                worst = worst.max((ours - acc).norm() / scale);
            }
        }
    }
    println!("shadows {shadows}: largest relative difference {worst:e}");
    assert!(worst < 1e-10, "{worst}");
}

#[test]
fn pprt_equals_direct_integration_without_shadows() {
    check(false);
}

#[test]
fn pprt_equals_direct_integration_with_shadows() {
    check(true);
}
