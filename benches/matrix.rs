//! Criterion benches of PSH coefficient matrices (ids as in the issue tracker).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use psh::geometry::rotation_from_rotvec;
use psh::optics::PolarizedPlastic;
use psh::polarized::{project_operator, Codomain, IsotropicMatrix, SpinBlock22};
use psh::testing::random_psh;

/// Project an isotropic pBRDF (polarized plastic) to a sparse PSH matrix of l < 5 and
/// l < 10 on the exact grid of the same band.
fn project_isotropic(c: &mut Criterion) {
    let plastic = PolarizedPlastic::new(0.3, 1.5, 0.5).unwrap();
    let mut grp = c.benchmark_group("psh_matrix");
    grp.sample_size(10);
    for l in [5usize, 10] {
        grp.bench_function(format!("project_isotropic/{l}"), |b| {
            b.iter(|| {
                let m =
                    project_operator(black_box(&plastic), l - 1, l - 1, SpinBlock22::ComplexPair)
                        .unwrap();
                IsotropicMatrix::from_dense(&m, 1e-12).unwrap()
            })
        });
    }
    grp.finish();
}

/// Apply a sparse isotropic matrix of l < 20 to an RGB full-Stokes coefficient vector.
fn apply_sparse(c: &mut Criterion) {
    let plastic = PolarizedPlastic::new(0.3, 1.5, 0.5).unwrap();
    let m = project_operator(&plastic, 19, 19, SpinBlock22::ComplexPair).unwrap();
    let sparse = IsotropicMatrix::from_dense(&m, 1e-12).unwrap();
    let f = random_psh(19, Codomain::Full, 3, 1).unwrap();
    let mut grp = c.benchmark_group("psh_matrix");
    grp.bench_function("apply_sparse/20", |b| {
        b.iter(|| sparse.apply(black_box(&f)).unwrap())
    });
    grp.finish();
}

/// Rotate the (dense) PSH matrix of l < 10 of an isotropic pBRDF to a surface normal.
fn rotate_to_normal(c: &mut Criterion) {
    let plastic = PolarizedPlastic::new(0.3, 1.5, 0.5).unwrap();
    let m = project_operator(&plastic, 9, 9, SpinBlock22::ComplexPair).unwrap();
    // The rotation taking +z to the normal (0.48, -0.6, 0.64): axis z x n, angle acos 0.64.
    let r = rotation_from_rotvec([0.684608, 0.547686, 0.0]).unwrap();
    let mut grp = c.benchmark_group("psh_matrix");
    grp.sample_size(20);
    grp.bench_function("rotate_to_normal/10", |b| {
        b.iter(|| m.rotated(black_box(&r)).unwrap())
    });
    grp.finish();
}

criterion_group!(benches, project_isotropic, apply_sparse, rotate_to_normal);
criterion_main!(benches);
