//! Criterion benches of the isotropic spherical decomposition (ids as in issue 11):
//! filtering 10,000 rotated kernels against a pre-convolved signal by ISD (6) versus
//! the same values by Wigner D rotation of the kernel's SH coefficients and a dot
//! product.

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use psh::geometry::rotation_from_rotvec;
use psh::isd::sh_rotate_dot;
use psh::isd::{DirectionSet, Isd, Pattern, PreConvolved, Profile, Sharing};
use psh::random::pseudo_random;
use psh::sh::num_coeffs;

const ROTATIONS: usize = 10_000;
const LMAX: [usize; 3] = [8, 16, 31];

fn rotations() -> Vec<nalgebra::Rotation3<f64>> {
    pseudo_random(3 * ROTATIONS, 3)
        .chunks_exact(3)
        .map(|v| rotation_from_rotvec([3.0 * v[0], 3.0 * v[1], 3.0 * v[2]]).unwrap())
        .collect()
}

/// ISD (6): RZH on shared Fibonacci directions, 10,000 rotations.
fn isd_filter(c: &mut Criterion) {
    let mut g = c.benchmark_group("isd/filter");
    g.sample_size(10);
    let rots = rotations();
    for lmax in LMAX {
        let dirs = DirectionSet::from_pattern(Pattern::Fibonacci, Sharing::Shared, lmax).unwrap();
        let isd = Isd::new(Profile::Zonal, dirs).unwrap();
        let n = num_coeffs(lmax);
        let lambda = isd.weights(&pseudo_random(n, 1)).unwrap();
        let pre = PreConvolved::new(&isd, &pseudo_random(n, 2)).unwrap();
        g.bench_with_input(BenchmarkId::from_parameter(lmax), &lmax, |b, _| {
            b.iter(|| pre.filter(&isd, black_box(&lambda), &rots).unwrap())
        });
    }
    g.finish();
}

/// The same values by real Wigner D rotation and dot product, 10,000 rotations.
fn sh_rotate(c: &mut Criterion) {
    let mut g = c.benchmark_group("sh_rotate_dot");
    g.sample_size(10);
    let rots = rotations();
    for lmax in LMAX {
        let n = num_coeffs(lmax);
        let (k, f) = (pseudo_random(n, 1), pseudo_random(n, 2));
        g.bench_with_input(BenchmarkId::from_parameter(lmax), &lmax, |b, _| {
            b.iter(|| sh_rotate_dot(black_box(&k), &f, &rots).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, isd_filter, sh_rotate);
criterion_main!(benches);
