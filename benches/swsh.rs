//! Criterion benches of the spin-weighted transforms (ids as in the issue tracker).

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use num_complex::Complex64;
use psh::random::pseudo_random;
use psh::sh::num_coeffs;
use psh::swsh::SpinTransform;

/// Spin-2 (linear polarization) transforms on the exact Gauss-Legendre grid: `sht_spin2`
/// on every core (rayon's pool), `sht_spin2_1thread` on one (ducc0's default).
fn sht_spin2(c: &mut Criterion) {
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    for (group, pool) in [("sht_spin2", None), ("sht_spin2_1thread", Some(&one))] {
        let mut g = c.benchmark_group(group);
        g.sample_size(10);
        for lmax in [128usize, 512] {
            let t = SpinTransform::new(2, lmax).unwrap();
            let re = pseudo_random(num_coeffs(lmax), 7);
            let coeffs: Vec<Complex64> = re.iter().map(|&x| Complex64::new(x, -x)).collect();
            let mut field = vec![Complex64::default(); t.grid().len()];
            t.synthesis(&coeffs, &mut field).unwrap();
            let mut back = vec![Complex64::default(); coeffs.len()];
            g.bench_with_input(BenchmarkId::new("analysis_gl", lmax), &lmax, |b, _| {
                b.iter(|| run(pool, || t.analysis(black_box(&field), &mut back).unwrap()))
            });
            g.bench_with_input(BenchmarkId::new("synthesis_gl", lmax), &lmax, |b, _| {
                b.iter(|| {
                    run(pool, || {
                        t.synthesis(black_box(&coeffs), &mut field).unwrap()
                    })
                })
            });
        }
        g.finish();
    }
}

/// `f` on `pool`, or on the global pool.
fn run<R: Send>(pool: Option<&rayon::ThreadPool>, f: impl FnOnce() -> R + Send) -> R {
    match pool {
        Some(p) => p.install(f),
        None => f(),
    }
}

criterion_group!(benches, sht_spin2);
criterion_main!(benches);
