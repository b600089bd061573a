//! Double-double numbers `hi + lo` (`|lo| <= ulp(hi)/2`), about 106 significant bits, from
//! the error-free transformations of Dekker (1971) and Knuth (TAOCP vol. 2, 4.2.2), following
//! the double-double algorithms of Hida, Li & Bailey (2001). Used where rounding errors must
//! stay far below f64 resolution: the 3j recursion over rows of thousands of steps
//! (`proofs/wigner3j-recursion.md`) and the accurate Legendre path
//! (`proofs/legendre-recursion.md`).

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A double-double number `hi + lo`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Dd {
    pub(crate) hi: f64,
    pub(crate) lo: f64,
}

/// `a + b = s + e` exactly.
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `a + b = s + e` exactly, for `|a| >= |b|`.
#[inline]
fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

/// Veltkamp splitting `a = hi + lo` into two 26-bit halves.
#[cfg(not(target_feature = "fma"))]
#[inline]
fn split(a: f64) -> (f64, f64) {
    let t = 134_217_729.0 * a; // 2^27 + 1
    let hi = t - (t - a);
    (hi, a - hi)
}

/// `a b = p + e` exactly, by a fused multiply-add where the target has one.
#[cfg(target_feature = "fma")]
#[inline]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// `a b = p + e` exactly (Dekker).
#[cfg(not(target_feature = "fma"))]
#[inline]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    (p, ((ah * bh - p) + ah * bl + al * bh) + al * bl)
}

/// `pi/2` as a double-double (`PI_LO` of `crate::sh::recursion::legendre` halved).
const FRAC_PI_2: Dd = Dd {
    hi: std::f64::consts::FRAC_PI_2,
    lo: 6.123_233_995_736_766e-17,
};

impl Dd {
    pub(crate) const ZERO: Dd = Dd { hi: 0.0, lo: 0.0 };
    pub(crate) const ONE: Dd = Dd { hi: 1.0, lo: 0.0 };

    #[inline]
    pub(crate) fn from_f64(x: f64) -> Dd {
        Dd { hi: x, lo: 0.0 }
    }

    /// `a + b` exactly.
    #[inline]
    pub(crate) fn sum(a: f64, b: f64) -> Dd {
        let (hi, lo) = two_sum(a, b);
        Dd { hi, lo }
    }

    /// `a b` exactly.
    #[inline]
    pub(crate) fn product(a: f64, b: f64) -> Dd {
        let (hi, lo) = two_prod(a, b);
        Dd { hi, lo }
    }

    /// `a / b` (relative error about `2^-104`): the division below for f64 operands, where
    /// `a - q1 b` is `(a - p) - e` with `a - p` exact.
    #[inline]
    pub(crate) fn quotient(a: f64, b: f64) -> Dd {
        let q1 = a / b;
        let (p, e) = two_prod(q1, b);
        let (hi, lo) = quick_two_sum(q1, ((a - p) - e) / b);
        Dd { hi, lo }
    }

    /// Multiplication by a power of two (exact barring underflow).
    #[inline]
    pub(crate) fn scale(self, p2: f64) -> Dd {
        Dd {
            hi: self.hi * p2,
            lo: self.lo * p2,
        }
    }

    /// Square root (one Newton correction of the f64 root); zero for `hi <= 0`.
    #[inline]
    pub(crate) fn sqrt(self) -> Dd {
        if self.hi <= 0.0 {
            return Dd::ZERO;
        }
        let x = self.hi.sqrt();
        let r = self - Dd::product(x, x);
        let (hi, lo) = quick_two_sum(x, r.hi / (2.0 * x));
        Dd { hi, lo }
    }

    /// `|hi|`.
    #[inline]
    pub(crate) fn abs(self) -> f64 {
        self.hi.abs()
    }

    /// `(sin x, cos x)` for `|x| <= pi/2`: Taylor series on `|x| <= pi/4`, otherwise of
    /// `pi/2 - |x|` with sine and cosine swapped.
    pub(crate) fn sin_cos(self) -> (Dd, Dd) {
        debug_assert!(self.abs() <= FRAC_PI_2.hi + 1e-15);
        let negative = self.hi < 0.0;
        let x = if negative { -self } else { self };
        let (s, c) = if x.hi <= 0.5 * FRAC_PI_2.hi {
            taylor_sin_cos(x)
        } else {
            let (s, c) = taylor_sin_cos(FRAC_PI_2 - x);
            (c, s)
        };
        (if negative { -s } else { s }, c)
    }
}

/// `(sin x, cos x)` by their Taylor series, for `0 <= x <= pi/4` (terms below `2^-110` of
/// the leading one are dropped).
fn taylor_sin_cos(x: Dd) -> (Dd, Dd) {
    let x2 = x * x;
    let (mut s, mut c) = (x, Dd::ONE);
    let (mut ts, mut tc) = (x, Dd::ONE);
    let tiny = 2f64.powi(-110);
    let mut k = 1.0;
    while tc.abs() > tiny || ts.abs() > tiny * x.abs() {
        // tc = (-1)^n x^{2n} / (2n)!, ts = (-1)^n x^{2n+1} / (2n+1)!.
        tc = -(tc * x2 / Dd::from_f64(k * (k + 1.0)));
        ts = -(ts * x2 / Dd::from_f64((k + 1.0) * (k + 2.0)));
        c = c + tc;
        s = s + ts;
        k += 2.0;
    }
    (s, c)
}

impl Neg for Dd {
    type Output = Dd;
    #[inline]
    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Add for Dd {
    type Output = Dd;
    #[inline]
    fn add(self, b: Dd) -> Dd {
        let (s, e) = two_sum(self.hi, b.hi);
        let (t, f) = two_sum(self.lo, b.lo);
        let (s, e) = quick_two_sum(s, e + t);
        let (hi, lo) = quick_two_sum(s, e + f);
        Dd { hi, lo }
    }
}

impl Sub for Dd {
    type Output = Dd;
    #[inline]
    fn sub(self, b: Dd) -> Dd {
        self + -b
    }
}

impl Mul for Dd {
    type Output = Dd;
    #[inline]
    fn mul(self, b: Dd) -> Dd {
        let (p, e) = two_prod(self.hi, b.hi);
        let (hi, lo) = quick_two_sum(p, e + (self.hi * b.lo + self.lo * b.hi));
        Dd { hi, lo }
    }
}

impl Mul<f64> for Dd {
    type Output = Dd;
    #[inline]
    fn mul(self, b: f64) -> Dd {
        let (p, e) = two_prod(self.hi, b);
        let (hi, lo) = quick_two_sum(p, e + self.lo * b);
        Dd { hi, lo }
    }
}

impl Div for Dd {
    type Output = Dd;
    /// Division (two quotient digits, relative error about `2^-104`).
    #[inline]
    fn div(self, b: Dd) -> Dd {
        let q1 = self.hi / b.hi;
        let r = self - b * q1;
        let q2 = r.hi / b.hi;
        let (hi, lo) = quick_two_sum(q1, q2);
        Dd { hi, lo }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sine and cosine against the f64 library at f64 resolution, and against the identity
    /// `sin^2 + cos^2 = 1` and `sin(2x) = 2 sin x cos x` at double-double resolution.
    #[test]
    fn sin_cos_is_accurate() {
        for &x in &[
            0.0,
            1e-300,
            1e-8,
            0.3,
            std::f64::consts::FRAC_PI_4,
            1.0,
            1.5,
            FRAC_PI_2.hi,
        ] {
            let (s, c) = Dd::from_f64(x).sin_cos();
            assert!((s.hi - x.sin()).abs() <= f64::EPSILON * x.sin().abs().max(1e-300));
            assert!((c.hi - x.cos()).abs() <= f64::EPSILON);
            let one = s * s + c * c - Dd::ONE;
            assert!(one.abs() < 1e-30, "x {x}: {one:?}");
            if x <= 0.75 {
                let (s2, _) = Dd::from_f64(2.0 * x).sin_cos();
                let d = s2 - s * c * 2.0;
                assert!(d.abs() <= 1e-30 * s2.abs().max(1e-300), "x {x}: {d:?}");
            }
        }
        let (s, c) = (-Dd::from_f64(0.3)).sin_cos();
        assert_eq!((s, c), {
            let (s, c) = Dd::from_f64(0.3).sin_cos();
            (-s, c)
        });
    }
}
