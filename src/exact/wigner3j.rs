//! Exact Wigner 3j symbols and Gaunt coefficients (feature `exact`): oracles for
//! [`crate::sh::coupling::wigner3j`] and [`crate::sh::coupling::gaunt`].
//!
//! Every 3j symbol with integer arguments is `± sqrt(r)` with `r` rational (Racah's formula,
//! DLMF 34.2.4), computed here in exact integer/rational arithmetic ([`rug`]). Gaunt
//! coefficients are `± sqrt(q) / sqrt(4 pi)` with `q` rational (DLMF §34.3(vii)); they are
//! represented by the exact factor `± sqrt(q)` ([`SignedSqrt`]) and the explicit
//! `1/sqrt(4 pi)`, evaluated only when converting to a [`Float`] ([`ExactGaunt`]).
//!
//! Conventions are those of [`crate::sh::coupling::gaunt`]: complex SH of PSH (1) with the
//! Condon-Shortley phase, real SH of PSH (12).
//!
//! Nothing here shares code with the `f64` implementation: the 3j symbols come from Racah's
//! sum rather than the recursion, and the real Gaunt coefficients from the change of basis
//! of PSH (12) carried out term by term in Gaussian-integer arithmetic (each complex Gaunt of
//! the sum computed separately), without the symmetry-based reduction used in `f64`.

use crate::error::{Error, Result};
use crate::sh::MAX_GAUNT_DEGREE;
use rug::float::Constant;
use rug::{Float, Integer, Rational};
use std::cmp::Ordering;

/// Guard bits added to the requested precision in conversions to [`Float`].
const GUARD_BITS: u32 = 64;

/// An exact real number `sign * sqrt(square)`, `square` a non-negative rational,
/// `sign in {-1, 0, 1}` (0 exactly when `square = 0`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SignedSqrt {
    sign: i32,
    square: Rational,
}

impl SignedSqrt {
    /// `sign * sqrt(square)`; the sign of a zero value is normalized to 0.
    /// Errors: [`Error::InvalidArgument`] if `square < 0` or `sign` is not -1, 0 or 1
    /// (a nonzero `square` with `sign == 0` is also rejected).
    pub fn new(sign: i32, square: Rational) -> Result<Self> {
        if square.cmp0() == Ordering::Less {
            return Err(Error::invalid(
                "square",
                square.to_string(),
                "the square of a real number is non-negative",
            ));
        }
        if !(-1..=1).contains(&sign) || (sign == 0 && square.cmp0() != Ordering::Equal) {
            return Err(Error::invalid(
                "sign",
                sign.to_string(),
                "the sign must be -1 or 1 (0 only for a zero value)",
            ));
        }
        let sign = if square.cmp0() == Ordering::Equal {
            0
        } else {
            sign
        };
        Ok(SignedSqrt { sign, square })
    }

    /// Zero.
    pub fn zero() -> Self {
        SignedSqrt {
            sign: 0,
            square: Rational::new(),
        }
    }

    /// Whether the value is exactly zero.
    pub fn is_zero(&self) -> bool {
        self.sign == 0
    }

    /// The sign, -1, 0 or 1.
    pub fn sign(&self) -> i32 {
        self.sign
    }

    /// The exact square of the value.
    pub fn square(&self) -> &Rational {
        &self.square
    }

    /// Exact product: `(s1 sqrt(r1)) (s2 sqrt(r2)) = s1 s2 sqrt(r1 r2)`.
    pub fn mul(&self, other: &SignedSqrt) -> SignedSqrt {
        let sign = self.sign * other.sign;
        if sign == 0 {
            return SignedSqrt::zero();
        }
        SignedSqrt {
            sign,
            square: Rational::from(&self.square * &other.square),
        }
    }

    /// The value rounded to `prec` bits (computed with extra guard bits, then rounded once
    /// more; the result is within one ulp of the exact value).
    pub fn to_float(&self, prec: u32) -> Float {
        let work = prec + GUARD_BITS;
        let mut v = Float::with_val(work, &self.square);
        v.sqrt_mut();
        if self.sign < 0 {
            v = -v;
        }
        Float::with_val(prec, &v)
    }

    /// The value as the nearest `f64` (up to one ulp).
    pub fn to_f64(&self) -> f64 {
        self.to_float(53 + GUARD_BITS).to_f64()
    }
}

/// An exact Gaunt coefficient, `coefficient / sqrt(4 pi)` with `coefficient` of the form
/// `± sqrt(q)`, `q` rational.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExactGaunt {
    coefficient: SignedSqrt,
}

impl ExactGaunt {
    /// The exact factor multiplying `1/sqrt(4 pi)`.
    pub fn coefficient(&self) -> &SignedSqrt {
        &self.coefficient
    }

    /// Whether the coefficient is exactly zero.
    pub fn is_zero(&self) -> bool {
        self.coefficient.is_zero()
    }

    /// `± sqrt(q / (4 pi))` rounded to `prec` bits (guard bits added internally; within one
    /// ulp of the exact value).
    pub fn to_float(&self, prec: u32) -> Float {
        let work = prec + GUARD_BITS;
        let four_pi = Float::with_val(work, Constant::Pi) * 4u32;
        let mut v = Float::with_val(work, &self.coefficient.square) / four_pi;
        v.sqrt_mut();
        if self.coefficient.sign < 0 {
            v = -v;
        }
        Float::with_val(prec, &v)
    }

    /// The value as the nearest `f64` (up to one ulp).
    pub fn to_f64(&self) -> f64 {
        self.to_float(53 + GUARD_BITS).to_f64()
    }
}

/// Checks `l <= MAX_GAUNT_DEGREE` and `|m| <= l`.
fn check(lname: &'static str, mname: &'static str, l: usize, m: i64) -> Result<()> {
    if l > MAX_GAUNT_DEGREE {
        return Err(Error::DegreeOutOfRange {
            name: lname,
            value: l as i128,
            reason: format!("the largest degree supported is {MAX_GAUNT_DEGREE}"),
        });
    }
    if m.unsigned_abs() > l as u64 {
        return Err(Error::OrderOutOfRange {
            name: mname,
            l: l as i64,
            m,
        });
    }
    Ok(())
}

/// `n!` (GMP's factorial).
fn fact(n: i64) -> Integer {
    Integer::from(Integer::factorial(n as u32))
}

/// Racah's formula (DLMF 34.2.4), for validated arguments:
/// `(l1 l2 l3; m1 m2 m3) = (-1)^{l1-l2-m3} Δ(l1 l2 l3)
///   [(l1+m1)!(l1-m1)!(l2+m2)!(l2-m2)!(l3+m3)!(l3-m3)!]^{1/2}
///   sum_s (-1)^s / [s! (l1+l2-l3-s)! (l1-m1-s)! (l2+m2-s)! (l3-l2+m1+s)! (l3-l1-m2+s)!]`,
/// `Δ^2 = (l1+l2-l3)! (l1-l2+l3)! (-l1+l2+l3)! / (l1+l2+l3+1)!`.
/// The sum is evaluated exactly as a terminating hypergeometric series: consecutive terms
/// have the ratio `-(a-s)(b-s)(c-s) / ((s+1)(s+1-d)(s+1-e))`, nested from the last term.
fn racah(l1: i64, l2: i64, l3: i64, m1: i64, m2: i64, m3: i64) -> SignedSqrt {
    if m1 + m2 + m3 != 0 || l3 < (l1 - l2).abs() || l3 > l1 + l2 {
        return SignedSqrt::zero();
    }
    // Summation limits and the parameters of the term ratio.
    let (a, b, c) = (l1 + l2 - l3, l1 - m1, l2 + m2);
    let (d, e) = (l2 - l3 - m1, l1 - l3 + m2); // s - d = l3 - l2 + m1 + s >= 0, etc.
    let smin = 0.max(d).max(e);
    let smax = a.min(b).min(c);
    if smin > smax {
        return SignedSqrt::zero();
    }
    // Nested sum: acc = 1 + r_s acc, from s = smax - 1 down to smin, acc = num / den.
    let mut num = Integer::from(1);
    let mut den = Integer::from(1);
    for s in (smin..smax).rev() {
        let p = Integer::from((a - s) * (b - s)) * (c - s);
        let q = Integer::from((s + 1) * (s + 1 - d)) * (s + 1 - e);
        // 1 - (p/q)(num/den) = (q den - p num) / (q den)
        num = Integer::from(&q * &den) - p * num;
        den *= q;
    }
    // First term t = (-1)^smin / D_smin.
    let dmin = fact(smin)
        * fact(a - smin)
        * fact(b - smin)
        * fact(c - smin)
        * fact(smin - d)
        * fact(smin - e);
    let sum = Rational::from((num, den * dmin));
    let sum_sign = match sum.cmp0() {
        Ordering::Equal => return SignedSqrt::zero(),
        Ordering::Greater => 1,
        Ordering::Less => -1,
    } * if smin % 2 == 0 { 1 } else { -1 };
    let delta_num = fact(l1 + l2 - l3) * fact(l1 - l2 + l3) * fact(-l1 + l2 + l3);
    let pre = delta_num
        * fact(l1 + m1)
        * fact(l1 - m1)
        * fact(l2 + m2)
        * fact(l2 - m2)
        * fact(l3 + m3)
        * fact(l3 - m3);
    let square = Rational::from((pre, fact(l1 + l2 + l3 + 1))) * Rational::from(sum.square_ref());
    let phase = if (l1 - l2 - m3).rem_euclid(2) == 0 {
        1
    } else {
        -1
    };
    SignedSqrt {
        sign: phase * sum_sign,
        square,
    }
}

/// Exact Wigner 3j symbol `(l1 l2 l3; m1 m2 m3)` by Racah's formula (DLMF 34.2.4), as
/// `± sqrt(r)`; arguments in `(l, m)` pairs as in [`crate::sh::coupling::wigner3j`]. Exactly zero when the selection rules (DLMF §34.2) forbid it, and also at
/// nontrivial zeros such as `(3 3 2; 2 -2 0)`.
///
/// Errors: [`Error::DegreeOutOfRange`] (degree above [`MAX_GAUNT_DEGREE`]),
/// [`Error::OrderOutOfRange`] (`|m_i| > l_i`). Cost grows like `(l1+l2+l3)^2` digits of work.
pub fn wigner_3j_exact(
    l1: usize,
    m1: i64,
    l2: usize,
    m2: i64,
    l3: usize,
    m3: i64,
) -> Result<SignedSqrt> {
    check("l1", "m1", l1, m1)?;
    check("l2", "m2", l2, m2)?;
    check("l3", "m3", l3, m3)?;
    Ok(racah(l1 as i64, l2 as i64, l3 as i64, m1, m2, m3))
}

/// `G = (2l1+1)(2l2+1)(2l3+1) * (l1 l2 l3; 0 0 0)^2 (l1 l2 l3; m1 m2 m3)^2` as the squared
/// coefficient of `1/sqrt(4 pi)`, with its sign (DLMF §34.3(vii)); arguments validated.
fn gaunt_coefficient(l1: i64, m1: i64, l2: i64, m2: i64, l3: i64, m3: i64) -> SignedSqrt {
    let w0 = racah(l1, l2, l3, 0, 0, 0);
    let wm = racah(l1, l2, l3, m1, m2, m3);
    let p = SignedSqrt {
        sign: 1,
        square: Rational::from(Integer::from((2 * l1 + 1) * (2 * l2 + 1)) * (2 * l3 + 1)),
    };
    p.mul(&w0).mul(&wm)
}

/// Exact complex Gaunt coefficient `∫ Y_{l1 m1} Y_{l2 m2} Y_{l3 m3} dω
/// = sqrt((2l1+1)(2l2+1)(2l3+1)/(4 pi)) (l1 l2 l3; 0 0 0)(l1 l2 l3; m1 m2 m3)`
/// (DLMF §34.3(vii); SH of PSH (1)). Errors as [`wigner_3j_exact`].
pub fn gaunt_exact(
    l1: usize,
    m1: i64,
    l2: usize,
    m2: i64,
    l3: usize,
    m3: i64,
) -> Result<ExactGaunt> {
    check("l1", "m1", l1, m1)?;
    check("l2", "m2", l2, m2)?;
    check("l3", "m3", l3, m3)?;
    Ok(ExactGaunt {
        coefficient: gaunt_coefficient(l1 as i64, m1, l2 as i64, m2, l3 as i64, m3),
    })
}

/// Exact product-form Gaunt coefficient `∫ conj(Y_{lm}) Y_{l1 m1} Y_{l2 m2} dω
/// = (-1)^m G(l1 m1, l2 m2, l -m)`, since `conj(Y_lm) = (-1)^m Y_{l,-m}` (PSH (1), with the
/// Condon-Shortley phase). Errors as [`wigner_3j_exact`].
pub fn gaunt_product_exact(
    l: usize,
    m: i64,
    l1: usize,
    m1: i64,
    l2: usize,
    m2: i64,
) -> Result<ExactGaunt> {
    check("l", "m", l, m)?;
    check("l1", "m1", l1, m1)?;
    check("l2", "m2", l2, m2)?;
    let mut c = gaunt_coefficient(l1 as i64, m1, l2 as i64, m2, l as i64, -m);
    if m.rem_euclid(2) == 1 {
        c.sign = -c.sign;
    }
    Ok(ExactGaunt { coefficient: c })
}

/// A Gaussian unit times `2^{-halves/2}`: the entries of the change of basis of PSH (12).
#[derive(Clone, Copy)]
struct UnitEntry {
    re: i64,
    im: i64,
    halves: u32,
}

/// Entry `U_{m mu}` of `Y^R_{lm} = sum_mu U_{m mu} Y_{l mu}` (PSH (12)), for `mu = ±|m|`:
/// `m > 0`: `U_{m,m} = 1/sqrt 2`, `U_{m,-m} = (-1)^m / sqrt 2`;
/// `m = 0`: `U_{0,0} = 1`;
/// `m < 0`: `U_{m,m} = i (-1)^m / sqrt 2`, `U_{m,-m} = -i / sqrt 2`.
fn u_entry(m: i64, mu: i64) -> UnitEntry {
    let parity = if m.rem_euclid(2) == 0 { 1 } else { -1 };
    match (m.cmp(&0), mu == m) {
        (Ordering::Equal, _) => UnitEntry {
            re: 1,
            im: 0,
            halves: 0,
        },
        (Ordering::Greater, true) => UnitEntry {
            re: 1,
            im: 0,
            halves: 1,
        },
        (Ordering::Greater, false) => UnitEntry {
            re: parity,
            im: 0,
            halves: 1,
        },
        (Ordering::Less, true) => UnitEntry {
            re: 0,
            im: parity,
            halves: 1,
        },
        (Ordering::Less, false) => UnitEntry {
            re: 0,
            im: -1,
            halves: 1,
        },
    }
}

/// Exact real Gaunt coefficient `∫ Y^R_{l1 m1} Y^R_{l2 m2} Y^R_{l3 m3} dω` for the real SH of
/// PSH (12), from its definition
/// `R = sum_{mu1 mu2 mu3} U_{m1 mu1} U_{m2 mu2} U_{m3 mu3} G(l1 mu1, l2 mu2, l3 mu3)`
/// (`mu_i = ±|m_i|`): every admissible term is computed exactly (each complex Gaunt by
/// Racah's formula) and the sum is carried out in Gaussian integers. All terms share
/// `|G|` (DLMF 34.3.10) and the imaginary parts cancel; both facts are checked, not assumed.
/// Errors as [`wigner_3j_exact`].
pub fn real_gaunt_exact(
    l1: usize,
    m1: i64,
    l2: usize,
    m2: i64,
    l3: usize,
    m3: i64,
) -> Result<ExactGaunt> {
    check("l1", "m1", l1, m1)?;
    check("l2", "m2", l2, m2)?;
    check("l3", "m3", l3, m3)?;
    let m = [m1, m2, m3];
    let l = [l1 as i64, l2 as i64, l3 as i64];
    let mut square: Option<Rational> = None;
    let (mut re, mut im) = (0i64, 0i64);
    let mut halves = 0;
    for signs in 0..8u32 {
        let mut mu = [0i64; 3];
        let mut skip = false;
        for i in 0..3 {
            let negative = signs & (1 << i) != 0;
            skip |= negative && m[i] == 0;
            mu[i] = if negative { -m[i].abs() } else { m[i].abs() };
        }
        if skip || mu.iter().sum::<i64>() != 0 {
            continue;
        }
        let g = gaunt_coefficient(l[0], mu[0], l[1], mu[1], l[2], mu[2]);
        if g.is_zero() {
            continue;
        }
        match &square {
            None => square = Some(g.square.clone()),
            Some(s) => assert_eq!(
                s, &g.square,
                "complex Gaunt terms of one real Gaunt differ in magnitude"
            ),
        }
        // Product of the three Gaussian units, times the sign of G.
        let (mut pr, mut pi) = (g.sign as i64, 0i64);
        halves = 0;
        for i in 0..3 {
            let u = u_entry(m[i], mu[i]);
            (pr, pi) = (pr * u.re - pi * u.im, pr * u.im + pi * u.re);
            halves += u.halves;
        }
        re += pr;
        im += pi;
    }
    assert_eq!(im, 0, "the real Gaunt coefficient must be real");
    let Some(square) = square else {
        return Ok(ExactGaunt {
            coefficient: SignedSqrt::zero(),
        });
    };
    if re == 0 {
        return Ok(ExactGaunt {
            coefficient: SignedSqrt::zero(),
        });
    }
    // (re 2^{-halves/2})^2 q = re^2 q / 2^halves.
    let factor = Rational::from((Integer::from(re * re), Integer::from(1) << halves));
    Ok(ExactGaunt {
        coefficient: SignedSqrt {
            sign: re.signum() as i32,
            square: square * factor,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::wigner_3j_row;

    fn q(n: i64, d: i64) -> Rational {
        Rational::from((n, d))
    }

    #[test]
    fn known_exact_values() {
        // (1 1 0; 1 -1 0) = 1/sqrt 3 (DLMF 34.3.1); (1 1 1; 1 -1 0) = 1/sqrt 6 (DLMF 34.3.2);
        // (2 2 2; 0 0 0) = -sqrt(2/35) (DLMF 34.3.5); (1 1 2; 0 0 0) = sqrt(2/15).
        let cases = [
            ((1, 1, 0, 1, -1, 0), 1, q(1, 3)),
            ((1, 1, 1, 1, -1, 0), 1, q(1, 6)),
            ((2, 2, 2, 0, 0, 0), -1, q(2, 35)),
            ((1, 1, 2, 0, 0, 0), 1, q(2, 15)),
            ((1, 1, 2, 1, -1, 0), 1, q(1, 30)),
        ];
        for ((l1, l2, l3, m1, m2, m3), sign, sq) in cases {
            let w = wigner_3j_exact(l1, m1, l2, m2, l3, m3).unwrap();
            assert_eq!(
                w,
                SignedSqrt::new(sign, sq).unwrap(),
                "({l1} {l2} {l3}; {m1} {m2} {m3})"
            );
        }
        // A nontrivial zero, and selection-rule zeros.
        assert!(wigner_3j_exact(3, 2, 3, -2, 2, 0).unwrap().is_zero());
        assert!(wigner_3j_exact(1, 0, 1, 0, 1, 0).unwrap().is_zero());
        assert!(wigner_3j_exact(1, 0, 1, 0, 3, 0).unwrap().is_zero());
        assert!(wigner_3j_exact(1, 1, 1, 1, 1, -1).unwrap().is_zero());
        // Real Gaunt of Y^R_11 Y^R_11 Y^R_20 = -(2/5) sqrt(5/(16 pi)) = -sqrt(4/5)/sqrt(4 pi)
        // (hand integration of x^2 (3 z^2 - 1)).
        let r = real_gaunt_exact(1, 1, 1, 1, 2, 0).unwrap();
        assert_eq!(r.coefficient(), &SignedSqrt::new(-1, q(1, 5)).unwrap());
        // G(00, lm, l-m) = (-1)^m / sqrt(4 pi).
        let g = gaunt_exact(0, 0, 3, 1, 3, -1).unwrap();
        assert_eq!(g.coefficient(), &SignedSqrt::new(-1, q(1, 1)).unwrap());
    }

    #[test]
    fn closed_forms_dlmf_34_3_5_and_34_3_6() {
        // DLMF 34.3.5, exactly.
        for &(l1, l2, l3) in &[
            (2i64, 3i64, 5i64),
            (10, 12, 14),
            (40, 37, 19),
            (100, 90, 60),
        ] {
            let j = l1 + l2 + l3;
            let g = j / 2;
            let r = Rational::from((
                fact(j - 2 * l1) * fact(j - 2 * l2) * fact(j - 2 * l3),
                fact(j + 1),
            )) * Rational::from((
                fact(g).square(),
                (fact(g - l1) * fact(g - l2) * fact(g - l3)).square(),
            ));
            let sign = if g % 2 == 0 { 1 } else { -1 };
            let w = wigner_3j_exact(l1 as usize, 0, l2 as usize, 0, l3 as usize, 0).unwrap();
            assert_eq!(w, SignedSqrt::new(sign, r).unwrap());
        }
        // DLMF 34.3.6, exactly.
        for &(l1, l2, m1, m2) in &[
            (3i64, 4i64, -2i64, 1i64),
            (20, 7, 20, -7),
            (50, 50, -13, 40),
        ] {
            let (lj, mm) = (l1 + l2, m1 + m2);
            let r = Rational::from((
                fact(2 * l1) * fact(2 * l2) * fact(lj + mm) * fact(lj - mm),
                fact(2 * lj + 1) * fact(l1 + m1) * fact(l1 - m1) * fact(l2 + m2) * fact(l2 - m2),
            ));
            let sign = if (l1 - l2 + mm).rem_euclid(2) == 0 {
                1
            } else {
                -1
            };
            let w = wigner_3j_exact(l1 as usize, m1, l2 as usize, m2, lj as usize, -mm).unwrap();
            assert_eq!(w, SignedSqrt::new(sign, r).unwrap());
        }
    }

    #[test]
    fn exact_symmetries() {
        // DLMF 34.3.8-34.3.10, as exact equalities.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move |n: i64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % (n as u64 + 1)) as i64
        };
        for _ in 0..200 {
            let (l1, l2) = (next(20), next(20));
            let l3 = (l1 - l2).abs() + next(l1 + l2 - (l1 - l2).abs());
            let m1 = next(2 * l1) - l1;
            let m2 = next(2 * l2) - l2;
            let m3 = -m1 - m2;
            if m3.abs() > l3 {
                continue;
            }
            let (u1, u2, u3) = (l1 as usize, l2 as usize, l3 as usize);
            let w = wigner_3j_exact(u1, m1, u2, m2, u3, m3).unwrap();
            let mut odd = w.clone();
            if (l1 + l2 + l3) % 2 == 1 {
                odd.sign = -odd.sign;
            }
            assert_eq!(wigner_3j_exact(u2, m2, u3, m3, u1, m1).unwrap(), w);
            assert_eq!(wigner_3j_exact(u3, m3, u1, m1, u2, m2).unwrap(), w);
            assert_eq!(wigner_3j_exact(u2, m2, u1, m1, u3, m3).unwrap(), odd);
            assert_eq!(wigner_3j_exact(u1, -m1, u2, -m2, u3, -m3).unwrap(), odd);
        }
    }

    #[test]
    fn orthogonality_at_high_precision() {
        // sum_{m1} (2 l3 + 1) (l1 l2 l3; m1 m2 m3)(l1 l2 l3'; m1 m2 m3) = δ (DLMF §34.3(iv)),
        // evaluated at 300 bits.
        let (l1, l2, m3) = (7usize, 5usize, -1i64);
        for l3 in 2..=12usize {
            for l3p in 2..=12usize {
                let mut s = Float::with_val(300, 0);
                for m1 in -(l1 as i64)..=l1 as i64 {
                    let m2 = -m3 - m1;
                    if m2.unsigned_abs() as usize > l2 {
                        continue;
                    }
                    let a = wigner_3j_exact(l1, m1, l2, m2, l3, m3)
                        .unwrap()
                        .to_float(300);
                    let b = wigner_3j_exact(l1, m1, l2, m2, l3p, m3)
                        .unwrap()
                        .to_float(300);
                    s += a * b * (2 * l3 as u32 + 1);
                }
                let e: i32 = if l3 == l3p { 1 } else { 0 };
                let err = Float::with_val(300, &s - e).abs();
                assert!(err < 1e-80, "{l3} {l3p}: {err}");
            }
        }
    }

    #[test]
    fn product_and_real_relations() {
        // gaunt_product = (-1)^m G(.., l -m), and the real Gaunt against hand-derived values:
        // ∫ Y^R_{1,-1} Y^R_{1,-1} Y^R_{2,0} = ∫ Y^R_11 Y^R_11 Y^R_20 (x <-> y symmetry of
        // Y_20), ∫ Y^R_{1,1} Y^R_{1,-1} Y^R_{2,-2} = (3/(4 pi)) (1/2) sqrt(15/pi) ∫ x^2 y^2
        // = (3/(4 pi)) (1/2) sqrt(15/pi) (4 pi/15) = sqrt(3/5)/sqrt(4 pi) ... with sign +.
        let p = gaunt_product_exact(2, 1, 1, 1, 1, 0).unwrap();
        let g = gaunt_exact(1, 1, 1, 0, 2, -1).unwrap();
        assert_eq!(p.coefficient().square(), g.coefficient().square());
        assert_eq!(p.coefficient().sign(), -g.coefficient().sign());
        let a = real_gaunt_exact(1, -1, 1, -1, 2, 0).unwrap();
        let b = real_gaunt_exact(1, 1, 1, 1, 2, 0).unwrap();
        assert_eq!(a, b);
        let c = real_gaunt_exact(1, 1, 1, -1, 2, -2).unwrap();
        assert_eq!(c.coefficient(), &SignedSqrt::new(1, q(3, 5)).unwrap());
        // Odd number of negative orders: zero.
        assert!(real_gaunt_exact(1, 1, 1, -1, 2, 2).unwrap().is_zero());
    }

    #[test]
    fn bad_input() {
        assert!(matches!(
            wigner_3j_exact(1, 2, 1, -2, 1, 0),
            Err(Error::OrderOutOfRange { .. })
        ));
        assert!(matches!(
            gaunt_exact(MAX_GAUNT_DEGREE + 1, 0, 1, 0, 1, 0),
            Err(Error::DegreeOutOfRange { .. })
        ));
        assert!(SignedSqrt::new(1, q(-1, 2)).is_err());
        assert!(SignedSqrt::new(0, q(1, 2)).is_err());
        assert!(SignedSqrt::new(2, q(1, 2)).is_err());
    }

    /// The f64 rows of `crate::sh::coupling::wigner3j` against Racah's formula up to degree 8192: samples
    /// of each row (both ends, the middle, the largest value and 150 points across), including
    /// the edge cases m = ±l whose rows peak at l3_min. Every value in the normal f64 range
    /// must be within one ulp (relative error <= 2^-52): the recursion runs in double-double,
    /// so the only sizeable error is the final rounding to f64.
    #[test]
    fn f64_rows_are_within_one_ulp_at_large_degrees() {
        let cases: &[(usize, usize, i64, i64)] = &[
            (40, 35, 3, -20),
            (120, 97, 0, 0),
            (200, 200, 150, -150),
            (500, 20, -7, 11),
            (700, 650, 300, 200),
            (1000, 1000, 1, -1),
            (1000, 1000, 1000, -1000),
            (2000, 1990, 2000, -1990),
            (2000, 1500, -1000, 700),
            (3000, 2999, 0, 0),
            (4096, 4000, 2048, -3000),
            (8192, 8192, 8192, -8192),
            (8192, 100, 0, 50),
        ];
        let one_ulp = f64::EPSILON;
        let mut max_rel: f64 = 0.0;
        for &(l1, l2, m1, m2) in cases {
            let row = wigner_3j_row(l1, m1, l2, m2).unwrap();
            let n = row.values().len();
            let argmax = (0..n)
                .max_by(|&a, &b| row.values()[a].abs().total_cmp(&row.values()[b].abs()))
                .unwrap();
            let mut ks: Vec<usize> = (0..n).step_by((n / 150).max(1)).collect();
            ks.extend([
                1.min(n - 1),
                2.min(n - 1),
                n / 2,
                n.saturating_sub(2),
                n - 1,
                argmax,
            ]);
            let mut case_rel: f64 = 0.0;
            for k in ks {
                let l3 = row.l3_min() + k;
                let exact = wigner_3j_exact(l1, m1, l2, m2, l3, -m1 - m2)
                    .unwrap()
                    .to_float(200);
                let e = exact.to_f64();
                if e.abs() < 1e-290 {
                    continue; // subnormal or underflowed: not a relative-accuracy range
                }
                let v = row.get(l3);
                let rel = Float::with_val(200, &exact - v).abs().to_f64() / e.abs();
                case_rel = case_rel.max(rel);
                assert!(
                    rel <= one_ulp,
                    "({l1} {l2} {l3}; {m1} {m2}): {v:e} vs {e:e} (relative error {rel:e})"
                );
            }
            eprintln!("({l1} {l2} l3; {m1} {m2}): n = {n}, max relative error {case_rel:.3e}");
            max_rel = max_rel.max(case_rel);
        }
        eprintln!("f64 rows vs Racah: max relative error {max_rel:.3e}");
    }

    /// The committed fixture `tests/fixtures/gaunt.json` agrees with this module: every value
    /// is recomputed and compared to the 40 printed digits.
    #[test]
    fn committed_fixture_matches_oracle() {
        let path =
            std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/gaunt.json");
        let text = std::fs::read_to_string(&path).unwrap();
        let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
        let mut checked = 0;
        for name in ["wigner3j", "gaunt", "gaunt_product", "real_gaunt"] {
            for e in doc[name].as_array().unwrap() {
                let l: Vec<usize> = e["l"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.as_u64().unwrap() as usize)
                    .collect();
                let m: Vec<i64> = e["m"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v.as_i64().unwrap())
                    .collect();
                let printed = e["value"].as_str().unwrap();
                let exact = match name {
                    "wigner3j" => wigner_3j_exact(l[0], m[0], l[1], m[1], l[2], m[2])
                        .unwrap()
                        .to_float(200),
                    "gaunt" => gaunt_exact(l[0], m[0], l[1], m[1], l[2], m[2])
                        .unwrap()
                        .to_float(200),
                    "gaunt_product" => gaunt_product_exact(l[0], m[0], l[1], m[1], l[2], m[2])
                        .unwrap()
                        .to_float(200),
                    _ => real_gaunt_exact(l[0], m[0], l[1], m[1], l[2], m[2])
                        .unwrap()
                        .to_float(200),
                };
                let value = Float::with_val(200, Float::parse(printed).unwrap());
                if printed == "0" {
                    assert!(exact.is_zero(), "{name} {l:?} {m:?}");
                } else {
                    let rel = Float::with_val(200, &value - &exact).abs() / exact.abs();
                    assert!(rel < 1e-39, "{name} {l:?} {m:?}: {printed}");
                }
                checked += 1;
            }
        }
        assert!(checked > 5000);
    }
}
