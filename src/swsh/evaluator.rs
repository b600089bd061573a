//! [`SpinEvaluator`]: the spin-`s` harmonics `sY_lm` at any direction from the recursion of
//! `swsh::recursion`, `O(lmax^2)` per direction.

use crate::error::{check_len, Error, Result};
use crate::sh::recursion::lambda::{Columns, HalfAngle};
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
            return Err(Error::invalid(
                "spin",
                spin.to_string(),
                format!(
                    "the spin recursion needs 1 <= |spin| <= lmax = {lmax} (spin 0: scalar SH)"
                ),
            ));
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
    /// with `lambda[l - l0] = Lambda_lm(theta)`, `l0 = max(|m|, |s|)`, `|m|` increasing.
    ///
    /// Southern angles are evaluated at `pi - theta` through
    /// `Lambda_lm(theta) = (-1)^{l+s} Lambda_{l,-m}(pi - theta)` (`proofs/swsh.md`), whose half
    /// angles are those of `theta` swapped (no rounding). The order `m = -s` of the
    /// northern angle, the one whose `d^l_{-s,-s}` tends to 1 at the pole, comes from the
    /// difference form of [`diagonal_column`] instead of the three-term recursion, which
    /// loses `u = 1 - cos theta` below `eps` (`proofs/swsh.md`, "The diagonal order near
    /// the poles").
    pub(crate) fn for_each_order(&self, theta: f64, mut f: impl FnMut(i64, usize, &[f64])) {
        let spin = self.spin();
        let north = HalfAngle::from_theta(theta);
        let south = theta > std::f64::consts::FRAC_PI_2;
        let half = if south { north.mirrored() } else { north };
        let mut scratch = Vec::new();
        let mut diagonal = Vec::new();
        let mut flipped = Vec::new();
        self.columns.for_each_column_lanes(
            &[half],
            0..self.columns.list.len(),
            |_| true,
            &mut scratch,
            |m, l0, col| {
                let mut lambda = col.as_flattened();
                if m == -spin {
                    diagonal_column(spin, self.lmax(), half, &mut diagonal);
                    lambda = &diagonal;
                }
                if !south {
                    return f(m, l0, lambda);
                }
                // (-1)^{l+s} with l = l0 + k.
                let first = if (l0 as i64 + spin) % 2 == 0 {
                    1.0
                } else {
                    -1.0
                };
                flipped.clear();
                flipped.extend(lambda.iter().enumerate().map(|(k, &x)| {
                    if k % 2 == 0 {
                        first * x
                    } else {
                        -first * x
                    }
                }));
                f(-m, l0, &flipped)
            },
        );
    }

    /// `sY_lm(theta, phi)` for all `l <= lmax` in flat order (zeros where `l < |s|`), into
    /// `out` of length `(lmax+1)^2`: `O(lmax^2)`, against `O(lmax^3)` for [`crate::swsh::swsh`].
    pub fn values(&self, theta: f64, phi: f64, out: &mut [Complex64]) -> Result<()> {
        crate::geometry::check_theta(theta)?;
        crate::error::finite("phi", phi)?;
        check_len("spin SH output", num_coeffs(self.lmax()), out.len())?;
        out.fill(Complex64::default());
        let mut cis = crate::sh::evaluation::harmonics::CisWalk::new(phi);
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

/// Buffers of [`SpinEvaluator::lambda_lanes`], kept between calls.
#[derive(Clone, Debug, Default)]
pub(crate) struct LanesScratch {
    column: Vec<[f64; 4]>,
    diagonal: Vec<f64>,
}

impl SpinEvaluator {
    /// `Lambda_lm(theta_k)` at four polar angles (in `[0, pi]`, unchecked), into
    /// `out[lm_index(l, m)][k]` (zero where `l < |s|`): what [`Self::for_each_order`]
    /// gives one angle at a time (southern angles mirrored, the order `m = -s` by the
    /// difference form), with the recursion run for the four in lanes.
    pub(crate) fn lambda_lanes(
        &self,
        theta: [f64; 4],
        scratch: &mut LanesScratch,
        out: &mut [[f64; 4]],
    ) {
        let spin = self.spin();
        let lmax = self.lmax();
        let south = theta.map(|t| t > std::f64::consts::FRAC_PI_2);
        let half: [HalfAngle; 4] = std::array::from_fn(|k| {
            let north = HalfAngle::from_theta(theta[k]);
            if south[k] {
                north.mirrored()
            } else {
                north
            }
        });
        // A southern angle's order m is the mirrored angle's -m times (-1)^{l+s}.
        let place = |k: usize, m: i64, l: usize| {
            let flip = south[k] && (l as i64 + spin) % 2 != 0;
            let at = lm_index(l, if south[k] { -m } else { m });
            (at, if flip { -1.0 } else { 1.0 })
        };
        out.fill([0.0; 4]);
        let LanesScratch { column, diagonal } = scratch;
        self.columns.for_each_column_lanes(
            &half,
            0..self.columns.list.len(),
            |m| m != -spin,
            column,
            |m, l0, col| {
                for (i, c) in col.iter().enumerate() {
                    for (k, &x) in c.iter().enumerate() {
                        let (at, sign) = place(k, m, l0 + i);
                        out[at][k] = sign * x;
                    }
                }
            },
        );
        let l0 = spin.unsigned_abs() as usize;
        for (k, &h) in half.iter().enumerate() {
            diagonal_column(spin, lmax, h, diagonal);
            for (i, &x) in diagonal.iter().enumerate() {
                let (at, sign) = place(k, -spin, l0 + i);
                out[at][k] = sign * x;
            }
        }
    }
}

/// `Lambda_{l,-s}(theta) = (-1)^s sqrt((2l+1)/(4 pi)) d^l_{-s,-s}(theta)`, `l = |s|..=lmax`,
/// into `out`, by the recursion of [`crate::sh::recursion::lambda`] at `m = m' = -s` in its
/// difference form (`proofs/swsh.md`, "The diagonal order near the poles"): with
/// `A_l = l (2l-1) / (l^2 - s^2)`, `B_l = ((l-1)^2 - s^2) / ((l-1)(2l-1))` and
/// `A_l (c_l - B_l) = 1`, `delta_l = A_l B_l delta_{l-1} - A_l u d_{l-1}`,
/// `d_l = d_{l-1} + delta_l`, from `d_{|s|} = cos^{2|s|}(theta/2)`, `delta_{|s|} = 0`.
fn diagonal_column(spin: i64, lmax: usize, half: HalfAngle, out: &mut Vec<f64>) {
    let s = spin.unsigned_abs() as usize;
    let s2 = (s * s) as f64;
    let u = half.u();
    let sign = if s.is_multiple_of(2) { 1.0 } else { -1.0 };
    let norm = |l: usize| sign * ((2 * l + 1) as f64 / (4.0 * std::f64::consts::PI)).sqrt();
    let mut d = half.cos().powi(2 * s as i32);
    let mut delta = 0.0;
    out.clear();
    out.push(norm(s) * d);
    for l in s + 1..=lmax {
        let lf = l as f64;
        let a = lf * (2.0 * lf - 1.0) / (lf * lf - s2);
        let ab = if l == s + 1 {
            0.0
        } else {
            let p = lf - 1.0;
            a * (p * p - s2) / (p * (2.0 * lf - 1.0))
        };
        delta = ab * delta - a * u * d;
        d += delta;
        out.push(norm(l) * d);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::swsh::swsh;

    /// The `O(l^2)` evaluator meets `10 l eps` of `sqrt((2l+1)/(4 pi))` at the poles and
    /// next to them against Risbo's recursion ([`swsh`], checked against `spherical` at
    /// the poles in the validation suite). Before the mirrored angles and the diagonal
    /// order's difference form it was 6e-12 off at `l = 500` for `m = +-s`.
    #[test]
    fn evaluator_meets_ten_l_eps_at_the_poles() {
        let lmax = 300;
        let mut out = vec![Complex64::default(); num_coeffs(lmax)];
        for spin in [-3i64, -2, 1, 2, 3] {
            let ev = SpinEvaluator::new(spin, lmax).unwrap();
            for t in crate::sh::evaluation::harmonics::tests::EDGE_THETAS {
                ev.values(t, 0.4, &mut out).unwrap();
                let want = swsh(spin, lmax, t, 0.4).unwrap();
                for l in 0..=lmax {
                    let bound = 10.0
                        * l.max(1) as f64
                        * f64::EPSILON
                        * ((2 * l + 1) as f64 / (4.0 * std::f64::consts::PI)).sqrt();
                    for i in l * l..(l + 1) * (l + 1) {
                        let e = (out[i] - want[i]).norm();
                        assert!(e <= bound, "spin {spin} theta {t} l {l} index {i}: {e:e}");
                    }
                }
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
}
