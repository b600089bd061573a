//! Arbitrary-precision oracles (feature `exact`, rug).
//!
//! These routines produce reference values for the f64 code of [`crate::sh`]. They share
//! no code with it: different algorithms where possible (Wigner's finite sum instead of a
//! recursion; an unnormalized recurrence with exact integer coefficients instead of the
//! normalized one), all arithmetic in MPFR with correct rounding, and every returned
//! value carries a *certified* relative error: each routine runs a rigorous a priori
//! (Wigner d) or running (Legendre) forward error bound alongside the computation and
//! repeats the computation at higher working precision until the bound is met. The
//! bounds are derived in `proofs/exact-oracles.md`.
//!
//! Inputs that come from f64 code should be converted with [`float_from_f64`], which is
//! exact: the oracle is then evaluated at exactly the argument the f64 code sees (for
//! instance `std::f64::consts::PI`, which is not pi).

pub(crate) mod legendre;
pub(crate) mod solid;
pub(crate) mod wigner3j;
pub(crate) mod wigner_d;

pub use legendre::{pbar, pbar_all, pbar_degrees, pbar_explicit, tri_index};
pub use solid::{sh_jets, Jet};
pub use wigner3j::{
    gaunt_exact, gaunt_product_exact, real_gaunt_exact, wigner_3j_exact, ExactGaunt, SignedSqrt,
};
pub use wigner_d::{big_d, small_d, small_d_block, small_d_half, small_d_many};

use rug::float::Round;
use rug::ops::{AddAssignRound, MulAssignRound};
use rug::Float;

/// The exact value of a finite or non-finite f64 as a [`Float`] of 53 bits.
///
/// Every f64 (normal or subnormal) has at most 53 significant bits and MPFR's exponent
/// range contains the whole f64 range, so the conversion is exact; `x.to_f64()` of the
/// result gives back `x` bit for bit (including the sign of zero).
pub fn float_from_f64(x: f64) -> Float {
    Float::with_val(53, x)
}

/// Decimal scientific string of `x` with `digits` significant digits, correctly rounded
/// (round to nearest), in the form `-d.ddd...e-123`; zero prints as `"0"` and the
/// non-finite values as `"inf"`, `"-inf"`, `"NaN"`.
///
/// The exponent is unbounded: values far below the f64 range print as e.g.
/// `"1.234e-614400"`, which `str::parse::<f64>` reads as `0.0`.
pub fn to_sci_string(x: &Float, digits: usize) -> String {
    let digits = digits.max(1);
    let (neg, s, exp) = x.to_sign_string_exp(10, Some(digits));
    let sign = if neg { "-" } else { "" };
    match exp {
        None => {
            if x.is_zero() {
                "0".to_string()
            } else {
                format!("{sign}{s}")
            }
        }
        Some(e) => {
            // MPFR's form is 0.DDDD x 10^e; ours is D.DDD x 10^(e-1).
            let (first, rest) = s.split_at(1);
            if rest.is_empty() {
                format!("{sign}{first}e{}", i64::from(e) - 1)
            } else {
                format!("{sign}{first}.{rest}e{}", i64::from(e) - 1)
            }
        }
    }
}

/// Precision (bits) of the Floats that hold error bounds. Bounds are always rounded
/// upwards, so their own rounding only makes them larger.
pub(crate) const BOUND_PREC: u32 = 64;

/// An upper bound of Higham's `gamma_n = n u / (1 - n u)` for unit roundoff
/// `u = 2^-prec` (MPFR, round to nearest): `(n + 1) 2^-prec`, valid while
/// `n^2 u <= 1/2`, which holds for every use here (`n < 2^20`, `prec >= 64`).
pub(crate) fn gamma(n: u64, prec: u32) -> Float {
    let mut g = Float::with_val(BOUND_PREC, n + 1);
    g >>= prec;
    g
}

/// `|x|` rounded upwards to [`BOUND_PREC`] bits.
pub(crate) fn abs_up(x: &Float) -> Float {
    Float::with_val_round(BOUND_PREC, x.abs_ref(), Round::Up).0
}

/// `a + b`, rounded upwards (both assumed non-negative).
pub(crate) fn add_up(a: &Float, b: &Float) -> Float {
    let mut r = a.clone();
    r.add_assign_round(b, Round::Up);
    r
}

/// `a * b`, rounded upwards (both assumed non-negative).
pub(crate) fn mul_up(a: &Float, b: &Float) -> Float {
    let mut r = a.clone();
    r.mul_assign_round(b, Round::Up);
    r
}

/// Number of extra bits needed so that an absolute error bound `err` becomes at most
/// `2^-target |value|`; `0` if it already is. `None` if `value` is zero while `err` is
/// not (the relative error is then unbounded and the caller must simply try harder).
pub(crate) fn deficit_bits(err: &Float, value: &Float, target: u32) -> Option<u32> {
    if err.is_zero() {
        return Some(0);
    }
    if value.is_zero() || !value.is_finite() || !err.is_finite() {
        return None;
    }
    // Compare log2(err) - log2|value| + target with 0, using exponents (exact integers).
    let e_err = i64::from(err.get_exp().unwrap_or(0));
    let e_val = i64::from(value.get_exp().unwrap_or(0));
    // err < 2^e_err and |value| >= 2^(e_val - 1), so err / |value| < 2^(e_err - e_val + 1).
    let excess = e_err - e_val + 1 + i64::from(target);
    if excess <= 0 {
        Some(0)
    } else {
        Some(u32::try_from(excess).unwrap_or(u32::MAX))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn f64_conversion_is_exact() {
        for &x in &[
            0.0,
            -0.0,
            1e-300,
            5e-324,
            0.3,
            std::f64::consts::PI,
            std::f64::consts::PI - 1e-8,
            f64::MAX,
        ] {
            let f = float_from_f64(x);
            assert_eq!(f.to_f64().to_bits(), x.to_bits());
            // Exactness: the 53-bit value equals the same value held at 300 bits.
            assert_eq!(f, Float::with_val(300, x));
        }
        // The f64 PI is below pi by about 1.2246e-16.
        let pi = Float::with_val(200, rug::float::Constant::Pi);
        let d = Float::with_val(200, &pi - float_from_f64(std::f64::consts::PI));
        assert!((d.to_f64() - 1.2246467991473532e-16).abs() < 1e-30);
    }

    #[test]
    fn sci_strings() {
        assert_eq!(to_sci_string(&Float::with_val(64, 0), 40), "0");
        assert_eq!(to_sci_string(&Float::with_val(64, 0.25), 3), "2.50e-1");
        assert_eq!(to_sci_string(&Float::with_val(64, -1234.5), 4), "-1.234e3");
        let tiny = Float::with_val(64, Float::u_exp(1, -3_000_000));
        let s = to_sci_string(&tiny, 5);
        assert!(s.ends_with("e-903090"), "{s}");
        assert_eq!(s.parse::<f64>().unwrap(), 0.0);
    }

    #[test]
    fn deficit() {
        let v = Float::with_val(64, 1.0);
        let e = Float::with_val(64, Float::u_exp(1, -200));
        assert_eq!(deficit_bits(&e, &v, 100), Some(0));
        assert!(deficit_bits(&e, &v, 250).unwrap() >= 50);
        assert_eq!(deficit_bits(&Float::new(64), &Float::new(64), 10), Some(0));
        assert_eq!(deficit_bits(&e, &Float::new(64), 10), None);
    }
}
