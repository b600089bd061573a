//! Criterion benches of polarized SH (ids as in the issue tracker).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use psh::geometry::rotation_from_rotvec;
use psh::geometry::CubeMapFrameField;
use psh::geometry::{CubeCross, PixelGrid};
use psh::polarized::{project_cube_map, project_image, Codomain, PshEvaluator, PshRotation};
use psh::random::pseudo_random;
use psh::testing::random_psh;

/// A 64x64x6 Stokes cube map, RGB, four components, to PSH coefficients l < 16.
fn psh_project(c: &mut Criterion) {
    let g = CubeCross::new(64).unwrap();
    let r = pseudo_random(g.len() * 4 * 3, 3);
    let images: Vec<Vec<[f64; 4]>> = (0..3)
        .map(|ch| {
            (0..g.len())
                .map(|i| {
                    let k = (ch * g.len() + i) * 4;
                    // s0 >= |(s1, s2, s3)|: a physical Stokes vector.
                    [2.0 + r[k], 0.5 * r[k + 1], 0.5 * r[k + 2], 0.2 * r[k + 3]]
                })
                .collect()
        })
        .collect();
    let refs: Vec<&[[f64; 4]]> = images.iter().map(|v| v.as_slice()).collect();
    let mut grp = c.benchmark_group("psh_project");
    grp.sample_size(10);
    // The cube-map path (`StokesMap::project`), and the generic texel quadrature.
    grp.bench_function("cube64/16", |b| {
        b.iter(|| project_cube_map(&g, black_box(&refs), Codomain::Full, 15).unwrap())
    });
    grp.bench_function("cube64_generic/16", |b| {
        b.iter(|| {
            project_image(&g, &CubeMapFrameField, black_box(&refs), Codomain::Full, 15).unwrap()
        })
    });
    grp.finish();
}

/// Rotate an RGB {s0..s3} coefficient vector of l < 100, Wigner blocks included:
/// `vector/100` streams them one degree at a time (`PshVector::rotated`, `psh rotate`,
/// Python's `rotated`), `stored/100` builds and keeps them all first (`PshRotation`, for
/// many vectors).
fn psh_rotate(c: &mut Criterion) {
    let v = random_psh(99, Codomain::Full, 3, 4).unwrap();
    let r = rotation_from_rotvec([0.3, -1.1, 0.7]).unwrap();
    let mut grp = c.benchmark_group("psh_rotate");
    grp.sample_size(20);
    grp.bench_function("vector/100", |b| {
        b.iter(|| black_box(&v).rotated(&r).unwrap())
    });
    grp.bench_function("stored/100", |b| {
        b.iter(|| {
            PshRotation::new(&r, 99)
                .unwrap()
                .rotate(black_box(&v))
                .unwrap()
        })
    });
    grp.finish();
}

/// Point evaluation PSH (30) of an RGB, four-component vector at 1,000 directions with one
/// `PshEvaluator` (the renderer's per-vertex step), l <= 4, 9 and 19 (the Python
/// quickstart's perspective view), one direction at a time and in a batch.
fn psh_evaluate(c: &mut Criterion) {
    let dirs = psh::testing::random_directions(1000, 5);
    let mut grp = c.benchmark_group("psh_evaluate");
    for lmax in [4, 9, 19] {
        let v = random_psh(lmax, Codomain::Full, 3, 6).unwrap();
        let mut eval = PshEvaluator::new(lmax).unwrap();
        grp.bench_function(format!("1000_dirs/{lmax}"), |b| {
            b.iter(|| {
                dirs.iter()
                    .map(|&w| {
                        eval.evaluate_all(black_box(&v), w).unwrap()[0]
                            .components()
                            .to_array()[1]
                    })
                    .sum::<f64>()
            })
        });
        // The same directions at once (`PshEvaluator::evaluate_batch`: the sums over four
        // directions in lanes), components in the theta-phi frames.
        let mut out = vec![[0.0; 4]; 3 * dirs.len()];
        grp.bench_function(format!("batch_1000_dirs/{lmax}"), |b| {
            b.iter(|| {
                eval.evaluate_batch(black_box(&v), &dirs, &mut out).unwrap();
                out[0][1]
            })
        });
    }
    grp.finish();
}

criterion_group!(benches, psh_project, psh_rotate, psh_evaluate);
criterion_main!(benches);
