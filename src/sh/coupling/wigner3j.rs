//! Wigner 3j symbols `(l1 l2 l3; m1 m2 m3)` as in DLMF §34.2 (Racah's formula, DLMF 34.2.4),
//! with `(l1 l2 l1+l2; m1 m2 -m1-m2)` of sign `(-1)^{l1-l2+m1+m2}` (DLMF 34.3.6).
//!
//! [`wigner_3j_row`] gives all `(l1 l2 l3; m1 m2 -m1-m2)` for
//! `l3 = max(|l1-l2|, |m1+m2|) ..= l1+l2` at once, by the three-term recursion in `l3` of
//! Schulten & Gordon (1975), run from both ends towards the middle and matched there (see
//! `proofs/wigner3j-recursion.md`); [`wigner_3j`] gives a single symbol.
//!
//! # Argument order
//! Every 3j and Gaunt function of the crate takes `(l, m)` pairs: `wigner_3j(l1, m1, l2, m2,
//! l3, m3)` is `(l1 l2 l3; m1 m2 m3)`, `wigner_3j_row(l1, m1, l2, m2)` its row over `l3`, as
//! `gaunt(l1, m1, l2, m2, l3, m3)` and `crate::exact::wigner3j::wigner_3j_exact`.
//!
//! # Accuracy and limits
//! Degrees up to [`MAX_GAUNT_DEGREE`] are accepted. The recursion runs in double-double
//! arithmetic (`sh::recursion::double_double`, about 106 bits) on values rescaled by
//! exact powers of two, so nothing overflows and the only sizeable error of a 3j symbol is
//! its final rounding to f64: against exact values (Racah's formula in rational arithmetic,
//! `crate::exact::wigner3j`) the symbols are within one ulp, in practice correctly rounded,
//! up to degree 8192 (tests `f64_rows_are_within_one_ulp_at_large_degrees` and
//! `tests/properties/gaunt_oracle.rs`). Symbols whose magnitude is below about `1e-300` come out as
//! subnormal numbers or zero; a nontrivial zero (one no selection rule predicts, e.g.
//! `(3 3 2; -2 2 0)`) comes out near `1e-32` times the row's scale rather than exactly zero.
//! Selection rules (sum of the `m`, triangle inequality, parity of `l1+l2+l3` when all `m`
//! vanish) give exact zeros without computation. Cost: about 60-120 ns per symbol of a row
//! (double-double with and without hardware FMA).

use crate::error::{Error, Result};
use crate::sh::index::MAX_DEGREE;
use crate::sh::recursion::double_double::Dd;

/// Largest degree accepted by the 3j and Gaunt routines, for each of `l1, l2, l3`: twice
/// [`MAX_DEGREE`], so that the product of two expansions of degree `MAX_DEGREE` can be
/// coupled. (A row of [`wigner_3j_row`] reaches `l3 = l1 + l2`.)
pub const MAX_GAUNT_DEGREE: usize = 2 * MAX_DEGREE;

/// Rows are rescaled by `2^-RESCALE_EXP` whenever an element exceeds `2^RESCALE_EXP`.
const RESCALE_EXP: i32 = 300;

// ---------------------------------------------------------------------------------------
// Input checks
// ---------------------------------------------------------------------------------------

/// Checks `l <= MAX_GAUNT_DEGREE` and `|m| <= l`, naming the offending argument.
pub(super) fn check_degree_order(
    lname: &'static str,
    mname: &'static str,
    l: usize,
    m: i64,
) -> Result<()> {
    if l > MAX_GAUNT_DEGREE {
        return Err(Error::DegreeOutOfRange {
            name: lname,
            value: l as i128,
            reason: format!(
                "the largest degree supported by the 3j/Gaunt routines is {MAX_GAUNT_DEGREE}"
            ),
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

/// Triangle condition `|l1-l2| <= l3 <= l1+l2` (DLMF §34.2).
pub(super) fn triangle(l1: usize, l2: usize, l3: usize) -> bool {
    l1.abs_diff(l2) <= l3 && l3 <= l1 + l2
}

// ---------------------------------------------------------------------------------------
// 3j recursion
// ---------------------------------------------------------------------------------------

/// Coefficients of the three-term recursion in `j = l3` for fixed `(l1, m1, l2, m2)`,
/// `m3 = -m1-m2` (Schulten & Gordon (1975), Sec. II; restated in Luscombe & Luban (1998)):
///
/// `j A(j+1) f(j+1) + B(j) f(j) + (j+1) A(j) f(j-1) = 0`, with
/// `A(j) = sqrt[(j^2 - (l1-l2)^2) ((l1+l2+1)^2 - j^2) (j^2 - m3^2)]`,
/// `B(j) = -(2j+1) [m3 (l1(l1+1) - l2(l2+1)) - j(j+1)(m2-m1)]`.
///
/// `A(j)^2` is formed exactly as a double-double from three integer factors below `2^32`
/// (exact in `f64`), `B(j)` from two integer factors below `2^53`; no rounding happens before the
/// square root of `A(j)^2`.
struct Recursion {
    d: i64,
    s: i64,
    m3: i64,
    c_b: i64,
    dm: i64,
}

impl Recursion {
    fn new(l1: i64, m1: i64, l2: i64, m2: i64) -> Self {
        let m3 = -(m1 + m2);
        Recursion {
            d: l1 - l2,
            s: l1 + l2 + 1,
            m3,
            c_b: l1 * (l1 + 1) - l2 * (l2 + 1),
            dm: m2 - m1,
        }
    }
    /// `A(j)`, for `j >= max(|l1 - l2|, |m3|)` (where every factor is non-negative).
    #[inline]
    fn a(&self, j: i64) -> Dd {
        let f1 = ((j - self.d) * (j + self.d)) as f64;
        let f2 = ((self.s - j) * (self.s + j)) as f64;
        let f3 = ((j - self.m3) * (j + self.m3)) as f64;
        // f1 f2 < 2^64 exact; e f3 exact for its low part e < 2^12.
        (Dd::product(f1, f2) * f3).sqrt()
    }
    #[inline]
    fn b(&self, j: i64) -> Dd {
        let inner = (self.m3 * self.c_b - j * (j + 1) * self.dm) as f64; // |.| < 2^53
        Dd::product(-((2 * j + 1) as f64), inner)
    }
}

/// Multiplies `values` by `2^-RESCALE_EXP` (exact).
fn rescale(values: &mut [Dd]) {
    let f = 2f64.powi(-RESCALE_EXP);
    for v in values {
        *v = v.scale(f);
    }
}

/// Least-squares factor `c` minimizing `sum_k |c x_k - y_k|^2` over a short window, with both
/// windows pre-scaled to unit maximum (for range safety): returns `(c_x, c_y)` such that
/// `c_x x ≈ c_y y` with `c_y = 1 / max|y|`.
fn match_factors(x: &[Dd], y: &[Dd]) -> (Dd, Dd) {
    let sx = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let sy = y.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    // Exact power-of-two pre-scaling.
    let px = 2f64.powi(-(sx.log2().floor() as i32));
    let py = 2f64.powi(-(sy.log2().floor() as i32));
    let (mut sxx, mut sxy) = (Dd::ZERO, Dd::ZERO);
    for (a, b) in x.iter().zip(y) {
        let (a, b) = (a.scale(px), b.scale(py));
        sxx = sxx + a * a;
        sxy = sxy + a * b;
    }
    ((sxy / sxx).scale(px), Dd::from_f64(py))
}

thread_local! {
    /// Scratch space of the row recursion (two solutions of the row's length).
    static SCRATCH: std::cell::RefCell<Vec<Dd>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The row `(l1 l2 l3; m1 m2 -m1-m2)`, `l3 = l3_min ..= l1+l2`, written into `out`; returns
/// `l3_min`. Inputs must already satisfy `|m1| <= l1`, `|m2| <= l2`, degrees in range.
pub(super) fn row_unchecked(l1: usize, m1: i64, l2: usize, m2: i64, out: &mut Vec<f64>) -> usize {
    SCRATCH.with(|s| {
        let mut s = s.borrow_mut();
        row_dd(l1, m1, l2, m2, &mut s, out)
    })
}

fn row_dd(l1: usize, m1: i64, l2: usize, m2: i64, buf: &mut Vec<Dd>, out: &mut Vec<f64>) -> usize {
    let (j1, j2) = (l1 as i64, l2 as i64);
    let m3 = -(m1 + m2);
    let jmin = (j1 - j2).abs().max(m3.abs());
    let jmax = j1 + j2;
    let n = (jmax - jmin + 1) as usize;
    let big = 2f64.powi(RESCALE_EXP);
    let rec = Recursion::new(j1, m1, j2, m2);

    // Scratch layout: f | g | B | C1 | C2, each of length n, indexed by k = j - jmin, with the
    // recursion written as C2[k] f(j+1) + B[k] f(j) + C1[k] f(j-1) = 0,
    // C1[k] = (j+1) A(j), C2[k] = j A(j+1); each A(j) is computed once.
    buf.clear();
    buf.resize(5 * n, Dd::ZERO);
    let (f, rest) = buf.split_at_mut(n);
    let (g, rest) = rest.split_at_mut(n);
    let (bj, rest) = rest.split_at_mut(n);
    let (c1, c2) = rest.split_at_mut(n);
    let mut a_j = rec.a(jmin);
    for k in 0..n {
        let j = jmin + k as i64;
        let a_next = rec.a(j + 1);
        bj[k] = rec.b(j);
        c1[k] = a_j * (j + 1) as f64;
        c2[k] = a_next * j as f64;
        a_j = a_next;
    }

    // Sign of the (unnormalized) value at l3 = jmax, tracked separately since that value
    // may underflow relative to the largest one.
    let top_negative;
    // The row is assembled in f.
    if n == 1 {
        f[0] = Dd::ONE;
        top_negative = false;
    } else if m1 == m2 && (m1 == 0 || j1 == j2) {
        // B(j) vanishes identically: every other symbol is zero (for m1 = m2 = 0 by the parity
        // rule, for l1 = l2, m1 = m2 by the odd column permutation, DLMF 34.3.9), and the
        // recursion reduces to the two-step first-order recursion
        // f(j+1) = -(j+1) A(j) / (j A(j+1)) f(j-1), stable in either direction.
        f[0] = Dd::ONE;
        let mut k = 2;
        while k < n {
            f[k] = -(c1[k - 1] / c2[k - 1] * f[k - 2]);
            if f[k].abs() > big {
                rescale(&mut f[..=k]);
            }
            k += 2;
        }
        top_negative = f[n - 1].hi < 0.0;
    } else {
        // Two solutions of the recursion: `f` started at l3 = jmin (forward), `g` started at
        // l3 = jmax (backward).
        let kmax = n - 1;
        // f[k+1] from f[k], f[k-1].
        let forward = |k: usize, f: &mut [Dd]| {
            f[k + 1] = -((bj[k] * f[k] + c1[k] * f[k - 1]) / c2[k]);
            if f[k + 1].abs() > big {
                rescale(&mut f[..=k + 1]);
            }
        };
        // g[k-1] from g[k], g[k+1].
        let backward = |k: usize, g: &mut [Dd]| {
            g[k - 1] = -((bj[k] * g[k] + c2[k] * g[k + 1]) / c1[k]);
            if g[k - 1].abs() > big {
                rescale(&mut g[k - 1..]);
            }
        };

        // Which direction is stable where (see proofs/wigner3j-recursion.md): besides the
        // wanted solution W, the recursion has a second solution O that is singular at the
        // end the recursion starts from (A(jmin) = 0, A(jmax + 1) = 0), decaying away from it
        // like 1/distance. Recursing away from an end is stable as long as |W| does not decay
        // faster than O: through a non-classical region, where |W| grows, and into the
        // classical region, where both oscillate. Each direction is run while
        // |W(k)| / |W(k-1)| >= (d-1)/d at distance d from its start.
        //
        // Forward from l3 = jmin.
        f[0] = Dd::ONE;
        f[1] = if jmin == 0 {
            // jmin = 0 means l1 = l2 and m3 = 0: A(0) = 0 and the recursion at j = 0 is empty.
            // Start from the ratio (l l 1; m -m 0) / (l l 0; m -m 0) = m / sqrt(l(l+1))
            // (DLMF 34.3.1, 34.3.2).
            Dd::from_f64(m1 as f64) / Dd::from_f64((j1 * (j1 + 1)) as f64).sqrt()
        } else {
            // A(jmin) = 0 removes f(jmin - 1).
            -(bj[0] / c2[0])
        };
        let mut kf = 1; // highest computed index of f
        while kf < kmax - 1 && kf as f64 * f[kf].abs() >= (kf - 1) as f64 * f[kf - 1].abs() {
            forward(kf, f);
            kf += 1;
        }
        // Backward from l3 = jmax, where A(jmax + 1) = 0, down to the forward's range at most.
        g[kmax] = Dd::ONE;
        g[kmax - 1] = -(bj[kmax] / c1[kmax]);
        let mut kg = kmax - 1; // lowest computed index of g
        while kg > kf {
            let d = (kmax - kg) as f64; // distance of g[kg] from the start
            if d * g[kg].abs() < (d - 1.0) * g[kg + 1].abs() {
                break;
            }
            backward(kg, g);
            kg -= 1;
        }
        // Across the classical region in between, where both directions are neutrally
        // stable, each solution is carried to the middle.
        let kmid = ((kf - 1) + kg.max(kf)) / 2;
        let lo = kmid.saturating_sub(1);
        let hi = (kmid + 1).min(kmax);
        while kg > lo {
            backward(kg, g);
            kg -= 1;
        }
        while kf < hi {
            forward(kf, f);
            kf += 1;
        }
        // Match the two solutions on the window lo..=hi by least squares (robust to an
        // accidental zero at one point) and splice them at kmid.
        let (cf, cg) = match_factors(&f[lo..=hi], &g[lo..=hi]);
        for v in &mut f[..kmid] {
            *v = *v * cf;
        }
        for (v, &w) in f[kmid..].iter_mut().zip(&g[kmid..]) {
            *v = w * cg;
        }
        // The backward start value 1 was only scaled by positive factors since.
        top_negative = false;
    }

    // Normalize: sum_{l3} (2 l3 + 1) (3j)^2 = 1 (DLMF §34.3(iv), orthogonality in l3, m3);
    // sign: (l1 l2 l1+l2; m1 m2 m3) has sign (-1)^{l1-l2-m3} (DLMF 34.3.6).
    let row = f;
    let peak = row.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let p2 = 2f64.powi(-(peak.log2().floor() as i32));
    let mut acc = Dd::ZERO;
    for (k, v) in row.iter_mut().enumerate() {
        *v = v.scale(p2);
        acc = acc + *v * *v * (2 * (jmin + k as i64) + 1) as f64;
    }
    let want_negative = (j1 - j2 - m3).rem_euclid(2) == 1;
    let mut c = Dd::ONE / acc.sqrt();
    if want_negative != top_negative {
        c = -c;
    }
    out.clear();
    out.extend(row.iter().map(|&v| {
        let x = v * c;
        x.hi + x.lo
    }));
    jmin as usize
}

/// Wigner 3j symbols `(l1 l2 l3; m1 m2 m3)`, `m3 = -m1-m2`, for every `l3` in
/// `l3_min ..= l3_max` with `l3_min = max(|l1-l2|, |m1+m2|)`, `l3_max = l1+l2`.
#[derive(Clone, Debug, PartialEq)]
pub struct Wigner3jRow {
    l3_min: usize,
    values: Vec<f64>,
}

impl Wigner3jRow {
    /// Smallest `l3` of the row: `max(|l1-l2|, |m1+m2|)`.
    pub fn l3_min(&self) -> usize {
        self.l3_min
    }
    /// Largest `l3` of the row: `l1 + l2`.
    pub fn l3_max(&self) -> usize {
        self.l3_min + self.values.len() - 1
    }
    /// The symbols, `values()[i]` for `l3 = l3_min() + i`.
    pub fn values(&self) -> &[f64] {
        &self.values
    }
    /// The symbol for `l3`; zero outside `l3_min ..= l3_max` (selection rules).
    pub fn get(&self, l3: usize) -> f64 {
        if l3 < self.l3_min {
            return 0.0;
        }
        self.values.get(l3 - self.l3_min).copied().unwrap_or(0.0)
    }
    /// `(l3, symbol)` pairs in increasing `l3`.
    pub fn iter(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.values
            .iter()
            .enumerate()
            .map(move |(i, &v)| (self.l3_min + i, v))
    }
}

/// All Wigner 3j symbols `(l1 l2 l3; m1 m2 -m1-m2)` over `l3`, by the three-term recursion of
/// Schulten & Gordon (1975) in `l3` (coefficients in the private `Recursion`), run in
/// double-double arithmetic from both ends of the row towards the middle (each direction
/// where it is stable: through its non-classical region, then to the middle of the classical
/// one), matched by least squares on a three-point window, normalized by
/// `sum_{l3} (2 l3 + 1) (3j)^2 = 1` (DLMF §34.3(iv)) and signed by
/// `sgn (l1 l2 l1+l2; m1 m2 m3) = (-1)^{l1-l2-m3}` (DLMF 34.3.6); rounded to f64 at the end
/// (within one ulp of the exact values, see the module documentation).
/// See `proofs/wigner3j-recursion.md`.
///
/// Cost `O(min(l1, l2))` (the row length `l1 + l2 - l3_min + 1 <= 2 min(l1, l2) + 1`). Errors: [`Error::DegreeOutOfRange`] if `l1` or `l2` exceeds
/// [`MAX_GAUNT_DEGREE`], [`Error::OrderOutOfRange`] if `|m1| > l1` or `|m2| > l2`.
pub fn wigner_3j_row(l1: usize, m1: i64, l2: usize, m2: i64) -> Result<Wigner3jRow> {
    let mut values = Vec::new();
    let l3_min = wigner_3j_row_into(l1, m1, l2, m2, &mut values)?;
    Ok(Wigner3jRow { l3_min, values })
}

/// As [`wigner_3j_row`], writing the symbols into `out` (cleared first, capacity reused)
/// and returning `l3_min`; `out[i]` is the symbol for `l3 = l3_min + i`.
pub fn wigner_3j_row_into(
    l1: usize,
    m1: i64,
    l2: usize,
    m2: i64,
    out: &mut Vec<f64>,
) -> Result<usize> {
    check_degree_order("l1", "m1", l1, m1)?;
    check_degree_order("l2", "m2", l2, m2)?;
    Ok(row_unchecked(l1, m1, l2, m2, out))
}

/// One Wigner 3j symbol `(l1 l2 l3; m1 m2 m3)`, arguments in `(l, m)` pairs.
///
/// Exact zero, without computation, unless `m1+m2+m3 = 0`, the triangle condition
/// `|l1-l2| <= l3 <= l1+l2` holds, and (when `m1 = m2 = m3 = 0`) `l1+l2+l3` is even
/// (DLMF §34.2, 34.3.5). Otherwise the columns are permuted cyclically (DLMF 34.3.8, no sign)
/// so that the largest degree is the recursion variable, and the row of [`wigner_3j_row`] is
/// evaluated (cost `O(min(l1, l2, l3))`).
///
/// Errors: [`Error::DegreeOutOfRange`] for a degree above [`MAX_GAUNT_DEGREE`],
/// [`Error::OrderOutOfRange`] for `|m_i| > l_i`.
pub fn wigner_3j(l1: usize, m1: i64, l2: usize, m2: i64, l3: usize, m3: i64) -> Result<f64> {
    check_degree_order("l1", "m1", l1, m1)?;
    check_degree_order("l2", "m2", l2, m2)?;
    check_degree_order("l3", "m3", l3, m3)?;
    let mut buf = Vec::new();
    Ok(wigner_3j_checked(l1, m1, l2, m2, l3, m3, &mut buf))
}

/// [`wigner_3j`] after the input checks; `buf` is scratch space.
pub(super) fn wigner_3j_checked(
    l1: usize,
    m1: i64,
    l2: usize,
    m2: i64,
    l3: usize,
    m3: i64,
    buf: &mut Vec<f64>,
) -> f64 {
    if m1 + m2 + m3 != 0 || !triangle(l1, l2, l3) {
        return 0.0;
    }
    if m1 == 0 && m2 == 0 && (l1 + l2 + l3) % 2 == 1 {
        return 0.0;
    }
    // Cyclic permutation putting the largest degree last (DLMF 34.3.8).
    let (a, b, c, ma, mb) = if l3 >= l1 && l3 >= l2 {
        (l1, l2, l3, m1, m2)
    } else if l1 >= l2 {
        (l2, l3, l1, m2, m3)
    } else {
        (l3, l1, l2, m3, m1)
    };
    let cmin = row_unchecked(a, ma, b, mb, buf);
    buf[c - cmin]
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::random::pseudo_random;

    /// Compensated (Neumaier) sum accumulator.
    #[derive(Default)]
    struct Neumaier {
        sum: f64,
        comp: f64,
    }

    impl Neumaier {
        fn add(&mut self, x: f64) {
            let t = self.sum + x;
            if self.sum.abs() >= x.abs() {
                self.comp += (self.sum - t) + x;
            } else {
                self.comp += (x - t) + self.sum;
            }
            self.sum = t;
        }
        fn value(&self) -> f64 {
            self.sum + self.comp
        }
    }

    /// An integer in `lo..=hi` from `x` in `[-1, 1)` (a draw of
    /// [`crate::random::pseudo_random`]), uniform for uniform `x`.
    pub(crate) fn pick(x: f64, lo: i64, hi: i64) -> i64 {
        (lo + ((x + 1.0) * 0.5 * (hi - lo + 1) as f64) as i64).min(hi)
    }

    /// Rows and single symbols against the exact values (Racah's formula in rational
    /// arithmetic) of the committed fixture, through [`crate::verify::oracle`].
    /// Against the committed fixture (its reader is `psh verify`'s, feature `verify`).
    #[cfg(feature = "verify")]
    #[test]
    fn matches_the_exact_fixture() {
        use crate::verify::oracle::gaunt_entries;
        let mut max_err: f64 = 0.0;
        let entries = gaunt_entries("wigner3j").unwrap();
        for &(l, m, exact) in &entries {
            let row = wigner_3j_row(l[0], m[0], l[1], m[1]).unwrap();
            assert_eq!(row.l3_max(), l[0] + l[1]);
            assert_eq!(row.get(l[0] + l[1] + 1), 0.0);
            if row.l3_min() > 0 {
                assert_eq!(row.get(row.l3_min() - 1), 0.0);
            }
            let single = wigner_3j(l[0], m[0], l[1], m[1], l[2], m[2]).unwrap();
            max_err = max_err.max((row.get(l[2]) - exact).abs());
            max_err = max_err.max((single - exact).abs());
        }
        assert!(entries.len() > 1000);
        assert!(max_err < 1e-14, "max abs error vs Racah {max_err:e}");
    }

    #[test]
    fn special_closed_forms() {
        // DLMF 34.3.1: (l l 0; m -m 0) = (-1)^{l-m} / sqrt(2l+1), for l up to 5000.
        for &l in &[0usize, 1, 2, 7, 40, 333, 1000, 5000] {
            for &m in &[0i64, 1, -1, (l / 3) as i64, -(l as i64), l as i64] {
                if m.unsigned_abs() as usize > l {
                    continue;
                }
                let v = wigner_3j(l, m, l, -m, 0, 0).unwrap();
                let s = if (l as i64 - m).rem_euclid(2) == 0 {
                    1.0
                } else {
                    -1.0
                };
                let e = s / ((2 * l + 1) as f64).sqrt();
                assert!((v - e).abs() <= 1e-15 * e.abs(), "l={l} m={m}: {v} vs {e}");
                // DLMF 34.3.2: (l l 1; m -m 0) = (-1)^{l-m} 2m / sqrt(2l(2l+1)(2l+2)).
                if l >= 1 {
                    let v1 = wigner_3j(l, m, l, -m, 1, 0).unwrap();
                    let e1 = s * 2.0 * m as f64
                        / ((2 * l) as f64 * (2 * l + 1) as f64 * (2 * l + 2) as f64).sqrt();
                    assert!(
                        (v1 - e1).abs() <= 2e-15 * e.abs(),
                        "l={l} m={m}: {v1} vs {e1}"
                    );
                }
            }
        }
    }

    /// `sqrt(prod_i num_i! / prod_j den_j!)` as an f64 (None if it under/overflows), by
    /// pairing the sorted factorial arguments and multiplying the surviving integer factors
    /// with exact power-of-two rescaling: each factor costs at most two roundings, so the
    /// relative error is below `2 eps` times the number of factors (a few thousand at most
    /// here).
    fn sqrt_fact_ratio(num: &[i64], den: &[i64]) -> Option<f64> {
        let mut a = num.to_vec();
        let mut b = den.to_vec();
        while a.len() < b.len() {
            a.push(0);
        }
        while b.len() < a.len() {
            b.push(0);
        }
        a.sort_unstable();
        b.sort_unstable();
        let (mut mant, mut exp) = (1.0f64, 0i64);
        for (&n, &d) in a.iter().zip(&b) {
            for k in (n.min(d) + 1)..=(n.max(d)) {
                if n > d {
                    mant *= k as f64;
                } else {
                    mant /= k as f64;
                }
                if !(2f64.powi(-500)..=2f64.powi(500)).contains(&mant) {
                    let e = mant.log2().floor() as i32;
                    mant *= 2f64.powi(-e);
                    exp += e as i64;
                }
            }
        }
        if exp % 2 != 0 {
            mant *= 2.0;
            exp -= 1;
        }
        let half = exp / 2;
        if !(-1000..=1000).contains(&half) {
            return None;
        }
        let v = mant.sqrt() * 2f64.powi(half as i32);
        (v.is_normal()).then_some(v)
    }

    #[test]
    fn stretched_closed_form_dlmf_34_3_6() {
        // (l1 l2 l1+l2; m1 m2 -m1-m2) against the factorial formula DLMF 34.3.6.
        let mut checked = 0;
        for x in pseudo_random(5 * 400, 1).chunks(5) {
            let big = x[0] < 0.0;
            let lmax = if big { 2500 } else { 40 };
            let l1 = pick(x[1], 0, lmax);
            let l2 = pick(x[2], 0, lmax);
            let m1 = pick(x[3], -l1, l1);
            let m2 = pick(x[4], -l2, l2);
            let Some(mag) = sqrt_fact_ratio(
                &[2 * l1, 2 * l2, l1 + l2 + m1 + m2, l1 + l2 - m1 - m2],
                &[2 * l1 + 2 * l2 + 1, l1 + m1, l1 - m1, l2 + m2, l2 - m2],
            ) else {
                continue; // beyond the f64 range: underflow is expected
            };
            let s = if (l1 - l2 + m1 + m2).rem_euclid(2) == 0 {
                1.0
            } else {
                -1.0
            };
            let e = s * mag;
            let row = wigner_3j_row(l1 as usize, m1, l2 as usize, m2).unwrap();
            let v = row.get((l1 + l2) as usize);
            let tol = if big { 1e-12 } else { 2e-14 };
            assert!(
                (v - e).abs() <= tol * e.abs(),
                "({l1} {l2} {}; {m1} {m2}): {v:e} vs {e:e}",
                l1 + l2
            );
            checked += 1;
        }
        assert!(checked > 250);
    }

    #[test]
    fn zero_m_closed_form_dlmf_34_3_5() {
        // (l1 l2 l3; 0 0 0) with J = l1+l2+l3 even against DLMF 34.3.5.
        for x in pseudo_random(4 * 300, 2).chunks(4) {
            let big = x[0] < 0.0;
            let lmax = if big { 3000 } else { 30 };
            let l1 = pick(x[1], 0, lmax);
            let l2 = pick(x[2], 0, lmax);
            let mut l3 = pick(x[3], (l1 - l2).abs(), l1 + l2);
            if (l1 + l2 + l3) % 2 == 1 {
                l3 -= 1;
                if l3 < (l1 - l2).abs() {
                    l3 += 2;
                }
            }
            let j = l1 + l2 + l3;
            let g = j / 2;
            let mag = sqrt_fact_ratio(
                &[j - 2 * l1, j - 2 * l2, j - 2 * l3, g, g],
                &[j + 1, g - l1, g - l1, g - l2, g - l2, g - l3, g - l3],
            )
            .expect("(l1 l2 l3; 0 0 0) is within the f64 range here");
            let e = if g % 2 == 0 { 1.0 } else { -1.0 } * mag;
            let v = wigner_3j(l1 as usize, 0, l2 as usize, 0, l3 as usize, 0).unwrap();
            let tol = if big { 1e-12 } else { 2e-14 };
            assert!(
                (v - e).abs() <= tol * e.abs(),
                "({l1} {l2} {l3}; 0 0 0): {v:e} vs {e:e}"
            );
            // Odd J vanishes exactly.
            if l3 < l1 + l2 {
                assert_eq!(
                    wigner_3j(l1 as usize, 0, l2 as usize, 0, (l3 + 1) as usize, 0).unwrap(),
                    0.0
                );
            }
        }
    }

    #[test]
    fn orthogonality_over_m() {
        // sum_{m1 + m2 = -m3} (2 l3 + 1) (l1 l2 l3; m1 m2 m3)(l1 l2 l3'; m1 m2 m3) = δ_{l3 l3'}
        // (DLMF §34.3(iv)); not implied by the row normalization, which is over l3.
        for &(l1, l2, m3) in &[
            (3usize, 5usize, 0i64),
            (10, 10, 3),
            (17, 4, -2),
            (40, 33, 25),
            (300, 250, 7),
            (1200, 1100, -600),
        ] {
            let (j1, j2) = (l1 as i64, l2 as i64);
            let jmin = (l1.abs_diff(l2)).max(m3.unsigned_abs() as usize);
            let jmax = l1 + l2;
            let n = jmax - jmin + 1;
            let mut s = vec![0.0f64; n * n];
            let mut row = Vec::new();
            for m1 in -j1..=j1 {
                let m2 = -m3 - m1;
                if m2.abs() > j2 {
                    continue;
                }
                let rmin = wigner_3j_row_into(l1, m1, l2, m2, &mut row).unwrap();
                assert_eq!(rmin, jmin);
                for i in 0..n {
                    for k in 0..n {
                        s[i * n + k] += (2 * (jmin + i) + 1) as f64 * row[i] * row[k];
                    }
                }
            }
            let mut err: f64 = 0.0;
            for i in 0..n {
                for k in 0..n {
                    let e = if i == k { 1.0 } else { 0.0 };
                    err = err.max((s[i * n + k] - e).abs());
                }
            }
            let tol = if l1 > 500 { 1e-12 } else { 1e-13 };
            assert!(err < tol, "l1={l1} l2={l2} m3={m3}: error {err:e}");
        }
    }

    #[test]
    fn orthogonality_over_l3() {
        // sum_{l3} (2 l3 + 1) (l1 l2 l3; m1 m2 m3)(l1 l2 l3; m1' m2' m3) = δ_{m1 m1'} for
        // m1 + m2 = m1' + m2' (DLMF §34.3(iv)); the diagonal is the normalization, the
        // off-diagonal is a genuine check of the recursion and matching.
        for &(l1, l2, msum) in &[
            (6usize, 9usize, 2i64),
            (25, 25, 0),
            (64, 40, -13),
            (2000, 1500, 100),
        ] {
            let (j1, j2) = (l1 as i64, l2 as i64);
            let mut rows = Vec::new();
            for m1 in -j1..=j1 {
                let m2 = msum - m1;
                if m2.abs() <= j2 && (m1 % 97 == 0 || l1 < 100) {
                    rows.push(wigner_3j_row(l1, m1, l2, m2).unwrap());
                }
            }
            let mut err: f64 = 0.0;
            for (i, a) in rows.iter().enumerate() {
                for (k, b) in rows.iter().enumerate() {
                    let mut acc = Neumaier::default();
                    for (l3, v) in a.iter() {
                        acc.add((2 * l3 + 1) as f64 * v * b.get(l3));
                    }
                    let e = if i == k { 1.0 } else { 0.0 };
                    err = err.max((acc.value() - e).abs());
                }
            }
            let tol = if l1 > 500 { 1e-12 } else { 1e-14 };
            assert!(err < tol, "l1={l1} l2={l2}: error {err:e}");
        }
    }

    #[test]
    fn symmetries() {
        // DLMF 34.3.8-34.3.10: cyclic permutations leave the symbol unchanged, odd permutations
        // and the sign flip of all m multiply it by (-1)^{l1+l2+l3}. Rows are compared across
        // different recursion variables, so this exercises independent recursions.
        let mut max_err: f64 = 0.0;
        for x in pseudo_random(6 * 3000, 3).chunks(6) {
            let lmax = if x[0] < -0.5 { 400 } else { 25 };
            let l1 = pick(x[1], 0, lmax);
            let l2 = pick(x[2], 0, lmax);
            let l3 = pick(x[3], (l1 - l2).abs(), l1 + l2);
            let m1 = pick(x[4], -l1, l1);
            let m2lo = (-l2).max(-l3 - m1);
            let m2hi = l2.min(l3 - m1);
            let m2 = pick(x[5], m2lo, m2hi);
            let m3 = -m1 - m2;
            let (u1, u2, u3) = (l1 as usize, l2 as usize, l3 as usize);
            let p = if (l1 + l2 + l3) % 2 == 0 { 1.0 } else { -1.0 };
            let r12 = wigner_3j_row(u1, m1, u2, m2).unwrap().get(u3);
            let r23 = wigner_3j_row(u2, m2, u3, m3).unwrap().get(u1);
            let r31 = wigner_3j_row(u3, m3, u1, m1).unwrap().get(u2);
            let r21 = wigner_3j_row(u2, m2, u1, m1).unwrap().get(u3);
            let r13 = wigner_3j_row(u1, m1, u3, m3).unwrap().get(u2);
            let rneg = wigner_3j_row(u1, -m1, u2, -m2).unwrap().get(u3);
            // Each value is the correctly rounded f64 of a double-double result, so two
            // evaluations differ by at most one ulp; at nontrivial zeros both are tiny compared
            // with the a-priori bound |3j| <= 1/sqrt(2 l + 1) (normalization in l).
            let bound = 1.0 / ((2 * l1.max(l2).max(l3) + 1) as f64).sqrt();
            for (name, v) in [
                ("231", r23),
                ("312", r31),
                ("213", p * r21),
                ("132", p * r13),
                ("-m", p * rneg),
            ] {
                max_err = max_err.max((v - r12).abs() / bound);
                assert!(
                    (v - r12).abs() <= f64::EPSILON * r12.abs() + 1e-28 * bound,
                    "{name}: ({l1} {l2} {l3}; {m1} {m2} {m3}) {v:e} vs {r12:e}"
                );
            }
        }
        eprintln!("symmetries: max |difference| / bound = {max_err:e}");
    }

    #[test]
    fn selection_rules_give_exact_zeros() {
        assert_eq!(wigner_3j(2, 1, 3, 1, 4, -1).unwrap(), 0.0); // m sum
        assert_eq!(wigner_3j(2, 0, 3, 0, 6, 0).unwrap(), 0.0); // triangle
        assert_eq!(wigner_3j(1, 0, 1, 0, 1, 0).unwrap(), 0.0); // parity
        assert_eq!(wigner_3j(3, 1, 3, 1, 3, -2).unwrap(), 0.0); // l1 = l2, m1 = m2, odd J
                                                                // Rows: structural zeros of the two-step recursion are exact.
        let r = wigner_3j_row(5, 0, 7, 0).unwrap();
        for (l3, v) in r.iter() {
            if (5 + 7 + l3) % 2 == 1 {
                assert_eq!(v, 0.0);
            } else {
                assert!(v != 0.0);
            }
        }
    }

    #[test]
    fn bad_input_is_an_error() {
        assert!(matches!(
            wigner_3j(1, 2, 1, 0, 1, -2),
            Err(Error::OrderOutOfRange { name: "m1", .. })
        ));
        assert!(matches!(
            wigner_3j(1, 0, 1, 0, 1, -3),
            Err(Error::OrderOutOfRange { name: "m3", .. })
        ));
        assert!(matches!(
            wigner_3j_row(3, 0, 2, 5),
            Err(Error::OrderOutOfRange { name: "m2", .. })
        ));
        assert!(matches!(
            wigner_3j(MAX_GAUNT_DEGREE + 1, 0, 1, 0, 1, 0),
            Err(Error::DegreeOutOfRange { name: "l1", .. })
        ));
    }

    #[test]
    fn large_degree_rows_are_finite_and_normalized() {
        // Degrees up to MAX_GAUNT_DEGREE: no overflow, no NaN, and the largest-l3 value still
        // has the sign of DLMF 34.3.6 even where its magnitude underflows.
        for &(l1, l2, m1, m2) in &[
            (8192usize, 8192usize, 8192i64, -8192i64),
            (8192, 3, -100, 2),
            (16384, 16384, 16384, -1),
            (5000, 4000, 0, 0),
            (6000, 6000, 17, 17),
        ] {
            let row = wigner_3j_row(l1, m1, l2, m2).unwrap();
            let mut acc = Neumaier::default();
            for (l3, v) in row.iter() {
                assert!(v.is_finite());
                acc.add((2 * l3 + 1) as f64 * v * v);
            }
            assert!(
                (acc.value() - 1.0).abs() < 1e-12,
                "{l1} {l2} {m1} {m2}: {}",
                acc.value()
            );
        }
    }
}
