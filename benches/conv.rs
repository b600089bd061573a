//! Criterion benches of the polarized spherical convolution (ids as in the issue tracker).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use psh::polarized::{kernel_coefficients, Codomain, ConvolutionKernel};
use psh::testing::random_psh;

/// PSH (68): kernel coefficients of l < 100 by 1D quadrature; PSH (69): convolution of an
/// RGB {s0..s3} vector of l < 100.
fn conv(c: &mut Criterion) {
    let lmax = 99;
    let kernel = ConvolutionKernel::linear_zenith();
    let mut grp = c.benchmark_group("conv");
    grp.bench_function("kernel_coeffs/100", |b| {
        b.iter(|| kernel_coefficients(black_box(&kernel), lmax).unwrap())
    });
    let k = kernel_coefficients(&kernel, lmax).unwrap();
    let f = random_psh(lmax, Codomain::Full, 3, 7).unwrap();
    grp.bench_function("apply/100", |b| {
        b.iter(|| k.convolve(black_box(&f)).unwrap())
    });
    grp.finish();
}

criterion_group!(benches, conv);
criterion_main!(benches);
