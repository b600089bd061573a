//! Random inputs for tests, benches and `psh verify`: coefficient vectors and matrices on
//! the index set PSH (31), kernels and directions, all from the crate's one generator
//! ([`crate::random`]). Library code never imports this module.

use crate::error::Result;
use crate::polarized::{in_index_set, Codomain, PshVector};
use crate::random::pseudo_random;

/// `n` deterministic pseudo-random unit directions (polar angle uniform in `[0, pi]`,
/// azimuth in `[-3.2, 3.2)`), from [`pseudo_random`] with `seed`.
pub fn random_directions(n: usize, seed: u64) -> Vec<[f64; 3]> {
    let r = pseudo_random(2 * n, seed);
    (0..n)
        .map(|k| {
            crate::geometry::direction(
                (r[2 * k] + 1.0) * 0.5 * std::f64::consts::PI,
                r[2 * k + 1] * 3.2,
            )
        })
        .collect()
}

/// Random coefficients on the index set PSH (31).
pub fn random_psh(
    lmax: usize,
    codomain: Codomain,
    channels: usize,
    seed: u64,
) -> Result<PshVector> {
    let p = codomain.components().len();
    let mut data = pseudo_random(channels * crate::sh::num_coeffs(lmax) * p, seed);
    for (i, x) in data.iter_mut().enumerate() {
        let lm = (i / p) % crate::sh::num_coeffs(lmax);
        let comp = codomain.components()[i % p];
        if !in_index_set(lm, comp) {
            *x = 0.0;
        }
    }
    PshVector::from_data(lmax, codomain, channels, data)
}

/// Convolution coefficients with random real forms `g_l` (all 16 entries), `l <= lmax`.
pub fn random_kernel(lmax: usize, seed: u64) -> Result<crate::polarized::KernelCoefficients> {
    let r = pseudo_random((lmax + 1) * 16, seed);
    let forms: Vec<crate::polarized::KernelValue> = (0..=lmax)
        .map(|l| std::array::from_fn(|q| std::array::from_fn(|p| r[l * 16 + q * 4 + p])))
        .collect();
    crate::polarized::KernelCoefficients::from_real_form(&forms)
}

/// A random coefficient matrix (full Stokes) on the index set PSH (31).
pub fn random_psh_matrix(lmax: usize, seed: u64) -> Result<crate::polarized::PshMatrix> {
    let n = crate::sh::num_coeffs(lmax);
    let mut data = pseudo_random(n * n * 16, seed);
    for (k, x) in data.iter_mut().enumerate() {
        let (jo, ji, po, pi) = (k / (16 * n), (k / 16) % n, (k / 4) % 4, k % 4);
        if !(in_index_set(jo, po) && in_index_set(ji, pi)) {
            *x = 0.0;
        }
    }
    crate::polarized::PshMatrix::from_data(lmax, data)
}

/// `f()` on a thread pool of `threads` threads: for checks that a result is the same bit
/// for bit on any thread count.
pub fn on_threads<R: Send>(threads: usize, f: impl FnOnce() -> R + Send) -> R {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(f)
}
