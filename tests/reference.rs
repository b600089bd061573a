//! The reference renderer (`pprt::reference`) against PPRT: integrating exactly what
//! unshadowed PPRT integrates (the band-limited environment and pBRDF matrices over the
//! whole sphere), it converges to the PPRT vertex values as the samples grow.

use psh::pprt::job::builtin_scene;
use psh::pprt::reference::{Fidelity, Reference, ReferenceSettings};
use psh::pprt::render::vertex_stokes;
use psh::pprt::transfer::{precompute, TransferSettings};

#[test]
fn reference_converges_to_pprt_on_a_band_limited_scene() {
    let l = 3;
    let scene = builtin_scene(l, 16, 12).unwrap();
    let settings = TransferSettings {
        l_low: l,
        l_high: 0,
        rays: 1,
        shadows: false,
    };
    let transfer = precompute(&scene, settings).unwrap();
    let none = vec![None; scene.materials().len()];
    let pprt = vertex_stokes(&scene, &transfer, &none).unwrap();
    let vertices: Vec<(usize, usize)> = scene
        .objects()
        .iter()
        .enumerate()
        .flat_map(|(o, obj)| {
            (0..obj.mesh.positions().len())
                .step_by(173)
                .map(move |v| (o, v))
        })
        .collect();
    let scale = pprt
        .iter()
        .flatten()
        .map(|v| v[1][0].abs())
        .fold(0.0, f64::max);
    let ladder = [64, 256, 1024, 4096];
    let errors: Vec<f64> = ladder
        .iter()
        .map(|&samples| {
            let r = Reference::new(
                &scene,
                ReferenceSettings {
                    samples,
                    fidelity: Fidelity::BandLimited(l),
                    seed: 7,
                },
            )
            .unwrap();
            let got = r.vertex_stokes(&vertices).unwrap();
            let mut sq = 0.0;
            for (g, &(o, v)) in got.iter().zip(&vertices) {
                for c in 0..3 {
                    for q in 0..4 {
                        sq += (g[c][q] - pprt[o][v][c][q]).powi(2);
                    }
                }
            }
            (sq / (12 * vertices.len()) as f64).sqrt() / scale
        })
        .collect();
    let slope = (errors[3] / errors[0]).ln() / (4096f64 / 64.0).ln();
    println!(
        "{} vertices; RMS error relative to the largest s0 per sample count {ladder:?}: \
         {errors:?}; log-log slope {slope:.2}",
        vertices.len()
    );
    assert!(errors[3] < 1e-3, "{errors:?}");
    assert!(slope < -0.8, "{slope}");
}
