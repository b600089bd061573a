//! Spherical harmonic transforms on the exact grid ([`SphereGrid`]): synthesis PSH (2)
//! and analysis PSH (3), for complex and real coefficients.
//!
//! Both factor into a Legendre sum per ring and an FFT per ring (rustfft):
//! synthesis `f(theta_j, phi_k) = sum_m e^{i m phi_k} sum_l f_lm Pbar_lm(theta_j)`,
//! analysis `f_lm = sum_j w_j (2 pi / n_phi) Pbar_lm(theta_j) sum_k f(theta_j, phi_k) e^{-i m phi_k}`,
//! exact for band-limited input on a grid that resolves the band limit (see
//! [`crate::sh::transform::grid`]). They run on the order-major sweeps of [`crate::sh::transform::sweeps`] at
//! spin 0 (`Pbar_lm = Lambda_lm`, the code path of the spin transforms); real fields use
//! the orders `m >= 0` alone and pack the two rings of a mirror pair into one complex FFT.

use crate::error::{check_len, finite_all, finite_complex, Result};
use crate::sh::index::{lm_index, num_coeffs};
use crate::sh::recursion::lambda::Columns;
use crate::sh::transform::grid::SphereGrid;
use crate::sh::transform::sweeps::OrderTransform;
use num_complex::Complex64;
use std::f64::consts::{FRAC_1_SQRT_2, SQRT_2};
use std::sync::Arc;

/// A planned transform pair for band limit `lmax` on a grid.
pub struct ShTransform {
    sweeps: OrderTransform,
}

impl std::fmt::Debug for ShTransform {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ShTransform")
            .field("lmax", &self.lmax())
            .field("n_theta", &self.grid().rings.len())
            .field("n_phi", &self.grid().n_phi)
            .finish()
    }
}

impl ShTransform {
    /// Transform for band limit `lmax` on the smallest exact grid
    /// ([`SphereGrid::for_band_limit`]).
    pub fn new(lmax: usize) -> Result<Self> {
        Self::with_grid(lmax, SphereGrid::for_band_limit(lmax)?)
    }

    /// Transform for band limit `lmax` on a given grid (checked to resolve it).
    pub fn with_grid(lmax: usize, grid: SphereGrid) -> Result<Self> {
        crate::sh::check_lmax(lmax)?;
        grid.check_band_limit(lmax)?;
        crate::sh::transform::sweeps::check_tables(lmax, &grid)?;
        Ok(Self {
            sweeps: OrderTransform::new(Arc::new(Columns::new(0, lmax)), grid)?,
        })
    }

    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.sweeps.lmax()
    }

    /// The grid (values are ring-major, index `j * n_phi + k`).
    pub fn grid(&self) -> &SphereGrid {
        self.sweeps.grid()
    }

    /// Synthesis PSH (2) of complex coefficients (flat order) onto the grid.
    pub fn synthesis_complex(&self, coeffs: &[Complex64], out: &mut [Complex64]) -> Result<()> {
        check_len("coefficients", num_coeffs(self.lmax()), coeffs.len())?;
        finite_complex("SH coefficient", coeffs)?;
        check_len("grid values", self.grid().len(), out.len())?;
        self.sweeps.synthesis(coeffs, out);
        Ok(())
    }

    /// Analysis PSH (3) of complex grid values into coefficients (flat order).
    pub fn analysis_complex(&self, values: &[Complex64], out: &mut [Complex64]) -> Result<()> {
        check_len("grid values", self.grid().len(), values.len())?;
        finite_complex("grid value", values)?;
        check_len("coefficients", num_coeffs(self.lmax()), out.len())?;
        self.sweeps.analysis(values, out);
        Ok(())
    }

    /// Synthesis PSH (2) of real coefficients (real SH PSH (12)) onto the grid.
    pub fn synthesis_real(&self, coeffs: &[f64], out: &mut [f64]) -> Result<()> {
        check_len("coefficients", num_coeffs(self.lmax()), coeffs.len())?;
        finite_all("SH coefficient", coeffs)?;
        check_len("grid values", self.grid().len(), out.len())?;
        // f = sum_l (c_l0 Pbar_l0 + sum_{m > 0} sqrt(2) Pbar_lm (c_lm cos m phi + c_{l,-m} sin m phi))
        //   = Re sum_{m >= 0} eps_m e^{i m phi} sum_l a_lm Pbar_lm, a_lm = (c_lm - i c_{l,-m}) / sqrt(2).
        self.sweeps.synthesis_real(
            |l, m| {
                let m = m as i64;
                if m == 0 {
                    Complex64::new(coeffs[lm_index(l, 0)], 0.0)
                } else {
                    FRAC_1_SQRT_2 * Complex64::new(coeffs[lm_index(l, m)], -coeffs[lm_index(l, -m)])
                }
            },
            out,
        );
        Ok(())
    }

    /// Analysis PSH (3) of a real field into real coefficients (real SH PSH (12)).
    pub fn analysis_real(&self, values: &[f64], out: &mut [f64]) -> Result<()> {
        check_len("grid values", self.grid().len(), values.len())?;
        finite_all("grid value", values)?;
        check_len("coefficients", num_coeffs(self.lmax()), out.len())?;
        // a_lm = <Pbar_lm e^{i m phi}, f>: its real part gives the cosine coefficient, minus
        // its imaginary part the sine one (int f sin(m phi)), both times sqrt(2) for m > 0.
        self.sweeps.analysis_real(values, |l, m, a| {
            let m = m as i64;
            if m == 0 {
                out[lm_index(l, 0)] = a.re;
            } else {
                out[lm_index(l, m)] = SQRT_2 * a.re;
                out[lm_index(l, -m)] = -SQRT_2 * a.im;
            }
        });
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::evaluation::harmonics::ShEvaluator;

    use crate::random::pseudo_random;

    #[test]
    fn real_synthesis_matches_pointwise_evaluation() {
        let lmax = 9;
        let t = ShTransform::new(lmax).unwrap();
        let c = pseudo_random(num_coeffs(lmax), 3);
        let mut f = vec![0.0; t.grid().len()];
        t.synthesis_real(&c, &mut f).unwrap();
        let ev = ShEvaluator::new(lmax).unwrap();
        let mut y = vec![0.0; ev.len()];
        for i in 0..t.grid().len() {
            let (th, ph) = t.grid().angles(i).unwrap();
            ev.real(th, ph, &mut y).unwrap();
            let v: f64 = y.iter().zip(&c).map(|(a, b)| a * b).sum();
            assert!((v - f[i]).abs() < 1e-13, "point {i}: {v} vs {}", f[i]);
        }
    }

    #[test]
    fn complex_synthesis_matches_pointwise_evaluation() {
        let lmax = 8;
        let t = ShTransform::with_grid(lmax, SphereGrid::new(10, 19).unwrap()).unwrap();
        let re = pseudo_random(num_coeffs(lmax), 5);
        let im = pseudo_random(num_coeffs(lmax), 6);
        let c: Vec<Complex64> = re
            .iter()
            .zip(&im)
            .map(|(&a, &b)| Complex64::new(a, b))
            .collect();
        let mut f = vec![Complex64::default(); t.grid().len()];
        t.synthesis_complex(&c, &mut f).unwrap();
        let ev = ShEvaluator::new(lmax).unwrap();
        let mut y = vec![Complex64::default(); ev.len()];
        for i in 0..t.grid().len() {
            let (th, ph) = t.grid().angles(i).unwrap();
            ev.complex(th, ph, &mut y).unwrap();
            let v: Complex64 = y.iter().zip(&c).map(|(a, b)| a * b).sum();
            assert!((v - f[i]).norm() < 1e-13, "point {i}");
        }
    }

    #[test]
    fn round_trips_are_exact_on_band_limited_input() {
        for lmax in [0usize, 1, 2, 7, 32] {
            let t = ShTransform::new(lmax).unwrap();
            let c = pseudo_random(num_coeffs(lmax), 11 + lmax as u64);
            let mut f = vec![0.0; t.grid().len()];
            t.synthesis_real(&c, &mut f).unwrap();
            let mut back = vec![0.0; c.len()];
            t.analysis_real(&f, &mut back).unwrap();
            for (a, b) in c.iter().zip(&back) {
                assert!((a - b).abs() < 1e-13, "lmax {lmax}: {a} vs {b}");
            }
            let cc: Vec<Complex64> = c.iter().map(|&x| Complex64::new(x, -0.5 * x)).collect();
            let mut fc = vec![Complex64::default(); t.grid().len()];
            t.synthesis_complex(&cc, &mut fc).unwrap();
            let mut backc = vec![Complex64::default(); cc.len()];
            t.analysis_complex(&fc, &mut backc).unwrap();
            for (a, b) in cc.iter().zip(&backc) {
                assert!((a - b).norm() < 1e-13, "lmax {lmax} complex");
            }
        }
    }

    /// Orders, ring pairs and FFTs run in parallel, each value summed by one task: the
    /// same bits on one thread and on three.
    #[test]
    fn results_do_not_depend_on_the_thread_count() {
        let lmax = 40;
        let t = ShTransform::new(lmax).unwrap();
        let c = pseudo_random(num_coeffs(lmax), 12);
        let run = |threads: usize| {
            crate::testing::on_threads(threads, || {
                let mut f = vec![0.0; t.grid().len()];
                t.synthesis_real(&c, &mut f).unwrap();
                let mut back = vec![0.0; c.len()];
                t.analysis_real(&f, &mut back).unwrap();
                let z: Vec<Complex64> = f.iter().map(|&x| Complex64::new(x, 0.5 * x)).collect();
                let mut a = vec![Complex64::default(); c.len()];
                t.analysis_complex(&z, &mut a).unwrap();
                (f, back, a)
            })
        };
        assert_eq!(run(1), run(3));
    }

    #[test]
    fn mismatched_lengths_are_errors() {
        let t = ShTransform::new(3).unwrap();
        let mut f = vec![0.0; t.grid().len()];
        assert!(t.synthesis_real(&[0.0; 3], &mut f).is_err());
        assert!(ShTransform::with_grid(5, SphereGrid::new(3, 20).unwrap()).is_err());
    }

    #[test]
    fn non_finite_inputs_are_errors_naming_the_value() {
        let t = ShTransform::new(3).unwrap();
        let (n, g) = (num_coeffs(3), t.grid().len());
        let mut c = vec![0.0; n];
        let mut f = vec![0.0; g];
        c[5] = f64::NAN;
        let e = t.synthesis_real(&c, &mut f).unwrap_err().to_string();
        assert!(e.contains("SH coefficient") && e.contains("NaN"), "{e}");
        f[7] = f64::INFINITY;
        assert!(t.analysis_real(&f, &mut c).is_err());
        let mut z = vec![Complex64::default(); g];
        z[2] = Complex64::new(0.0, f64::NAN);
        let mut a = vec![Complex64::default(); n];
        assert!(t.analysis_complex(&z, &mut a).is_err());
        a[1] = Complex64::new(f64::NEG_INFINITY, 0.0);
        assert!(t.synthesis_complex(&a, &mut z).is_err());
    }
}
