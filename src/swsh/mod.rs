//! Spin-weighted spherical harmonics `sY_lm` (PSH Sec. 6.1).
//!
//! For spin `s` and `|s| <= l`, with the Wigner small d of [`crate::sh::WignerD`]:
//!
//! `sY_lm(theta, phi) = (-1)^s sqrt((2l+1)/(4 pi)) d^l_{m,-s}(theta) e^{i m phi}`
//!
//! (derived in `proofs/swsh.md`). It reduces to `Y_lm` of PSH (1) at `s = 0`
//! (`d^l_{m0} = sqrt((l-m)!/(l+m)!) P_l^m`), equals PSH (26a) at `s = 2` (the
//! components of the spin-2 basis in the theta-phi frame field), and obeys the pole
//! conditions PSH (27): `d^l_{m,-s}(0) = delta_{m,-s}` and
//! `d^l_{m,-s}(pi) = (-1)^{l+m} delta_{m,s}`, so `2Y_lm` is non-zero at the north pole only
//! for `m = -2` and at the south pole only for `m = 2`.
//!
//! The small d come from Risbo's recursion, stable to `l >= 1000` at every angle, poles
//! included; evaluating one direction costs `O(lmax^3)` (all blocks), which is meant for
//! single directions and reference values, not for transforms: those use the recursion in
//! `l` of [`SpinEvaluator`] (`O(lmax^2)` per direction) and [`SpinTransform`] (on the exact
//! grid).

pub(crate) mod evaluator;
pub(crate) mod transform;

pub use evaluator::SpinEvaluator;
pub use transform::SpinTransform;

use crate::error::{finite, Error, Result};
use crate::geometry::check_theta;
use crate::sh::evaluation::harmonics::{cis_m, sh_complex};
use crate::sh::rotation::small_d::SmallDRecursion;
use crate::sh::{check_lmax, lm_index, num_coeffs};
use num_complex::Complex64;
use std::f64::consts::PI;

/// Largest `|s|` accepted (the spins of polarized light are 0 and 2; the formula holds
/// for any integer spin).
pub const MAX_SPIN: i64 = 64;

/// `sY_lm(theta, phi)` for all `l <= lmax`, `|m| <= l`, in flat order `l*l + l + m`, with
/// zeros where `l < |s|` (PSH (26)-(27) for `s = 2`).
pub fn swsh(spin: i64, lmax: usize, theta: f64, phi: f64) -> Result<Vec<Complex64>> {
    if spin.unsigned_abs() > MAX_SPIN as u64 {
        return Err(Error::invalid(
            "spin",
            spin.to_string(),
            format!("|spin| must be at most {MAX_SPIN}"),
        ));
    }
    check_lmax(lmax)?;
    check_theta(theta)?;
    finite("phi", phi)?;
    let mut out = vec![Complex64::default(); num_coeffs(lmax)];
    let phases: Vec<Complex64> = (-(lmax as i64)..=lmax as i64)
        .map(|m| {
            let (c, s) = cis_m(m.unsigned_abs() as usize, phi);
            Complex64::new(c, m.signum() as f64 * s)
        })
        .collect();
    let sign = if spin % 2 == 0 { 1.0 } else { -1.0 };
    let mut rec = SmallDRecursion::new(theta, lmax)?;
    let mut d = Vec::new();
    while let Some(l) = rec.next_block(&mut d) {
        if (l as i64) < spin.abs() {
            continue;
        }
        let n = 2 * l + 1;
        let li = l as i64;
        let col = (-spin + li) as usize;
        let norm = sign * ((2 * l + 1) as f64 / (4.0 * PI)).sqrt();
        for m in -li..=li {
            let dm = d[(m + li) as usize * n + col];
            out[lm_index(l, m)] = phases[(m + lmax as i64) as usize] * (norm * dm);
        }
    }
    Ok(out)
}

/// `2Y_lm(theta, phi)` by the closed form PSH (26a)-(26c) through `Y_lm` and `Y_{l-1,m}`,
/// for `2 <= l`, `|m| <= l`; singular at the poles (a cross-check away from them).
pub fn spin2_closed_form(l: usize, m: i64, theta: f64, phi: f64) -> Result<Complex64> {
    if l < 2 {
        return Err(Error::DegreeOutOfRange {
            name: "l",
            value: l as i128,
            reason: "spin-2 harmonics start at l = 2".into(),
        });
    }
    crate::sh::check_lm(l as i64, m)?;
    let y = sh_complex(l, theta, phi)?;
    let (lf, mf) = (l as f64, m as f64);
    let (s, c) = theta.sin_cos();
    let cot = c / s;
    let alpha = (2.0 * mf * mf - lf * (lf + 1.0)) / (s * s) - 2.0 * mf * (lf - 1.0) * cot / s
        + lf * (lf - 1.0) * cot * cot;
    let beta = 2.0
        * ((2.0 * lf + 1.0) / (2.0 * lf - 1.0) * (lf * lf - mf * mf)).sqrt()
        * (mf / (s * s) + cot / s);
    let ylm1 = if (m.unsigned_abs() as usize) < l {
        y[lm_index(l - 1, m)]
    } else {
        Complex64::default()
    };
    let fact: f64 = ((l - 1)..=(l + 2)).map(|k| k as f64).product();
    Ok((alpha * y[lm_index(l, m)] + beta * ylm1) / fact.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::evaluation::harmonics::sh_complex;

    #[test]
    fn spin_two_matches_psh_26_away_from_the_poles() {
        let lmax = 12;
        for &(t, p) in &[(0.4, 0.3), (1.3, -2.0), (2.7, 1.1)] {
            let y2 = swsh(2, lmax, t, p).unwrap();
            for l in 2..=lmax {
                for m in -(l as i64)..=l as i64 {
                    let e = spin2_closed_form(l, m, t, p).unwrap();
                    let got = y2[lm_index(l, m)];
                    assert!(
                        (got - e).norm() < 1e-12,
                        "l {l} m {m} theta {t}: {got} vs {e}"
                    );
                }
            }
        }
    }

    #[test]
    fn spin_zero_is_scalar_sh() {
        let (a, b) = (
            swsh(0, 20, 0.7, 2.1).unwrap(),
            sh_complex(20, 0.7, 2.1).unwrap(),
        );
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).norm() < 1e-14);
        }
    }

    /// PSH (27): at the north pole only m = -2 survives, at the south pole only m = 2.
    #[test]
    fn poles_follow_psh_27() {
        let lmax = 30;
        for (theta, keep) in [(0.0, -2i64), (PI, 2)] {
            let y = swsh(2, lmax, theta, 0.9).unwrap();
            for l in 2..=lmax {
                for m in -(l as i64)..=l as i64 {
                    let v = y[lm_index(l, m)].norm();
                    if m == keep {
                        // |2Y_l,+-2| at the pole is sqrt((2l+1)/(4 pi)).
                        let e = ((2 * l + 1) as f64 / (4.0 * PI)).sqrt();
                        assert!((v - e).abs() < 1e-13, "l {l}");
                    } else {
                        assert!(v < 1e-14, "l {l} m {m}: {v}");
                    }
                }
            }
        }
    }

    #[test]
    fn bad_input_is_an_error() {
        assert!(swsh(2, 4, f64::NAN, 0.0).is_err());
        assert!(swsh(2, 4, 0.1, f64::INFINITY).is_err());
        assert!(swsh(1000, 4, 0.1, 0.0).is_err());
        assert!(swsh(2, crate::sh::MAX_DEGREE + 1, 0.1, 0.0).is_err());
    }
}
