//! Spin-s transforms on the exact grid: synthesis `f = sum a_lm sY_lm` and analysis
//! `a_lm = <sY_lm, f>` (PSH (32) for one spin component), with
//! `sY_lm = Lambda_lm(theta) e^{i m phi}`, `Lambda_lm = (-1)^s sqrt((2l+1)/(4 pi)) d^l_{m,-s}`.
//!
//! Per ring, `Lambda_lm` for `l = l0..=lmax` (`l0 = max(|m|, |s|)`) comes from the
//! three-term recursion of the Wigner d in `l` at fixed `(m, m')`, in the `u = 1 - cos theta`
//! form of [`crate::sh::legendre`] (derived in `proofs/swsh.md`):
//!
//! `d^l = A_l ((c_l - u) d^{l-1} - B_l d^{l-2})`, `A_l = l (2l-1) / sqrt((l^2-m^2)(l^2-m'^2))`,
//! `B_l = sqrt(((l-1)^2-m^2)((l-1)^2-m'^2)) / ((l-1)(2l-1))`, `c_l = 1 - m m' / (l (l-1))`,
//!
//! started from the one-term closed form of `d^{l0}` (half-angle powers times a square root
//! of a binomial), evaluated through its logarithm with the exponent scaling of the Legendre
//! recursion so that nothing overflows or underflows. The grid is the one of
//! [`crate::sh::grid`]: `d^l_{m,-s} d^l'_{m,-s}` is a polynomial of degree `l + l'` in
//! `cos theta`, so `lmax + 1` rings integrate the analysis exactly.

use crate::error::{check_len, Error, Result};
use crate::sh::grid::SphereGrid;
use crate::sh::legendre::{descale, BIG, SCALE_BITS, SMALL};
use crate::sh::{lm_index, num_coeffs};
use num_complex::Complex64;
use rustfft::{Fft, FftPlanner};
use std::f64::consts::PI;
use std::sync::Arc;

#[derive(Debug)]
/// Recursion data of one order `m`: its start degree, the start's `log2` magnitude parts
/// and sign, and `[A_l, B_l, c_l]` for `l = l0 + 1..=lmax`.
struct Column {
    l0: usize,
    /// `0.5 log2 binom(2 l0, k)`; the start is `sign * 2^log_binom * cos^a(theta/2) sin^b(theta/2)`.
    log_binom: f64,
    a: i32,
    b: i32,
    /// Sign of the start; for the `(-sin)` powers of case (a) it applies to odd `b` only.
    sign: f64,
    coeffs: Vec<[f64; 3]>,
}

/// The recursion tables of the spin-`s` harmonics up to `lmax`: evaluates
/// `Lambda_lm(theta)` for every order at any polar angle, `O(lmax^2)` per angle.
#[derive(Debug)]
pub struct SpinEvaluator {
    spin: i64,
    lmax: usize,
    columns: Vec<Column>,
    /// `(-1)^s sqrt((2l+1)/(4 pi))` for `l <= lmax`.
    norms: Vec<f64>,
}

/// A planned spin-`s` transform pair for band limit `lmax`.
pub struct SpinTransform {
    eval: SpinEvaluator,
    grid: SphereGrid,
    forward: Arc<dyn Fft<f64>>,
    inverse: Arc<dyn Fft<f64>>,
}

impl std::fmt::Debug for SpinTransform {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SpinTransform")
            .field("spin", &self.eval.spin)
            .field("lmax", &self.eval.lmax)
            .finish()
    }
}

impl SpinTransform {
    /// Spin-`s` transform for band limit `lmax` on the smallest exact grid.
    pub fn new(spin: i64, lmax: usize) -> Result<Self> {
        Self::with_grid(spin, lmax, SphereGrid::for_band_limit(lmax)?)
    }

    /// Spin-`s` transform on a given grid (checked to resolve `lmax`). `1 <= |s| <= lmax`
    /// (spin 0 is the scalar transform of [`crate::sh::transform`]).
    pub fn with_grid(spin: i64, lmax: usize, grid: SphereGrid) -> Result<Self> {
        let eval = SpinEvaluator::new(spin, lmax)?;
        grid.check_band_limit(lmax)?;
        let mut planner = FftPlanner::new();
        Ok(Self {
            eval,
            forward: planner.plan_fft_forward(grid.n_phi),
            inverse: planner.plan_fft_inverse(grid.n_phi),
            grid,
        })
    }

    /// The grid (values ring-major).
    pub fn grid(&self) -> &SphereGrid {
        &self.grid
    }

    /// The spin weight.
    pub fn spin(&self) -> i64 {
        self.eval.spin
    }

    /// The evaluator of the harmonics.
    pub fn evaluator(&self) -> &SpinEvaluator {
        &self.eval
    }

    fn bin(&self, m: i64) -> usize {
        m.rem_euclid(self.grid.n_phi as i64) as usize
    }

    /// Synthesis: `f(theta_j, phi_k) = sum_{l >= |s|, m} a_lm sY_lm` onto the grid; entries
    /// of `coeffs` with `l < |s|` are ignored.
    pub fn synthesis(&self, coeffs: &[Complex64], out: &mut [Complex64]) -> Result<()> {
        check_len("coefficients", num_coeffs(self.eval.lmax), coeffs.len())?;
        check_len("grid values", self.grid.len(), out.len())?;
        let np = self.grid.n_phi;
        let mut ring = vec![Complex64::default(); np];
        for j in 0..self.grid.rings.len() {
            ring.fill(Complex64::default());
            self.eval
                .for_each_order(self.grid.rings.theta[j], |m, l0, lambda| {
                    ring[self.bin(m)] = lambda
                        .iter()
                        .enumerate()
                        .map(|(k, &v)| coeffs[lm_index(l0 + k, m)] * v)
                        .sum();
                });
            self.inverse.process(&mut ring);
            out[j * np..(j + 1) * np].copy_from_slice(&ring);
        }
        Ok(())
    }

    /// Analysis: `a_lm = <sY_lm, f>` by the exact rule; zeros where `l < |s|`.
    pub fn analysis(&self, values: &[Complex64], out: &mut [Complex64]) -> Result<()> {
        check_len("grid values", self.grid.len(), values.len())?;
        check_len("coefficients", num_coeffs(self.eval.lmax), out.len())?;
        let np = self.grid.n_phi;
        out.fill(Complex64::default());
        let mut ring = vec![Complex64::default(); np];
        for j in 0..self.grid.rings.len() {
            ring.copy_from_slice(&values[j * np..(j + 1) * np]);
            self.forward.process(&mut ring);
            let w = self.grid.weight(j);
            self.eval
                .for_each_order(self.grid.rings.theta[j], |m, l0, lambda| {
                    let g = ring[self.bin(m)] * w;
                    for (k, &v) in lambda.iter().enumerate() {
                        out[lm_index(l0 + k, m)] += g * v;
                    }
                });
        }
        Ok(())
    }
}

impl SpinEvaluator {
    /// Tables for spin `s`, `1 <= |s| <= lmax` (spin 0: the scalar SH of [`crate::sh`]).
    pub fn new(spin: i64, lmax: usize) -> Result<Self> {
        crate::sh::check_lmax(lmax)?;
        if spin == 0 || spin.unsigned_abs() as usize > lmax {
            return Err(Error::InvalidArgument {
                name: "spin",
                value: spin.to_string(),
                reason: format!(
                    "the spin recursion needs 1 <= |spin| <= lmax = {lmax} (spin 0: scalar SH)"
                ),
            });
        }
        let mp = -spin;
        let columns = (-(lmax as i64)..=lmax as i64)
            .map(|m| column(m, mp, lmax))
            .collect();
        Ok(Self {
            spin,
            lmax,
            columns,
            norms: (0..=lmax)
                .map(|l| {
                    let parity = if spin % 2 == 0 { 1.0 } else { -1.0 };
                    parity * ((2 * l + 1) as f64 / (4.0 * PI)).sqrt()
                })
                .collect(),
        })
    }

    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// Walks the orders at polar angle `theta` (in `[0, pi]`, unchecked): `f(m, l0, lambda)`
    /// with `lambda[l - l0] = Lambda_lm(theta)`, `l0 = max(|m|, |s|)`.
    pub(crate) fn for_each_order(&self, theta: f64, mut f: impl FnMut(i64, usize, &[f64])) {
        let (sh, ch) = (0.5 * theta).sin_cos();
        let (log_c, log_s) = (ch.log2(), sh.log2());
        let u = 2.0 * sh * sh;
        let mut buf = vec![0.0; self.lmax + 1];
        for (i, col) in self.columns.iter().enumerate() {
            let m = i as i64 - self.lmax as i64;
            let out = &mut buf[..=self.lmax - col.l0];
            // Start: sign 2^log_binom cos^a sin^b, as mantissa * 2^exp with exp a multiple
            // of SCALE_BITS (cos, sin of the half angle are exact zero only at the poles).
            let mut log = col.log_binom;
            let mut zero = false;
            for (pow, lg) in [(col.a, log_c), (col.b, log_s)] {
                if pow > 0 {
                    if lg == f64::NEG_INFINITY {
                        zero = true;
                    } else {
                        log += pow as f64 * lg;
                    }
                }
            }
            let (mut p1, mut exp) = if zero {
                (0.0, 0)
            } else {
                let k = ((-log) / SCALE_BITS as f64).ceil().max(0.0) as i32;
                ((log + (k * SCALE_BITS) as f64).exp2(), -k * SCALE_BITS)
            };
            p1 *= col.sign;
            let mut p2 = 0.0;
            let norm = &self.norms[col.l0..];
            out[0] = norm[0] * descale(p1, exp);
            for (k, &[a, b, c]) in col.coeffs.iter().enumerate() {
                let p = a * ((c - u) * p1 - b * p2);
                p2 = p1;
                p1 = p;
                if exp < 0 && p1.abs() > BIG {
                    p1 *= SMALL;
                    p2 *= SMALL;
                    exp += SCALE_BITS;
                }
                out[k + 1] = norm[k + 1] * descale(p1, exp);
            }
            f(m, col.l0, out);
        }
    }

    /// `sY_lm(theta, phi)` for all `l <= lmax` in flat order (zeros where `l < |s|`), into
    /// `out` of length `(lmax+1)^2`: `O(lmax^2)`, against `O(lmax^3)` for [`crate::swsh::swsh`].
    pub fn values(&self, theta: f64, phi: f64, out: &mut [Complex64]) -> Result<()> {
        crate::sh::check_theta(theta)?;
        crate::error::finite("phi", phi)?;
        check_len("spin SH output", num_coeffs(self.lmax), out.len())?;
        out.fill(Complex64::default());
        self.for_each_order(theta, |m, l0, lambda| {
            let (c, s) = crate::sh::harmonics::cis_m(m.unsigned_abs() as usize, phi);
            let e = Complex64::new(c, m.signum() as f64 * s);
            for (k, &v) in lambda.iter().enumerate() {
                out[lm_index(l0 + k, m)] = e * v;
            }
        });
        Ok(())
    }
}

/// `0.5 log2 binom(n, k)`.
fn half_log2_binom(n: usize, k: usize) -> f64 {
    0.5 * (1..=k)
        .map(|i| (((n - k + i) as f64) / i as f64).log2())
        .sum::<f64>()
}

/// Start and recursion coefficients of order `m` for `m' = -s` (closed forms of
/// `d^{l0}_{m m'}` in `proofs/swsh.md`).
fn column(m: i64, mp: i64, lmax: usize) -> Column {
    let j = m.abs().max(mp.abs());
    let l0 = j as usize;
    let (k, a, b, sign) = if m.abs() >= mp.abs() {
        if m >= 0 {
            // d^j_{j,m'} = sqrt(C(2j, j+m')) c^{j+m'} (-s)^{j-m'}
            let b = j - mp;
            (j + mp, j + mp, b, if b % 2 == 0 { 1.0 } else { -1.0 })
        } else {
            // d^j_{-j,m'} = sqrt(C(2j, j-m')) c^{j-m'} s^{j+m'}
            (j - mp, j - mp, j + mp, 1.0)
        }
    } else if mp > 0 {
        // d^j_{m,j} = sqrt(C(2j, j+m)) c^{j+m} s^{j-m}
        (j + m, j + m, j - m, 1.0)
    } else {
        // d^j_{m,-j} = (-1)^{m+j} sqrt(C(2j, j-m)) c^{j-m} s^{j+m}
        let sign = if (m + j) % 2 == 0 { 1.0 } else { -1.0 };
        (j - m, j - m, j + m, sign)
    };
    let (mf, mpf) = (m as f64, mp as f64);
    let coeffs = (l0 + 1..=lmax)
        .map(|l| {
            let lf = l as f64;
            let big_a =
                lf * (2.0 * lf - 1.0) / ((lf * lf - mf * mf) * (lf * lf - mpf * mpf)).sqrt();
            let l1 = lf - 1.0;
            let big_b =
                ((l1 * l1 - mf * mf) * (l1 * l1 - mpf * mpf)).sqrt() / (l1 * (2.0 * lf - 1.0));
            let c = 1.0 - mf * mpf / (lf * l1);
            [big_a, big_b, c]
        })
        .collect();
    Column {
        l0,
        log_binom: half_log2_binom(2 * l0, k as usize),
        a: a as i32,
        b: b as i32,
        sign,
        coeffs,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::swsh::swsh;

    #[test]
    fn synthesis_matches_pointwise_swsh() {
        for spin in [2i64, -2, 1, 3] {
            let lmax = 9;
            let t = SpinTransform::new(spin, lmax).unwrap();
            let re = crate::verify::pseudo_random(num_coeffs(lmax), 3);
            let im = crate::verify::pseudo_random(num_coeffs(lmax), 4);
            let c: Vec<Complex64> = re
                .iter()
                .zip(&im)
                .map(|(&a, &b)| Complex64::new(a, b))
                .collect();
            let mut f = vec![Complex64::default(); t.grid().len()];
            t.synthesis(&c, &mut f).unwrap();
            for i in (0..t.grid().len()).step_by(7) {
                let (th, ph) = t.grid().angles(i).unwrap();
                let y = swsh(spin, lmax, th, ph).unwrap();
                let v: Complex64 = y.iter().zip(&c).map(|(a, b)| a * b).sum();
                let tol = 1e-13 * v.norm().max(1.0);
                assert!(
                    (v - f[i]).norm() < tol,
                    "spin {spin} point {i}: {v} vs {}",
                    f[i]
                );
            }
        }
    }

    #[test]
    fn round_trip_is_exact() {
        for (spin, lmax) in [(2i64, 2usize), (2, 33), (-2, 20), (1, 12)] {
            let t = SpinTransform::new(spin, lmax).unwrap();
            let re = crate::verify::pseudo_random(num_coeffs(lmax), 5);
            let c: Vec<Complex64> = re
                .iter()
                .enumerate()
                .map(|(i, &a)| {
                    let (l, _) = crate::sh::lm_of_index(i);
                    if (l as i64) < spin.abs() {
                        Complex64::default()
                    } else {
                        Complex64::new(a, 0.5 * a)
                    }
                })
                .collect();
            let mut f = vec![Complex64::default(); t.grid().len()];
            t.synthesis(&c, &mut f).unwrap();
            let mut back = vec![Complex64::default(); c.len()];
            t.analysis(&f, &mut back).unwrap();
            for (x, y) in c.iter().zip(&back) {
                assert!((x - y).norm() < 1e-13, "spin {spin} lmax {lmax}");
            }
        }
    }

    #[test]
    fn evaluator_matches_risbo_and_rejects_bad_input() {
        let ev = SpinEvaluator::new(2, 20).unwrap();
        let mut out = vec![Complex64::default(); num_coeffs(20)];
        for (t, p) in [
            (0.0, 0.3),
            (1e-9, 1.0),
            (1.2, -2.0),
            (std::f64::consts::PI, 0.5),
        ] {
            ev.values(t, p, &mut out).unwrap();
            for (a, b) in out.iter().zip(swsh(2, 20, t, p).unwrap()) {
                assert!((a - b).norm() < 1e-13, "theta {t}");
            }
        }
        assert!(ev.values(f64::NAN, 0.0, &mut out).is_err());
        assert!(ev.values(0.1, f64::INFINITY, &mut out).is_err());
        assert!(ev.values(0.1, 0.0, &mut out[..5]).is_err());
    }

    #[test]
    fn bad_spins_are_errors() {
        assert!(SpinTransform::new(0, 4).is_err());
        assert!(SpinTransform::new(5, 4).is_err());
    }
}
