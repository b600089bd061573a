//! Criterion benches of PSH coefficient matrices (ids as in the issue tracker).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use psh::geometry::rotation_from_rotvec;
use psh::optics::{PolarizedPlastic, TabulatedPbrdf};
use psh::polarized::{
    horizon_free_grid, project_isotropic_with, project_operator, Codomain, IsotropicMatrix,
    SpinBlock22,
};
use psh::progress::Silent;
use psh::stokes::MuellerField;
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

/// Project a measured table at the KAIST dataset's downsampled resolution (73 x 19 x 19,
/// three RGB channels: a plastic sampled into each) to isotropic matrices of l < 20 on the
/// horizon-free grid, as `psh pbrdf project --lmax 19` does (the anchor: polarsh's
/// `MuellerField.from_SB20` + `SHCoeff(20)`, docs/measured-pbrdf.md).
fn project_table(c: &mut Criterion) {
    use std::f64::consts::PI;
    let plastic = PolarizedPlastic::new(0.3, 1.5, 0.5).unwrap();
    let n = |k: usize, n: usize| k as f64 / (n - 1) as f64;
    let table = TabulatedPbrdf::sample(
        &[&plastic, &plastic, &plastic],
        (0..73).map(|k| -PI + 2.0 * PI * n(k, 73)).collect(),
        (0..19).map(|k| PI / 2.0 * n(k, 19)).collect(),
        (0..19).map(|k| PI / 2.0 * n(k, 19).powi(2)).collect(),
        vec![611.0, 549.0, 464.0],
    )
    .unwrap();
    let channels: Vec<_> = (0..3).map(|k| table.channel(k).unwrap()).collect();
    let fields: Vec<&dyn MuellerField> = channels.iter().map(|c| c as _).collect();
    let mut grp = c.benchmark_group("psh_matrix");
    grp.sample_size(10);
    grp.bench_function("project_table/20", |b| {
        b.iter(|| {
            project_isotropic_with(black_box(&fields), 19, horizon_free_grid(19), 1e-3, &Silent)
                .unwrap()
        })
    });
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

criterion_group!(
    benches,
    project_isotropic,
    project_table,
    apply_sparse,
    rotate_to_normal
);
criterion_main!(benches);
