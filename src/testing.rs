//! Random inputs for tests, benches and `psh verify`: coefficient vectors and matrices on
//! the index set PSH (31), kernels and directions, all from the crate's one generator
//! ([`crate::random`]). Library code never imports this module.

use crate::error::Result;
use crate::polarized::{in_index_set, Codomain, PshMatrix, PshVector};
use crate::random::pseudo_random;
use crate::sh::num_coeffs;

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

/// The rotation vector of the turn by `t` about the axis at polar angle `tilt`, azimuth
/// `phi`.
pub fn axis_angle(tilt: f64, phi: f64, t: f64) -> [f64; 3] {
    let k = crate::geometry::direction(tilt, phi);
    [t * k[0], t * k[1], t * k[2]]
}

/// Rotations at the edges of the Euler angles, as `(tilt, phi, t)` of [`axis_angle`]:
/// tiny turns about axes near z, tilted and horizontal, turns near a half turn, a half
/// turn about an axis next to z, a generic small one.
pub const EDGE_ROTATIONS: [(f64, f64, f64); 10] = [
    (1e-3, 0.4, 1e-12),
    (1e-2, -2.0, 1e-8),
    (1e-6, 1.0, 1e-5),
    (1.2, 0.3, 1e-10),
    (std::f64::consts::FRAC_PI_2, 0.7, 1e-9),
    (0.3, 0.1, 1e-15),
    (0.3, 0.1, std::f64::consts::PI - 1e-12),
    (
        std::f64::consts::FRAC_PI_2,
        -1.3,
        std::f64::consts::PI - 1e-9,
    ),
    (1e-9, 2.5, std::f64::consts::PI),
    (0.7, -0.2, 1e-2),
];

/// Largest error, in units of `eps`, of `D^1` of the [`EDGE_ROTATIONS`], of a turn of
/// 1e-8 about an axis 1e-2 from z, of a turn of 1e-300 and of the identity against the
/// Cayley-Klein form (`proofs/euler-angles.md`): with the unit quaternion `(w, x, y, z)`
/// taken from the rotation vector directly and `a = w - i z`, `b = y + i x`,
/// `D^1 = [[a^2, -sqrt2 a b, b^2], [sqrt2 a b*, |a|^2 - |b|^2, -sqrt2 a* b],
/// [b*^2, sqrt2 a* b*, a*^2]]` (rows and columns `m = 1, 0, -1`).
pub fn cayley_klein_error() -> Result<f64> {
    use num_complex::Complex64;
    let mut cases: Vec<[f64; 3]> = EDGE_ROTATIONS
        .iter()
        .map(|&(tilt, phi, t)| axis_angle(tilt, phi, t))
        .collect();
    cases.extend([[1e-10, 0.0, 1e-8], [1e-300, 0.0, 0.0], [0.0; 3]]);
    let mut worst = 0.0f64;
    for v in cases {
        let t = v[0].hypot(v[1]).hypot(v[2]);
        let (s, w) = (0.5 * t).sin_cos();
        let [x, y, z] = if t == 0.0 {
            [0.0; 3]
        } else {
            v.map(|c| s * (c / t))
        };
        let (a, b) = (Complex64::new(w, -z), Complex64::new(y, x));
        let r2 = std::f64::consts::SQRT_2;
        let want = [
            a * a,
            -r2 * a * b,
            b * b,
            r2 * a * b.conj(),
            Complex64::from(a.norm_sqr() - b.norm_sqr()),
            -r2 * a.conj() * b,
            b.conj() * b.conj(),
            r2 * a.conj() * b.conj(),
            a.conj() * a.conj(),
        ];
        let r = if t == 0.0 {
            nalgebra::Rotation3::identity()
        } else {
            crate::geometry::rotation_from_rotvec(v)?
        };
        let d = crate::sh::WignerD::new(&r, 1)?;
        // psh's rows and columns run m = -1, 0, 1: entry i of `want` is 8 - i.
        let got = d.block(1)?;
        for (i, w) in want.iter().enumerate() {
            worst = worst.max((got[8 - i] - w).norm() / f64::EPSILON);
        }
    }
    Ok(worst)
}

/// Largest error, in units of `l eps`, of `D^l` of the [`EDGE_ROTATIONS`] (built from
/// their vectors, and as the product of their factors' matrices, whose entries are off by
/// ~eps) against the product of the blocks of `Rz(phi) Ry(tilt) Rz(t) Ry(-tilt) Rz(-phi)`:
/// each factor has exact Euler angles, so this is a route to `D^l` that never meets the
/// ill-determined angles of a small tilt (`proofs/euler-angles.md`).
pub fn factorization_error(l: usize) -> Result<f64> {
    use nalgebra::{Rotation3, Vector3};
    use num_complex::Complex64;
    let n = 2 * l + 1;
    let product = |a: &[Complex64], b: &[Complex64]| -> Vec<Complex64> {
        let mut out = vec![Complex64::default(); n * n];
        for (row, a_row) in out.chunks_exact_mut(n).zip(a.chunks_exact(n)) {
            for (&x, b_row) in a_row.iter().zip(b.chunks_exact(n)) {
                for (o, &y) in row.iter_mut().zip(b_row) {
                    *o += x * y;
                }
            }
        }
        out
    };
    let block = |r: &Rotation3<f64>| -> Result<Vec<Complex64>> {
        Ok(crate::sh::WignerD::new(r, l)?.block(l)?.to_vec())
    };
    let z = |a: f64| Rotation3::from_axis_angle(&Vector3::z_axis(), a);
    let y = |a: f64| Rotation3::from_axis_angle(&Vector3::y_axis(), a);
    let mut worst = 0.0f64;
    for &(tilt, phi, t) in &EDGE_ROTATIONS {
        let factors = [z(phi), y(tilt), z(t), y(-tilt), z(-phi)];
        let mut want = block(&factors[0])?;
        for f in &factors[1..] {
            want = product(&want, &block(f)?);
        }
        let from_vector = crate::geometry::rotation_from_rotvec(axis_angle(tilt, phi, t))?;
        let from_product = factors.iter().fold(Rotation3::identity(), |a, f| a * f);
        for r in [from_vector, from_product] {
            for (g, w) in block(&r)?.iter().zip(&want) {
                worst = worst.max((g - w).norm() / (l.max(1) as f64 * f64::EPSILON));
            }
        }
    }
    Ok(worst)
}

/// Largest distance, in units of `eps`, of the Gauss-Legendre polar angles of `n` rings
/// (the 40 next to each pole and 6 at the equator) to the roots of `P_n(cos theta)`:
/// `|P_n(cos theta_j)| / |dP_n/dtheta|` with `P_n` from the double-double path
/// ([`crate::sh::zonal_legendre`], whose error here is below 1e-17 in angle) and
/// `|dP_n/dtheta| = sqrt(2 / w_j)` (`proofs/quadrature.md`).
pub fn gauss_legendre_pole_distance(n: usize) -> Result<f64> {
    let g = crate::sh::GaussLegendre::new(n)?;
    let norm = ((2 * n + 1) as f64 / (4.0 * std::f64::consts::PI)).sqrt();
    let mut worst = 0.0f64;
    for j in (0..40.min(n))
        .chain(n / 2 - 3.min(n / 2)..(n / 2 + 3).min(n))
        .chain(n.saturating_sub(40)..n)
    {
        let p = crate::sh::zonal_legendre(n, g.theta[j])[n] / norm;
        worst = worst.max(p.abs() * (g.weights[j] / 2.0).sqrt() / f64::EPSILON);
    }
    Ok(worst)
}

/// The share `sqrt(sum_{max(l_o, l_i) > l} P^2 / sum P^2)` of a matrix's squared entries
/// above degree `l`: by Parseval (the PSH basis is orthonormal) the band-limit residual of
/// its operator projected to `l` (`proofs/band-limit-residual.md`).
pub fn share_above(m: &PshMatrix, l: usize) -> f64 {
    let n = num_coeffs(m.lmax());
    let (mut all, mut high) = (0.0f64, 0.0f64);
    for jo in 0..n {
        for ji in 0..n {
            for po in 0..4 {
                for pi in 0..4 {
                    let x = m.data()[m.index(jo, ji, po, pi)];
                    all += x * x;
                    if jo.max(ji) >= num_coeffs(l) {
                        high += x * x;
                    }
                }
            }
        }
    }
    (high / all).sqrt()
}
