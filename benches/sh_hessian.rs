//! Criterion benches of the SH gradients and Hessians via solid harmonics (SHH Sec. 4).

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use psh::sh::SolidHarmonics;
use psh::testing::random_directions;

/// Values, gradients and Hessians of all real SH `l <= L` at 10,000 directions (the
/// setting of SHH Fig. 4), outputs reused across iterations: `1e4_dirs` on every core
/// (rayon's pool), `1e4_dirs_1thread` on one.
fn sh_hessian(c: &mut Criterion) {
    let mut g = c.benchmark_group("sh_hessian");
    let dirs = random_directions(10_000, 7);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    for lmax in [4usize, 20] {
        let sh = SolidHarmonics::new(lmax).unwrap();
        let n = dirs.len() * sh.len();
        let (mut v, mut gr, mut h) = (vec![0.0; n], vec![[0.0; 3]; n], vec![[0.0; 6]; n]);
        g.bench_with_input(BenchmarkId::new("1e4_dirs", lmax), &lmax, |b, _| {
            b.iter(|| {
                sh.eval_batch(black_box(&dirs), &mut v, &mut gr, &mut h)
                    .unwrap()
            })
        });
        g.bench_with_input(BenchmarkId::new("1e4_dirs_1thread", lmax), &lmax, |b, _| {
            b.iter(|| {
                one.install(|| {
                    sh.eval_batch(black_box(&dirs), &mut v, &mut gr, &mut h)
                        .unwrap()
                })
            })
        });
    }
    g.finish();
}

criterion_group!(benches, sh_hessian);
criterion_main!(benches);
