//! Fully normalized associated Legendre functions `Pbar_lm(theta) = A_lm P_l^m(cos theta)`,
//! with the Condon-Shortley phase in `P_l^m` (PSH (1)), so that `Y_lm = Pbar_lm e^{i m phi}`.
//!
//! The recursion (derivation and stability argument in `proofs/legendre-recursion.md`):
//! - `Pbar_00 = 1/sqrt(4 pi)`,
//! - `Pbar_mm = -sqrt((2m+1)/(2m)) sin(theta) Pbar_{m-1,m-1}` (the diagonal),
//! - `Pbar_lm = a_lm ((Pbar_{l-1,m} - Pbar_{l-2,m} / a_{l-1,m}) - u Pbar_{l-1,m})`, with
//!   `a_lm = sqrt((4l^2 - 1)/(l^2 - m^2))`, `Pbar_{m-1,m} = 0` and `u = 1 - cos(theta)`,
//!
//! the usual column recursion with `cos theta` written `1 - u`. It runs in the northern
//! hemisphere only (the southern one by `Pbar_lm(pi - theta) = (-1)^{l+m} Pbar_lm(theta)`,
//! DLMF 14.7.17), where `u = 2 sin^2(theta/2)` keeps its full relative accuracy: near the
//! poles `cos theta` rounds to 1 and loses the information that the recursion amplifies
//! by `l^2`.
//!
//! The diagonal `Pbar_mm ~ sin^m(theta)` underflows long before the columns it starts
//! grow back to order one (at l = 2048 already for theta = 0.3). The diagonal and the
//! column recursions therefore carry a binary exponent beside the mantissa (the
//! "X-number" idea of Fukushima, J. Geodesy 86 (2012)): exact power-of-two rescaling,
//! so no digit is lost, and values are returned as ordinary `f64` (which may round to
//! zero where the true value is below the `f64` range, i.e. negligible).
//!
//! Two precisions share that code: [`Legendre`] (tabulated `f64` coefficients, the fast
//! path of transforms and batch evaluation) and [`for_each_column_accurate`]
//! (double-double state and coefficients, for single directions at very high degree,
//! where the `f64` recursion's rounding error would pass `1e-12`: near the poles `u` is
//! of the order of the rounding of the other terms and its effect, amplified like `l^2`,
//! is lost; measured in `psh verify` (`sh.fast_path_l2048`, `sh.band_norm_l2048`).

use crate::error::Result;
use crate::geometry::check_theta;
use crate::sh::index::check_lmax;
use crate::sh::recursion::double_double::Dd;
use std::ops::{Mul, Sub};

/// Exponent step of the scaled recursion: values are `mantissa * 2^(-SCALE_BITS * k)`.
pub(crate) const SCALE_BITS: i32 = 600;
/// `2^SCALE_BITS` and its inverse.
pub(crate) const BIG: f64 = f64::from_bits(((1023 + SCALE_BITS) as u64) << 52);
pub(crate) const SMALL: f64 = f64::from_bits(((1023 - SCALE_BITS) as u64) << 52);

/// A polar angle reduced to the northern hemisphere: `cos >= 0`, `sin >= 0`,
/// `vers = 1 - cos` to full relative accuracy, and whether it was mirrored from the south.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polar {
    /// `cos theta'` with `theta' = min(theta, pi - theta)`.
    cos: f64,
    /// `sin theta'`.
    sin: f64,
    /// `1 - cos theta'`.
    vers: f64,
    /// `theta > pi/2`: values take the factor `(-1)^{l+m}`.
    south: bool,
    /// Low parts of `sin` and `vers` (double-double), zero unless built by
    /// [`Polar::from_theta_accurate`].
    lo: [f64; 2],
}

impl Polar {
    /// From a polar angle in `[0, pi]` (not validated: callers check it).
    pub fn from_theta(theta: f64) -> Self {
        let (t, south) = northern(theta);
        let t = t.hi;
        let (s, c) = t.sin_cos();
        let h = (0.5 * t).sin();
        Self {
            cos: c,
            sin: s,
            vers: 2.0 * h * h,
            south,
            lo: [0.0; 2],
        }
    }

    /// From a polar angle, with `sin` and `vers` to double-double accuracy: the values
    /// are then those at exactly the given `f64` angle, not at its sine rounded to `f64`
    /// (whose relative error would grow `m`-fold in `sin^m theta`).
    pub fn from_theta_accurate(theta: f64) -> Self {
        let (t, south) = northern(theta);
        let (s, c) = t.sin_cos();
        let h = (t * 0.5).sin_cos().0;
        let v = h * h * 2.0;
        Self {
            cos: c.hi,
            sin: s.hi,
            vers: v.hi,
            south,
            lo: [s.lo, v.lo],
        }
    }

    /// From the z component and `rho = sqrt(x^2 + y^2)` of a unit direction.
    pub fn from_z_rho(z: f64, rho: f64) -> Self {
        let c = z.abs();
        Self {
            cos: c,
            sin: rho,
            vers: rho * rho / (1.0 + c),
            south: z < 0.0,
            lo: [0.0; 2],
        }
    }
}

/// The lower part of pi in double-double: `pi = PI + PI_LO` to about 1e-32.
const PI_LO: f64 = 1.2246467991473532e-16;

/// `theta` reflected into `[0, pi/2]` as a double-double, and whether it was reflected.
/// `pi - theta = (PI - theta) + PI_LO`, where `PI - theta` is exact (Sterbenz) for
/// `theta` in `[pi/2, pi]`: at `theta = PI` (an f64 short of pi by `PI_LO`) the reflected
/// angle is `PI_LO`, not 0.
fn northern(theta: f64) -> (Dd, bool) {
    if theta > std::f64::consts::FRAC_PI_2 {
        (Dd::sum(std::f64::consts::PI - theta, PI_LO), true)
    } else {
        (Dd::from_f64(theta), false)
    }
}

/// Arithmetic the column recursion needs: `f64`, or double-double for the accurate path.
trait Arith: Copy + Sub<Output = Self> + Mul<Output = Self> + Mul<f64, Output = Self> {
    fn of(x: f64) -> Self;
    fn of2(hi: f64, lo: f64) -> Self;
    fn to_f64(self) -> f64;
}

impl Arith for f64 {
    #[inline(always)]
    fn of(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn of2(hi: f64, lo: f64) -> Self {
        hi + lo
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
}

impl Arith for Dd {
    #[inline(always)]
    fn of(x: f64) -> Self {
        Dd::from_f64(x)
    }
    #[inline(always)]
    fn of2(hi: f64, lo: f64) -> Self {
        Dd::sum(hi, lo)
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self.hi + self.lo
    }
}

/// Walks the columns of the recursion, whatever the arithmetic: the diagonal with its
/// exponent, then each column into `buf`, mirrored to the south when needed.
fn walk_columns<T: Arith>(
    lmax: usize,
    mmax: usize,
    polar: Polar,
    zonal: Option<&[[f64; 3]]>,
    diag_factor: impl Fn(usize) -> T,
    coefficients: impl Fn(usize, usize) -> (T, T),
    mut f: impl FnMut(usize, &[f64]),
) {
    let mut buf = vec![0.0; lmax + 1];
    let u = T::of2(polar.vers, polar.lo[1]);
    let sin = T::of2(polar.sin, polar.lo[0]);
    let mut diag = T::of(0.5 / std::f64::consts::PI.sqrt());
    let mut diag_exp: i32 = 0;
    for m in 0..=mmax {
        if m > 0 {
            diag = diag * diag_factor(m) * sin;
            let d = diag.to_f64();
            if d != 0.0 && d.abs() < SMALL {
                diag = diag * BIG;
                diag_exp -= SCALE_BITS;
            }
        }
        let out = &mut buf[..=lmax - m];
        if let (0, Some(table)) = (m, zonal) {
            zonal_column(
                table,
                [polar.vers],
                out.iter_mut().map(std::array::from_mut),
            );
            if polar.south {
                for o in out.iter_mut().skip(1).step_by(2) {
                    *o = -*o;
                }
            }
            f(m, out);
            continue;
        }
        let (mut p2, mut p1) = (T::of(0.0), diag);
        let mut exp = diag_exp;
        out[0] = descale(p1.to_f64(), exp);
        for (k, o) in out.iter_mut().enumerate().skip(1) {
            let (a, b) = coefficients(m, k);
            let p = a * ((p1 - b * p2) - u * p1);
            p2 = p1;
            p1 = p;
            if exp < 0 && p1.to_f64().abs() > BIG {
                p1 = p1 * SMALL;
                p2 = p2 * SMALL;
                exp += SCALE_BITS;
            }
            *o = descale(p1.to_f64(), exp);
        }
        if polar.south {
            for o in out.iter_mut().skip(1).step_by(2) {
                *o = -*o;
            }
        }
        f(m, out);
    }
}

/// Double-double walk of the columns `m = 0..=lmax` (see [`Legendre::for_each_column`]),
/// with recursion coefficients computed on the fly in double-double: slower (about ten
/// times) but accurate to a few `1e-15` at any degree up to [`crate::sh::MAX_DEGREE`].
pub fn for_each_column_accurate(lmax: usize, polar: Polar, f: impl FnMut(usize, &[f64])) {
    columns_accurate(lmax, lmax, polar, f)
}

/// `P_l(t)` for `l < p.len()` by Bonnet's recurrence (DLMF 14.10.3 at `m = 0`) and, when
/// `dp` is given (of the same length), `P_l'(t)` by `P_{l+1}' = P_{l-1}' + (2l+1) P_l`
/// (DLMF 14.10.4 at `m = 0`); `|t| <= 1`.
pub fn legendre_polynomials(t: f64, p: &mut [f64], mut dp: Option<&mut [f64]>) {
    for l in 0..p.len() {
        let lf = l as f64;
        p[l] = match l {
            0 => 1.0,
            1 => t,
            _ => ((2.0 * lf - 1.0) * t * p[l - 1] - (lf - 1.0) * p[l - 2]) / lf,
        };
        if let Some(dp) = dp.as_deref_mut() {
            dp[l] = match l {
                0 => 0.0,
                1 => 1.0,
                _ => dp[l - 2] + (2.0 * lf - 1.0) * p[l - 1],
            };
        }
    }
}

/// `Pbar_l0(theta)`, `l <= lmax`, by the accurate path (column `m = 0` only).
pub fn zonal_legendre(lmax: usize, theta: f64) -> Vec<f64> {
    let mut out = Vec::new();
    columns_accurate(lmax, 0, Polar::from_theta_accurate(theta), |_, col| {
        out = col.to_vec()
    });
    out
}

/// Accurate walk of the columns `m <= mmax`.
fn columns_accurate(lmax: usize, mmax: usize, polar: Polar, f: impl FnMut(usize, &[f64])) {
    // Squares of the coefficients are ratios of integers exact in f64 (l <= MAX_DEGREE),
    // so one double-double quotient and one square root give them to ~1e-32.
    let a_squared = |l: usize, m: usize| -> (f64, f64) {
        let (l, m) = (l as f64, m as f64);
        (4.0 * l * l - 1.0, (l - m) * (l + m))
    };
    walk_columns(
        lmax,
        mmax,
        polar,
        None,
        |m| -Dd::quotient((2 * m + 1) as f64, (2 * m) as f64).sqrt(),
        |m, k| {
            let l = m + k;
            let (num, den) = a_squared(l, m);
            let inv_prev = if k == 1 {
                Dd::ZERO
            } else {
                let (pn, pd) = a_squared(l - 1, m);
                Dd::quotient(pd, pn).sqrt()
            };
            (Dd::quotient(num, den).sqrt(), inv_prev)
        },
        f,
    );
}

/// `Pbar_mm / Pbar_{m-1,m-1} = -sqrt((2m+1)/(2m)) sin theta` without the `sin theta`:
/// the diagonal factor of the normalized recursion, `m >= 1`.
pub(crate) fn diagonal_factor(m: usize) -> f64 {
    -((2 * m + 1) as f64 / (2 * m) as f64).sqrt()
}

/// Recursion coefficients of the normalized Legendre functions up to degree `lmax`.
///
/// Building the table costs `O(lmax^2)` square roots and `16 (lmax+1)(lmax+2)/2` bytes;
/// it is then shared by every evaluation (directions, quadrature rings, transforms).
#[derive(Clone, Debug)]
pub struct Legendre {
    lmax: usize,
    /// For column m, entries `(l - m)` for `l = m..=lmax`: `[a_lm, 1/a_{l-1,m}]`
    /// (`a_mm` and `1/a_{m-1,m}` are unused and stored as 0).
    ab: Vec<[f64; 2]>,
    /// Start of column m in `ab`.
    offsets: Vec<usize>,
    /// `-sqrt((2m+1)/(2m))`, the diagonal factor (index 0 unused).
    diag: Vec<f64>,
    /// The zonal column's difference form: `[(l-1)/l, (2l-1)/l, sqrt((2l+1)/(4 pi))]`
    /// for `l = 0..=lmax` ([`zonal_column`]).
    zonal: Vec<[f64; 3]>,
}

impl Legendre {
    /// Tables for all degrees `l <= lmax`.
    pub fn new(lmax: usize) -> Result<Self> {
        check_lmax(lmax)?;
        let mut ab = Vec::with_capacity((lmax + 1) * (lmax + 2) / 2);
        let mut offsets = Vec::with_capacity(lmax + 1);
        for m in 0..=lmax {
            offsets.push(ab.len());
            ab.push([0.0, 0.0]);
            let mut prev_a = 0.0f64;
            for l in m + 1..=lmax {
                let (lf, mf) = (l as f64, m as f64);
                let a = ((4.0 * lf * lf - 1.0) / ((lf - mf) * (lf + mf))).sqrt();
                let inv_prev = if l == m + 1 { 0.0 } else { 1.0 / prev_a };
                ab.push([a, inv_prev]);
                prev_a = a;
            }
        }
        let diag = (0..=lmax)
            .map(|m| if m == 0 { 0.0 } else { diagonal_factor(m) })
            .collect();
        let zonal = (0..=lmax)
            .map(|l| {
                let lf = l as f64;
                let norm = ((2.0 * lf + 1.0) / (4.0 * std::f64::consts::PI)).sqrt();
                if l == 0 {
                    [0.0, 0.0, norm]
                } else {
                    [(lf - 1.0) / lf, (2.0 * lf - 1.0) / lf, norm]
                }
            })
            .collect();
        Ok(Self {
            lmax,
            ab,
            offsets,
            diag,
            zonal,
        })
    }

    /// The largest degree of the table.
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// The diagonal factor `-sqrt((2m+1)/(2m))` of order `m >= 1`.
    pub(crate) fn diagonal(&self, m: usize) -> f64 {
        self.diag[m]
    }

    /// Recursion coefficients `[a_lm, 1/a_{l-1,m}]` of column `m`, for `l = m..=lmax`.
    #[inline]
    pub(crate) fn column_coefficients(&self, m: usize) -> &[[f64; 2]] {
        let start = self.offsets[m];
        &self.ab[start..start + self.lmax + 1 - m]
    }

    /// Walks the columns `m = 0..=lmax` at one polar angle, calling `f(m, column)` where
    /// `column[l - m] = Pbar_lm`. Inputs are not validated here (hot loop): callers
    /// validate angles or directions once.
    pub fn for_each_column(&self, polar: Polar, f: impl FnMut(usize, &[f64])) {
        walk_columns(
            self.lmax,
            self.lmax,
            polar,
            Some(&self.zonal),
            |m| self.diag[m],
            |m, k| {
                let [a, b] = self.column_coefficients(m)[k];
                (a, b)
            },
            f,
        );
    }

    /// Walks the columns at `N` polar angles at once: `f(m, column)` with
    /// `column[l - m][j] = Pbar_lm` at `polars[j]`.
    ///
    /// The `N` recursions run in lock step (independent chains keep the FPU pipelines
    /// full and vectorize). The exponent bookkeeping of the scaled recursion is done once
    /// per block of `LANE_BLOCK` steps instead of at every step: within a block a value
    /// grows by at most `a_lm^16 < 2^200`, far inside the `2^423` head room above `BIG`.
    /// `scratch` holds the column (resized to `lmax + 1` rows; reuse it across calls).
    /// Inlined, so that it runs in the instruction set of a caller compiled per
    /// instruction set (the batch SH's polar kernel).
    #[inline(always)]
    pub fn for_each_column_lanes<const N: usize>(
        &self,
        polars: &[Polar; N],
        scratch: &mut Vec<[f64; N]>,
        mut f: impl FnMut(usize, &[[f64; N]]),
    ) {
        let lmax = self.lmax;
        scratch.resize(lmax + 1, [0.0; N]);
        let buf = scratch;
        let sin: [f64; N] = std::array::from_fn(|j| polars[j].sin);
        let u: [f64; N] = std::array::from_fn(|j| polars[j].vers);
        let sign: [f64; N] = std::array::from_fn(|j| if polars[j].south { -1.0 } else { 1.0 });
        let mut diag = [0.5 / std::f64::consts::PI.sqrt(); N];
        let mut diag_exp = [0i32; N];
        for m in 0..=lmax {
            if m > 0 {
                let g = self.diag[m];
                for j in 0..N {
                    diag[j] *= g * sin[j];
                    if diag[j] != 0.0 && diag[j].abs() < SMALL {
                        diag[j] *= BIG;
                        diag_exp[j] -= SCALE_BITS;
                    }
                }
            }
            let col = &mut buf[..=lmax - m];
            if m == 0 {
                zonal_column(&self.zonal, u, col.iter_mut());
                for o in col.iter_mut().skip(1).step_by(2) {
                    for j in 0..N {
                        o[j] *= sign[j];
                    }
                }
                f(m, col);
                continue;
            }
            let ab = self.column_coefficients(m);
            let (mut p1, mut p2) = (diag, [0.0f64; N]);
            let mut exp = diag_exp;
            let mut scaled = exp.iter().any(|&e| e < 0);
            let (mut fe, mut fo) = if scaled {
                lane_factors(&exp, &sign)
            } else {
                ([1.0; N], sign)
            };
            for j in 0..N {
                col[0][j] = p1[j] * fe[j];
            }
            let mut k = 1;
            while k < col.len() {
                let end = (k + LANE_BLOCK).min(col.len());
                for kk in k..end {
                    let [a, b] = ab[kk];
                    let fk = if kk % 2 == 0 { &fe } else { &fo };
                    let out = &mut col[kk];
                    for j in 0..N {
                        let p = a * ((p1[j] - b * p2[j]) - u[j] * p1[j]);
                        p2[j] = p1[j];
                        p1[j] = p;
                        out[j] = p * fk[j];
                    }
                }
                if scaled {
                    scaled = rescale_lanes(&mut p1, &mut p2, &mut exp);
                    (fe, fo) = lane_factors(&exp, &sign);
                }
                k = end;
            }
            f(m, col);
        }
    }
}

/// The zonal column `Pbar_l0 = sqrt((2l+1)/(4 pi)) P_l(cos theta)`, `l = 0..`, at `N`
/// northern polar angles given by `u = 1 - cos theta`, into `out` (one row per degree),
/// by Bonnet's recurrence in Reinsch's difference form (`proofs/legendre-recursion.md`,
/// "The zonal column near the poles"): `delta_l = ((l-1) delta_{l-1} - (2l-1) u P_{l-1}) / l`,
/// `P_l = P_{l-1} + delta_l`. Near a pole `P_l = 1 - l(l+1) u / 2 + ...`: the
/// three-term form adds `u P_{l-1}` to numbers of order one at every step and loses it
/// below `u ~ eps` (a relative error `l^2 u / 2`, 2.6e-11 at `l = 1024`, `theta = 1e-8`),
/// where the differences carry it to full relative accuracy.
fn zonal_column<'a, const N: usize>(
    table: &[[f64; 3]],
    u: [f64; N],
    out: impl Iterator<Item = &'a mut [f64; N]>,
) {
    let (mut p, mut delta) = ([1.0f64; N], [0.0f64; N]);
    for ([c1, c2, norm], o) in table.iter().zip(out) {
        for j in 0..N {
            delta[j] = c1 * delta[j] - c2 * u[j] * p[j];
            p[j] += delta[j];
            o[j] = norm * p[j];
        }
    }
}

/// Steps of the lane recursion between exponent checks.
pub const LANE_BLOCK: usize = 16;

/// Output factors `2^exp` (zero at `exp <= -1200`, where the true value is below
/// `2^(605 - 1200)`, negligible against band maxima of order one) for even and odd `l - m`, the odd ones with the mirror sign.
#[inline]
fn lane_factors<const N: usize>(exp: &[i32; N], sign: &[f64; N]) -> ([f64; N], [f64; N]) {
    let fe = lane_scale(exp);
    let fo = std::array::from_fn(|j| fe[j] * sign[j]);
    (fe, fo)
}

/// Brings lanes whose recursion has climbed back to `|p1| >= 1` one scale step up
/// (`p * 2^-SCALE_BITS`, `exp + SCALE_BITS`); returns whether any lane is still scaled.
#[inline]
pub(crate) fn rescale_lanes<const N: usize>(
    p1: &mut [f64; N],
    p2: &mut [f64; N],
    exp: &mut [i32; N],
) -> bool {
    for j in 0..N {
        if exp[j] < 0 && p1[j].abs() >= 1.0 {
            p1[j] *= SMALL;
            p2[j] *= SMALL;
            exp[j] += SCALE_BITS;
        }
    }
    exp.iter().any(|&e| e < 0)
}

/// Output factors `2^exp` of lanes: 1, `2^-SCALE_BITS`, or zero below (values there are
/// under `2^(-SCALE_BITS)`, negligible against band maxima of order one).
#[inline]
pub(crate) fn lane_scale<const N: usize>(exp: &[i32; N]) -> [f64; N] {
    std::array::from_fn(|j| match exp[j] {
        0 => 1.0,
        e if e == -SCALE_BITS => SMALL,
        _ => 0.0,
    })
}

/// `p * 2^exp` for `exp` a non-positive multiple of `SCALE_BITS` and `|p| <= 2^SCALE_BITS`,
/// without intermediate underflow to zero of the scale factor.
#[inline]
pub(crate) fn descale(mut p: f64, mut exp: i32) -> f64 {
    while exp < 0 && p != 0.0 {
        p *= SMALL;
        exp += SCALE_BITS;
    }
    p
}

/// Index of `(l, m)`, `0 <= m <= l`, in the triangular order `l (l + 1) / 2 + m`.
#[inline]
pub const fn tri_index(l: usize, m: usize) -> usize {
    l * (l + 1) / 2 + m
}

/// All `Pbar_lm(theta)`, `0 <= m <= l <= lmax`, in triangular order [`tri_index`]
/// (accurate path).
pub fn legendre_all(lmax: usize, theta: f64) -> Result<Vec<f64>> {
    check_theta(theta)?;
    check_lmax(lmax)?;
    let mut out = vec![0.0; tri_index(lmax, lmax) + 1];
    for_each_column_accurate(lmax, Polar::from_theta_accurate(theta), |m, col| {
        for (k, &v) in col.iter().enumerate() {
            out[tri_index(m + k, m)] = v;
        }
    });
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Closed forms of low degrees (DLMF 14.5, with A_lm of PSH (1)).
    #[test]
    fn low_degrees_match_closed_forms() {
        for &t in &[0.0, 0.2, 1.0, PI / 2.0, 2.5, PI] {
            let p = legendre_all(2, t).unwrap();
            let (s, c) = (t.sin(), t.cos());
            let k = 1.0 / (4.0 * PI);
            let expect = [
                k.sqrt(),
                (3.0 * k).sqrt() * c,
                -(3.0 * k / 2.0).sqrt() * s,
                (5.0 * k).sqrt() * 0.5 * (3.0 * c * c - 1.0),
                -(15.0 * k / 2.0).sqrt() * s * c,
                (15.0 * k / 8.0).sqrt() * s * s,
            ];
            for (a, b) in p.iter().zip(expect) {
                assert!((a - b).abs() < 1e-15, "theta {t}: {a} vs {b}");
            }
        }
    }

    /// The addition theorem at coincident points, sum_m |Y_lm|^2 = (2l+1)/(4 pi), checks every
    /// m of a band at once, including columns that start below the f64 range.
    #[test]
    fn band_sums_hold_at_high_degree() {
        let lmax = 3000;
        for &t in &[1e-300, 1e-8, 0.3, PI / 2.0, PI - 1e-8] {
            let p = legendre_all(lmax, t).unwrap();
            for l in [0, 1, 17, 1000, 2048, 3000] {
                let mut sum = p[tri_index(l, 0)].powi(2);
                for m in 1..=l {
                    sum += 2.0 * p[tri_index(l, m)].powi(2);
                }
                let expect = (2 * l + 1) as f64 / (4.0 * PI);
                assert!(
                    ((sum - expect) / expect).abs() < 1e-12,
                    "theta {t} l {l}: {sum} vs {expect}"
                );
            }
        }
    }

    #[test]
    fn bad_input_is_an_error() {
        assert!(legendre_all(4, f64::NAN).is_err());
        assert!(legendre_all(4, -0.1).is_err());
        assert!(legendre_all(crate::sh::MAX_DEGREE + 1, 0.1).is_err());
    }
}
