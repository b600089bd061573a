//! Criterion benches of the scalar SH core (ids as in the issue tracker).

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use psh::geometry::rotation_from_rotvec;
use psh::random::pseudo_random;
use psh::sh::for_each_block;
use psh::sh::num_coeffs;
use psh::sh::ShEvaluator;
use psh::sh::ShTransform;
use psh::testing::random_directions;

/// All complex Wigner blocks l <= L of one generic rotation, each block visited once.
fn wigner_d(c: &mut Criterion) {
    let mut g = c.benchmark_group("wigner_d");
    g.sample_size(10);
    let r = rotation_from_rotvec([0.3, -1.1, 0.7]).unwrap();
    for lmax in [100usize, 500] {
        g.bench_with_input(BenchmarkId::new("all_l", lmax), &lmax, |b, &lmax| {
            b.iter(|| {
                let mut sum = 0.0;
                for_each_block(&r, lmax, |_, blk| sum += blk[0].re).unwrap();
                black_box(sum)
            })
        });
    }
    g.finish();
}

/// Real SH of all l <= L at 10,000 directions (batch, row per direction).
fn sh_real(c: &mut Criterion) {
    let mut g = c.benchmark_group("sh_real");
    let dirs = random_directions(10_000, 1);
    for lmax in [4usize, 20] {
        let ev = ShEvaluator::new(lmax).unwrap();
        let mut out = vec![0.0; dirs.len() * ev.len()];
        g.bench_with_input(BenchmarkId::new("all_lm_1e4_dirs", lmax), &lmax, |b, _| {
            b.iter(|| ev.real_batch(black_box(&dirs), &mut out).unwrap())
        });
    }
    g.finish();
}

/// Real-field transforms on the exact (Gauss-Legendre) grid.
fn sht_scalar(c: &mut Criterion) {
    let mut g = c.benchmark_group("sht_scalar");
    g.sample_size(20);
    for lmax in [128usize, 512, 2048] {
        let t = ShTransform::new(lmax).unwrap();
        let coeffs = pseudo_random(num_coeffs(lmax), 2);
        let mut field = vec![0.0; t.grid().len()];
        t.synthesis_real(&coeffs, &mut field).unwrap();
        let mut back = vec![0.0; coeffs.len()];
        g.bench_with_input(BenchmarkId::new("analysis_gl", lmax), &lmax, |b, _| {
            b.iter(|| t.analysis_real(black_box(&field), &mut back).unwrap())
        });
        g.bench_with_input(BenchmarkId::new("synthesis_gl", lmax), &lmax, |b, _| {
            b.iter(|| t.synthesis_real(black_box(&coeffs), &mut field).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, wigner_d, sh_real, sht_scalar);
criterion_main!(benches);
