//! Spin-s transforms on the exact grid: synthesis `f = sum a_lm sY_lm` and analysis
//! `a_lm = <sY_lm, f>` (PSH (32) for one spin component), with
//! `sY_lm = Lambda_lm(theta) e^{i m phi}`, `Lambda_lm = (-1)^s sqrt((2l+1)/(4 pi)) d^l_{m,-s}`,
//! on the order-major sweeps of `crate::sh::transform::sweeps` (the code path of the
//! scalar transforms, at spin `s`).

use super::evaluator::SpinEvaluator;
use crate::error::{check_len, finite_complex, Result};
use crate::sh::num_coeffs;
use crate::sh::transform::grid::SphereGrid;
use crate::sh::transform::sweeps::OrderTransform;
use num_complex::Complex64;

/// A planned spin-`s` transform pair for band limit `lmax`.
pub struct SpinTransform {
    eval: SpinEvaluator,
    sweeps: OrderTransform,
}

impl std::fmt::Debug for SpinTransform {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SpinTransform")
            .field("spin", &self.spin())
            .field("lmax", &self.eval.lmax())
            .finish()
    }
}

impl SpinTransform {
    /// Spin-`s` transform for band limit `lmax` on the smallest exact grid.
    pub fn new(spin: i64, lmax: usize) -> Result<Self> {
        Self::with_grid(spin, lmax, SphereGrid::for_band_limit(lmax)?)
    }

    /// Spin-`s` transform on a given grid (checked to resolve `lmax`). `1 <= |s| <= lmax`
    /// (spin 0 is the scalar transform of [`crate::sh::ShTransform`]).
    pub fn with_grid(spin: i64, lmax: usize, grid: SphereGrid) -> Result<Self> {
        crate::sh::check_lmax(lmax)?;
        grid.check_band_limit(lmax)?;
        crate::sh::transform::sweeps::check_tables(lmax, &grid)?;
        let eval = SpinEvaluator::new(spin, lmax)?;
        Ok(Self {
            sweeps: OrderTransform::new(eval.columns.clone(), grid)?,
            eval,
        })
    }

    /// The grid (values ring-major).
    pub fn grid(&self) -> &SphereGrid {
        self.sweeps.grid()
    }

    /// The spin weight.
    pub fn spin(&self) -> i64 {
        self.eval.spin()
    }

    /// The evaluator of the harmonics.
    pub fn evaluator(&self) -> &SpinEvaluator {
        &self.eval
    }

    /// Synthesis: `f(theta_j, phi_k) = sum_{l >= |s|, m} a_lm sY_lm` onto the grid; entries
    /// of `coeffs` with `l < |s|` are ignored.
    pub fn synthesis(&self, coeffs: &[Complex64], out: &mut [Complex64]) -> Result<()> {
        check_len("coefficients", num_coeffs(self.eval.lmax()), coeffs.len())?;
        check_len("grid values", self.grid().len(), out.len())?;
        finite_complex("spin SH coefficient", coeffs)?;
        self.sweeps.synthesis(coeffs, out);
        Ok(())
    }

    /// Analysis: `a_lm = <sY_lm, f>` by the exact rule; zeros where `l < |s|`. Each
    /// coefficient is summed by one task in a fixed order, so the result does not depend on
    /// the thread count.
    pub fn analysis(&self, values: &[Complex64], out: &mut [Complex64]) -> Result<()> {
        check_len("grid values", self.grid().len(), values.len())?;
        check_len("coefficients", num_coeffs(self.eval.lmax()), out.len())?;
        finite_complex("grid value", values)?;
        self.sweeps.analysis(values, out);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::lm_index;
    use crate::swsh::swsh;

    #[test]
    fn synthesis_matches_pointwise_swsh() {
        for spin in [2i64, -2, 1, 3] {
            let lmax = 9;
            let t = SpinTransform::new(spin, lmax).unwrap();
            let re = crate::random::pseudo_random(num_coeffs(lmax), 3);
            let im = crate::random::pseudo_random(num_coeffs(lmax), 4);
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
            let re = crate::random::pseudo_random(num_coeffs(lmax), 5);
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

    /// The mirror relation `Lambda_lm(pi - theta) = (-1)^{l+s} Lambda_{l,-m}(theta)` that
    /// pairs the rings (proofs/swsh.md), on Risbo's values.
    #[test]
    fn mirror_rings_swap_orders() {
        let lmax = 12;
        for spin in [1i64, 2, -2, 3] {
            for theta in [0.0, 0.3, 1.2, std::f64::consts::FRAC_PI_2] {
                let north = swsh(spin, lmax, theta, 0.0).unwrap();
                let south = swsh(spin, lmax, std::f64::consts::PI - theta, 0.0).unwrap();
                for l in spin.unsigned_abs() as usize..=lmax {
                    let sign = if (l as i64 + spin) % 2 == 0 {
                        1.0
                    } else {
                        -1.0
                    };
                    for m in -(l as i64)..=l as i64 {
                        let (a, b) = (south[lm_index(l, m)], north[lm_index(l, -m)] * sign);
                        assert!((a - b).norm() < 1e-14, "spin {spin} l {l} m {m}");
                    }
                }
            }
        }
    }

    /// Every coefficient and ring value is summed by one task in a fixed order.
    #[test]
    fn results_do_not_depend_on_the_thread_count() {
        let lmax = 40;
        let t = SpinTransform::new(2, lmax).unwrap();
        let re = crate::random::pseudo_random(num_coeffs(lmax), 8);
        let c: Vec<Complex64> = re.iter().map(|&a| Complex64::new(a, -0.3 * a)).collect();
        let run = |threads: usize| {
            crate::testing::on_threads(threads, || {
                let mut f = vec![Complex64::default(); t.grid().len()];
                t.synthesis(&c, &mut f).unwrap();
                let mut back = vec![Complex64::default(); c.len()];
                t.analysis(&f, &mut back).unwrap();
                (f, back)
            })
        };
        assert_eq!(run(1), run(3));
    }

    #[test]
    fn bad_spins_are_errors() {
        assert!(SpinTransform::new(0, 4).is_err());
        assert!(SpinTransform::new(5, 4).is_err());
    }

    #[test]
    fn non_finite_inputs_are_errors_naming_the_value() {
        let t = SpinTransform::new(2, 4).unwrap();
        let mut c = vec![Complex64::default(); num_coeffs(4)];
        let mut f = vec![Complex64::default(); t.grid().len()];
        c[9] = Complex64::new(f64::NAN, 0.0);
        let e = t.synthesis(&c, &mut f).unwrap_err().to_string();
        assert!(
            e.contains("spin SH coefficient") && e.contains("NaN"),
            "{e}"
        );
        f[3] = Complex64::new(0.0, f64::INFINITY);
        let e = t.analysis(&f, &mut c).unwrap_err().to_string();
        assert!(e.contains("grid value") && e.contains("inf"), "{e}");
    }
}
