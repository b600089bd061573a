//! [`SpinEvaluator`]: the spin-`s` harmonics `sY_lm` at any direction from the recursion of
//! `swsh::recursion`, `O(lmax^2)` per direction.

use crate::error::{check_len, Error, Result};
use crate::sh::column_recursion::{Columns, HalfAngle};
use crate::sh::{lm_index, num_coeffs};
use num_complex::Complex64;
use std::sync::Arc;

/// The recursion tables of the spin-`s` harmonics up to `lmax`: evaluates
/// `Lambda_lm(theta)` for every order at any polar angle, `O(lmax^2)` per angle.
#[derive(Clone, Debug)]
pub struct SpinEvaluator {
    /// Shared with the [`super::SpinTransform`] built on them.
    pub(super) columns: Arc<Columns>,
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
        Ok(Self {
            columns: Arc::new(Columns::new(spin, lmax)),
        })
    }

    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.columns.lmax
    }

    /// The spin weight.
    pub fn spin(&self) -> i64 {
        self.columns.spin
    }

    /// Walks the orders at polar angle `theta` (in `[0, pi]`, unchecked): `f(m, l0, lambda)`
    /// with `lambda[l - l0] = Lambda_lm(theta)`, `l0 = max(|m|, |s|)` (one lane of
    /// [`SpinEvaluator::for_each_order_lanes`]).
    pub(crate) fn for_each_order(&self, theta: f64, mut f: impl FnMut(i64, usize, &[f64])) {
        let mut scratch = Vec::new();
        self.columns.for_each_column_lanes(
            &[HalfAngle::from_theta(theta)],
            0..self.columns.list.len(),
            |_| true,
            &mut scratch,
            |m, l0, col| f(m, l0, col.as_flattened()),
        );
    }

    /// `sY_lm(theta, phi)` for all `l <= lmax` in flat order (zeros where `l < |s|`), into
    /// `out` of length `(lmax+1)^2`: `O(lmax^2)`, against `O(lmax^3)` for [`crate::swsh::swsh`].
    pub fn values(&self, theta: f64, phi: f64, out: &mut [Complex64]) -> Result<()> {
        crate::geometry::check_theta(theta)?;
        crate::error::finite("phi", phi)?;
        check_len("spin SH output", num_coeffs(self.lmax()), out.len())?;
        out.fill(Complex64::default());
        let mut cis = crate::sh::harmonics::CisWalk::new(phi);
        self.for_each_order(theta, |m, l0, lambda| {
            let (c, s) = cis.at(m.unsigned_abs() as usize);
            let e = Complex64::new(c, m.signum() as f64 * s);
            for (k, &v) in lambda.iter().enumerate() {
                out[lm_index(l0 + k, m)] = e * v;
            }
        });
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::swsh::swsh;

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
}
