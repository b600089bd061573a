//! Wigner's small d-matrix in arbitrary precision, by Wigner's finite sum, certified.
//!
//! Convention: the standard one of quantum mechanics (Wigner 1931; Sakurai, *Modern
//! Quantum Mechanics*, Eq. 3.8.33 (3.9.33 in the 2nd edition); Edmonds 4.1.15), rows `m`,
//! columns `m'`:
//!
//! ```text
//! d^j_{m m'}(beta) = sum_s (-1)^{m - m' + s}
//!     sqrt((j+m)! (j-m)! (j+m')! (j-m')!) / ((j+m'-s)! s! (m-m'+s)! (j-m-s)!)
//!     cos(beta/2)^{2j + m' - m - 2s} sin(beta/2)^{m - m' + 2s},
//! ```
//!
//! the sum running over the integers `s` for which every factorial argument is `>= 0`.
//! Thus `d^{1/2} = [[cos b/2, -sin b/2], [sin b/2, cos b/2]]` (rows `m = +1/2, -1/2`) and
//! `d^1_{1,0}(b) = -sin(b)/sqrt(2)`. The full matrix is
//! `D^l_{m m'}(alpha, beta, gamma) = e^{-i m alpha} d^l_{m m'}(beta) e^{-i m' gamma}` for
//! the active rotation `R = Rz(alpha) Ry(beta) Rz(gamma)`; with it, the rotation of
//! functions `R_F[f](w) = f(R^-1 w)` (PSH (8)) maps `Y_{l m'}` to
//! `sum_m Y_lm D^l_{m m'}(R)`, which is PSH (9): `<Y_lm, R_F[Y_{l'm'}]> = delta_ll' D^l_mm'`.
//! This module's tests check that statement directly at `l = 1, 2`.
//!
//! The sum alternates and its terms can exceed the result by a factor up to `4^j`
//! (at `l = 1000`, about `10^602`): the working precision is chosen from a rigorous a
//! priori error bound, `|d_hat - d| <= (gamma_n + 2 gamma_{2j+20}) sum_s |t_s|`, computed
//! alongside the sum and met by raising the precision until it is below `2^-prec |d|`
//! (see `proofs/exact-oracles.md`).

use rug::float::Round;
use rug::ops::{AddAssignRound, NegAssign, Pow};
use rug::{Assign, Complex, Float, Integer};

use super::{abs_up, deficit_bits, gamma, mul_up, BOUND_PREC};

/// Largest working precision (bits) the certification loop will try. Unreachable for
/// finite `beta` (see the proof page: `d` vanishes only where its closed form forces it,
/// and then the sum is exactly zero).
const MAX_WORK_PREC: u32 = 1 << 22;

/// `d^l_{m m'}(beta)` for integer `l`, with relative error below `2^(1-prec)` and `prec`
/// bits. `beta` is used exactly as given (build it from an f64 with
/// [`super::float_from_f64`]). Returns `0` if `|m| > l` or `|m'| > l`, NaN for a
/// non-finite `beta`.
pub fn small_d(l: u32, m: i32, mp: i32, beta: &Float, prec: u32) -> Float {
    small_d_many(l, &[(m, mp)], beta, prec)
        .pop()
        .unwrap_or_else(|| Float::new(prec))
}

/// `d^j_{m m'}(beta)` for integer or half-integer `j`, indices given doubled:
/// `two_j = 2j`, `two_m = 2m`, `two_mp = 2m'`. Returns `0` if `|m| > j` or `|m'| > j`,
/// NaN if the parities of `two_j`, `two_m`, `two_mp` differ (no such matrix element) or
/// `beta` is not finite. Relative error below `2^(1-prec)`.
pub fn small_d_half(two_j: u32, two_m: i32, two_mp: i32, beta: &Float, prec: u32) -> Float {
    small_d_many_doubled(two_j, &[(two_m, two_mp)], beta, prec)
        .pop()
        .unwrap_or_else(|| Float::new(prec))
}

/// `d^l_{m m'}(beta)` for many pairs `(m, m')` of one degree, sharing the tables of
/// factorials and powers; same guarantees as [`small_d`].
pub fn small_d_many(l: u32, pairs: &[(i32, i32)], beta: &Float, prec: u32) -> Vec<Float> {
    let doubled: Vec<(i32, i32)> = pairs
        .iter()
        .map(|&(m, mp)| (m.saturating_mul(2), mp.saturating_mul(2)))
        .collect();
    small_d_many_doubled(l.saturating_mul(2), &doubled, beta, prec)
}

/// The whole block `d^l(beta)`, row-major `(2l+1) x (2l+1)`, rows `m = -l..=l`, columns
/// `m' = -l..=l`; same guarantees as [`small_d`]. Cost `O(l^3)` big-float operations.
pub fn small_d_block(l: u32, beta: &Float, prec: u32) -> Vec<Float> {
    let li = l as i32;
    let pairs: Vec<(i32, i32)> = (-li..=li)
        .flat_map(|m| (-li..=li).map(move |mp| (m, mp)))
        .collect();
    small_d_many(l, &pairs, beta, prec)
}

/// `D^l_{m m'}(alpha, beta, gamma) = e^{-i m alpha} d^l_{m m'}(beta) e^{-i m' gamma}`
/// for `R = Rz(alpha) Ry(beta) Rz(gamma)` (PSH (9) with the Euler angles above).
///
/// The real and imaginary parts each have absolute error below `2^(1-prec) |d|` (the
/// phase is computed at `prec + 64` bits plus the bits of `|m alpha + m' gamma|`).
#[allow(clippy::too_many_arguments)]
pub fn big_d(
    l: u32,
    m: i32,
    mp: i32,
    alpha: &Float,
    beta: &Float,
    gamma: &Float,
    prec: u32,
) -> Complex {
    let d = small_d(l, m, mp, beta, prec + 8);
    if !alpha.is_finite() || !gamma.is_finite() {
        return Complex::with_val(prec, (f64::NAN, f64::NAN));
    }
    // Phase -(m alpha + m' gamma): each product is exact at these precisions.
    let pa = alpha.prec() + 40;
    let pg = gamma.prec() + 40;
    let ma = Float::with_val(pa, alpha * m);
    let mg = Float::with_val(pg, gamma * mp);
    let mag = ma
        .get_exp()
        .unwrap_or(0)
        .max(mg.get_exp().unwrap_or(0))
        .max(0) as u32;
    let pp = prec + 64 + mag;
    let phase = -Float::with_val(pp, &ma + &mg);
    let (s, c) = (
        Float::with_val(pp, phase.sin_ref()),
        Float::with_val(pp, phase.cos_ref()),
    );
    let re = Float::with_val(prec, &d * &c);
    let im = Float::with_val(prec, &d * &s);
    Complex::with_val(prec, (re, im))
}

/// Doubled-index core of all the entry points.
fn small_d_many_doubled(two_j: u32, pairs: &[(i32, i32)], beta: &Float, prec: u32) -> Vec<Float> {
    let target = prec.saturating_add(1);
    let tj = i64::from(two_j);
    let mut out: Vec<Option<Float>> = vec![None; pairs.len()];
    let mut todo: Vec<usize> = Vec::new();
    for (i, &(tm, tmp)) in pairs.iter().enumerate() {
        let (tm, tmp) = (i64::from(tm), i64::from(tmp));
        if (tj - tm) % 2 != 0 || (tj - tmp) % 2 != 0 || !beta.is_finite() {
            out[i] = Some(Float::with_val(prec, f64::NAN));
        } else if tm.abs() > tj || tmp.abs() > tj {
            out[i] = Some(Float::new(prec));
        } else {
            todo.push(i);
        }
    }
    if !todo.is_empty() {
        let facts = exact_factorials(two_j);
        // Every element gets the same first try; the ones whose bound is not met are
        // retried at the precision their deficit asks for, grouped to share tables.
        let mut p = first_work_prec(two_j, target);
        while !todo.is_empty() {
            if p > MAX_WORK_PREC {
                for &i in &todo {
                    out[i] = Some(Float::with_val(prec, f64::NAN));
                }
                break;
            }
            let ctx = Tables::new(&facts, two_j, beta, p);
            let mut retry: Vec<(usize, u32)> = Vec::new();
            for &i in &todo {
                let (tm, tmp) = pairs[i];
                let (v, bound) = ctx.element(two_j, tm, tmp);
                match deficit_bits(&bound, &v, target) {
                    Some(0) => out[i] = Some(Float::with_val(prec, &v)),
                    Some(k) => retry.push((i, p.saturating_add(k).saturating_add(32))),
                    None => retry.push((i, p.saturating_mul(2))),
                }
            }
            // Next round: the smallest requested precision, rounded up; elements that
            // asked for more are simply tried again (their deficit shrinks each round).
            todo = retry.iter().map(|&(i, _)| i).collect();
            if let Some(next) = retry.iter().map(|&(_, q)| q).min() {
                p = next.max(p + 64).div_ceil(256) * 256;
            }
        }
    }
    out.into_iter()
        .map(|v| v.expect("every element was set"))
        .collect()
}

/// First working precision: the target, plus the `2j` bits that cancellation can cost
/// (`sum_s |t_s| <= 4^j`, see the proof page), plus margin for the bound's factor.
fn first_work_prec(two_j: u32, target: u32) -> u32 {
    let bits =
        u64::from(target) + u64::from(two_j) + 64 + 2 * u64::from(32 - two_j.leading_zeros());
    (bits.min(u64::from(MAX_WORK_PREC)) as u32).div_ceil(64) * 64
}

/// `n!` for `n = 0..=two_j` as exact integers (shared by every working precision).
fn exact_factorials(two_j: u32) -> Vec<Integer> {
    let mut f = Vec::with_capacity(two_j as usize + 1);
    let mut acc = Integer::from(1);
    f.push(acc.clone());
    for n in 1..=two_j {
        acc *= n;
        f.push(acc.clone());
    }
    f
}

/// Factorials (each correctly rounded from the exact integer) and the powers
/// `cos(beta/2)^k`, `sin(beta/2)^k`, `k = 0..=2j` (each one correctly rounded `pow` of
/// the correctly rounded `cos(beta/2)`, `sin(beta/2)`), at working precision `p`.
struct Tables {
    p: u32,
    fact: Vec<Float>,
    cpow: Vec<Float>,
    spow: Vec<Float>,
}

impl Tables {
    fn new(facts: &[Integer], two_j: u32, beta: &Float, p: u32) -> Self {
        let fact: Vec<Float> = facts.iter().map(|f| Float::with_val(p, f)).collect();
        // beta/2 is exact: a power-of-two scaling in binary floating point.
        let mut half = beta.clone();
        half >>= 1;
        let c = Float::with_val(p, half.cos_ref());
        let s = Float::with_val(p, half.sin_ref());
        let cpow = (0..=two_j)
            .map(|k| Float::with_val(p, (&c).pow(k)))
            .collect();
        let spow = (0..=two_j)
            .map(|k| Float::with_val(p, (&s).pow(k)))
            .collect();
        Tables {
            p,
            fact,
            cpow,
            spow,
        }
    }

    /// Wigner's sum for row `m = two_m/2`, column `m' = two_mp/2`: the value at
    /// precision `p` and a rigorous bound of its absolute error.
    ///
    /// With `a = j+m`, `b = j-m`, `c = j+m'`, `d = j-m'` the term is
    /// `(-1)^{a-c+s} sqrt(a! b! c! d!) / ((c-s)! s! (a-c+s)! (b-s)!) cos^{b+c-2s} sin^{a-c+2s}`,
    /// `max(0, c-a) <= s <= min(c, b)`.
    ///
    /// Error: each computed term is `t_s (1 + th)`, `|th| <= gamma_K`, `K = 2j + 20`
    /// (8 roundings in the root of four rounded factorials, 7 in the denominator, 1
    /// division, `k + 1` in each power `pow(fl(c), k)` with exponents summing to `2j`,
    /// 2 products); recursive summation of `n` terms adds `gamma_{n-1} sum |t_hat|`.
    /// The bound returned is `(gamma_n + 2 gamma_K) S`, `S >= sum_s |t_hat_s|` summed
    /// with upward rounding.
    fn element(&self, two_j: u32, two_m: i32, two_mp: i32) -> (Float, Float) {
        let p = self.p;
        let tj = i64::from(two_j);
        let a = ((tj + i64::from(two_m)) / 2) as usize;
        let b = ((tj - i64::from(two_m)) / 2) as usize;
        let c = ((tj + i64::from(two_mp)) / 2) as usize;
        let d = ((tj - i64::from(two_mp)) / 2) as usize;
        let mut root = Float::with_val(p, &self.fact[a] * &self.fact[b]);
        root *= &self.fact[c];
        root *= &self.fact[d];
        root.sqrt_mut();

        let s_lo = c.saturating_sub(a);
        let s_hi = c.min(b);
        let mut sum = Float::new(p);
        let mut sum_abs = Float::new(BOUND_PREC);
        let mut den = Float::new(p);
        let mut t = Float::new(p);
        let mut n_terms: u64 = 0;
        for s in s_lo..=s_hi {
            // a - c + s >= 0 by the lower limit.
            let amc = a + s - c;
            den.assign(&self.fact[c - s] * &self.fact[s]);
            den *= &self.fact[amc];
            den *= &self.fact[b - s];
            t.assign(&root / &den);
            t *= &self.cpow[b + c - 2 * s];
            t *= &self.spow[amc + s];
            if amc % 2 == 1 {
                t.neg_assign();
            }
            sum_abs.add_assign_round(&abs_up(&t), Round::Up);
            sum += &t;
            n_terms += 1;
        }
        let k = u64::from(two_j) + 20;
        let mut g2 = gamma(k, p);
        g2 <<= 1; // exact
        let g = Float::with_val_round(BOUND_PREC, &gamma(n_terms, p) + &g2, Round::Up).0;
        let bound = mul_up(&g, &sum_abs);
        (sum, bound)
    }
}

#[cfg(test)]
mod tests {
    use super::super::float_from_f64;
    use super::super::legendre::pbar;
    use super::*;
    use rug::float::Constant;

    const PREC: u32 = 160;

    fn close(a: &Float, b: &Float, tol: f64) -> bool {
        let d = Float::with_val(400, a - b).abs();
        d.to_f64() <= tol
    }

    fn f(prec: u32, x: f64) -> Float {
        Float::with_val(prec, x)
    }

    /// Spin 1/2: the defining 2x2 matrix (rows m = +1/2, -1/2).
    #[test]
    fn spin_half() {
        for &b in &[0.0, 0.3, 1.1, 2.9, -0.7] {
            let beta = float_from_f64(b);
            let mut h = beta.clone();
            h >>= 1;
            let c = Float::with_val(200, h.cos_ref());
            let s = Float::with_val(200, h.sin_ref());
            let tol = 1e-46;
            assert!(close(&small_d_half(1, 1, 1, &beta, PREC), &c, tol));
            assert!(close(
                &small_d_half(1, 1, -1, &beta, PREC),
                &(-s.clone()),
                tol
            ));
            assert!(close(&small_d_half(1, -1, 1, &beta, PREC), &s, tol));
            assert!(close(&small_d_half(1, -1, -1, &beta, PREC), &c, tol));
        }
        assert!(small_d_half(1, 0, 1, &float_from_f64(0.3), 64).is_nan());
    }

    /// Spin 1 closed forms (Sakurai Eq. 3.8.35 / 3.9.35):
    /// `d^1 = [[(1+c)/2, -s/r2, (1-c)/2], [s/r2, c, -s/r2], [(1-c)/2, s/r2, (1+c)/2]]`,
    /// rows and columns `m = 1, 0, -1`.
    #[test]
    fn spin_one() {
        for &b in &[0.3, 1.1, std::f64::consts::FRAC_PI_2, 3.0] {
            let beta = float_from_f64(b);
            let c = Float::with_val(200, beta.cos_ref());
            let s = Float::with_val(200, beta.sin_ref());
            let r2 = f(200, 2.0).sqrt();
            let one = f(200, 1.0);
            let p = Float::with_val(200, &one + &c) / 2u32;
            let q = Float::with_val(200, &one - &c) / 2u32;
            let t = Float::with_val(200, &s / &r2);
            let want = [
                [p.clone(), -t.clone(), q.clone()],
                [t.clone(), c.clone(), -t.clone()],
                [q.clone(), t.clone(), p.clone()],
            ];
            for (i, m) in [1, 0, -1].iter().enumerate() {
                for (k, mp) in [1, 0, -1].iter().enumerate() {
                    let got = small_d(1, *m, *mp, &beta, PREC);
                    assert!(close(&got, &want[i][k], 1e-46), "b={b} m={m} mp={mp}");
                }
            }
        }
    }

    /// `d^l_{m0}(beta) = sqrt(4 pi / (2l+1)) Pbar_lm(beta)` and
    /// `d^l_{0m} = (-1)^m d^l_{m0}`: Wigner's sum against the independent Legendre
    /// recurrence, up to l = 1000.
    #[test]
    fn column_zero_is_legendre() {
        for &b in &[0.3, 1.1, std::f64::consts::FRAC_PI_2, 2.8] {
            let beta = float_from_f64(b);
            let mut cases: Vec<(u32, i32)> = Vec::new();
            for l in 0..=12u32 {
                for m in 0..=l as i32 {
                    cases.push((l, m));
                }
            }
            for &m in &[0, 1, 2, 333, 500, 999, 1000] {
                cases.push((1000, m));
            }
            for (l, m) in cases {
                let d = small_d(l, m, 0, &beta, PREC);
                let d0m = small_d(l, 0, m, &beta, PREC);
                let pl = pbar(l as usize, m as usize, &beta, PREC + 20);
                let factor = (Float::with_val(300, Constant::Pi) * 4u32 / (2 * l + 1)).sqrt();
                let want = Float::with_val(300, &pl * &factor);
                let tol = Float::with_val(64, want.abs_ref()).to_f64() * 2f64.powi(-155);
                assert!(close(&d, &want, tol), "b={b} l={l} m={m}: {d} vs {want}");
                let sign = if m % 2 == 0 { 1 } else { -1 };
                assert!(
                    close(&d0m, &Float::with_val(300, &want * sign), tol),
                    "b={b} l={l} m={m}"
                );
            }
        }
    }

    /// Orthogonality of the real matrices `d^l(beta)`: `d d^T = I`.
    #[test]
    fn blocks_are_orthogonal() {
        let beta = float_from_f64(1.1);
        for l in [0u32, 1, 2, 3, 6, 20] {
            let n = (2 * l + 1) as usize;
            let d = small_d_block(l, &beta, PREC);
            for i in 0..n {
                for k in 0..n {
                    let mut acc = Float::new(PREC + 20);
                    for j in 0..n {
                        acc += Float::with_val(PREC + 20, &d[i * n + j] * &d[k * n + j]);
                    }
                    let want = if i == k { 1.0 } else { 0.0 };
                    assert!(close(&acc, &f(64, want), 1e-45), "l={l} i={i} k={k}");
                }
            }
        }
    }

    /// Symmetries (Sakurai 3.8.38 / Edmonds 4.2.6):
    /// `d_{m m'} = (-1)^{m-m'} d_{m' m} = d_{-m', -m}`.
    #[test]
    fn symmetries() {
        let beta = float_from_f64(0.3);
        for l in [1u32, 4, 7, 100] {
            let li = l as i32;
            let step = if l > 10 { 13 } else { 1 };
            for m in (-li..=li).step_by(step) {
                for mp in (-li..=li).step_by(step) {
                    let a = small_d(l, m, mp, &beta, PREC);
                    let b = small_d(l, mp, m, &beta, PREC);
                    let c = small_d(l, -mp, -m, &beta, PREC);
                    let sign = if (m - mp).rem_euclid(2) == 0 { 1 } else { -1 };
                    let tol = Float::with_val(64, a.abs_ref()).to_f64() * 2f64.powi(-158);
                    assert!(
                        close(&a, &Float::with_val(PREC, &b * sign), tol),
                        "l={l} m={m} mp={mp}"
                    );
                    assert!(close(&a, &c, tol), "l={l} m={m} mp={mp}");
                }
            }
        }
    }

    /// Composition about one axis: `d(b1 + b2) = d(b1) d(b2)` (b1 + b2 held exactly).
    #[test]
    fn composition() {
        let b1 = float_from_f64(0.3);
        let b2 = float_from_f64(1.1);
        let b12 = Float::with_val(200, &b1 + &b2); // exact
        for l in [2u32, 5] {
            let n = (2 * l + 1) as usize;
            let d1 = small_d_block(l, &b1, PREC);
            let d2 = small_d_block(l, &b2, PREC);
            let d12 = small_d_block(l, &b12, PREC);
            for i in 0..n {
                for k in 0..n {
                    let mut acc = Float::new(PREC + 20);
                    for j in 0..n {
                        acc += Float::with_val(PREC + 20, &d1[i * n + j] * &d2[j * n + k]);
                    }
                    assert!(close(&acc, &d12[i * n + k], 1e-45), "l={l} i={i} k={k}");
                }
            }
        }
    }

    /// Edge rows `m = l`: `d^l_{l m'} = (-1)^{l-m'} sqrt(C(2l, l+m')) cos^{l+m'} sin^{l-m'}`
    /// (of beta/2), and at beta = 0 the identity, exactly.
    #[test]
    fn edges_and_identity() {
        let beta = float_from_f64(1.1);
        let mut h = beta.clone();
        h >>= 1;
        let c = Float::with_val(400, h.cos_ref());
        let s = Float::with_val(400, h.sin_ref());
        let l = 1000u32;
        for &mp in &[-1000, -999, -1, 0, 1, 500, 1000] {
            let got = small_d(l, l as i32, mp, &beta, PREC);
            let binom = Float::with_val(
                400,
                Integer::from(Integer::binomial_u(2 * l, (l as i32 + mp) as u32)),
            );
            let mut want = binom.sqrt();
            want *= Float::with_val(400, (&c).pow((l as i32 + mp) as u32));
            want *= Float::with_val(400, (&s).pow((l as i32 - mp) as u32));
            if (l as i32 - mp) % 2 != 0 {
                want = -want;
            }
            let tol = Float::with_val(64, want.abs_ref()).to_f64() * 2f64.powi(-158);
            assert!(close(&got, &want, tol), "mp={mp}");
        }
        let zero = float_from_f64(0.0);
        for m in -3..=3 {
            for mp in -3..=3 {
                let v = small_d(3, m, mp, &zero, 64);
                assert_eq!(v, if m == mp { 1 } else { 0 });
            }
        }
        assert!(small_d(3, 4, 0, &beta, 64).is_zero());
        assert!(small_d(3, 1, 0, &float_from_f64(f64::INFINITY), 64).is_nan());
    }

    /// The certified bound is honest at l = 1000: 140-bit results agree with 500-bit
    /// ones within the claimed `2^(1-140)` relative error, including tiny corners such
    /// as `d^1000_{1000,-1000}(1.1) = sin^2000(0.55) ~ 1e-567`.
    #[test]
    fn certified_bound_is_met_at_l1000() {
        let beta = float_from_f64(1.1);
        let pairs = [
            (0, 0),
            (1000, -1000),
            (-1000, 1000),
            (1000, 0),
            (3, -7),
            (700, 650),
            (-999, 2),
            (17, 17),
        ];
        let lo = small_d_many(1000, &pairs, &beta, 140);
        let hi = small_d_many(1000, &pairs, &beta, 500);
        for ((lo, hi), pair) in lo.iter().zip(&hi).zip(&pairs) {
            let d = Float::with_val(600, lo - hi).abs();
            let rel = (d / Float::with_val(600, hi.abs_ref())).to_f64();
            assert!(rel < 2f64.powi(-139), "{pair:?}: {rel:e}");
        }
    }

    /// PSH (9) with `R_F[f](w) = f(R^-1 w)` (PSH (8)):
    /// `Y_{l m'}(R^-1 w) = sum_m Y_lm(w) D^l_{m m'}(R)` for `R = Rz(a) Ry(b) Rz(g)`,
    /// with `Y_1m`, `Y_2m` written as polynomials in `(x, y, z)` (Condon-Shortley phase).
    #[test]
    fn big_d_rotates_spherical_harmonics() {
        let p = 200;
        let (a, b, g) = (
            float_from_f64(0.4),
            float_from_f64(1.1),
            float_from_f64(-2.3),
        );
        let rz = |t: &Float, v: [Float; 3]| -> [Float; 3] {
            let (c, s) = (
                Float::with_val(p, t.cos_ref()),
                Float::with_val(p, t.sin_ref()),
            );
            [
                Float::with_val(p, &c * &v[0]) - Float::with_val(p, &s * &v[1]),
                Float::with_val(p, &s * &v[0]) + Float::with_val(p, &c * &v[1]),
                v[2].clone(),
            ]
        };
        let ry = |t: &Float, v: [Float; 3]| -> [Float; 3] {
            let (c, s) = (
                Float::with_val(p, t.cos_ref()),
                Float::with_val(p, t.sin_ref()),
            );
            [
                Float::with_val(p, &c * &v[0]) + Float::with_val(p, &s * &v[2]),
                v[1].clone(),
                Float::with_val(p, &c * &v[2]) - Float::with_val(p, &s * &v[0]),
            ]
        };
        let neg = |t: &Float| Float::with_val(p, -t);
        // Y_lm at a unit vector, as a polynomial (Wikipedia table of spherical harmonics).
        let y = |l: i32, m: i32, v: &[Float; 3]| -> Complex {
            let pi = Float::with_val(p, Constant::Pi);
            let (x, yy, z) = (&v[0], &v[1], &v[2]);
            let xp = Complex::with_val(p, (x, Float::with_val(p, yy * m.signum())));
            match (l, m.abs()) {
                (1, 0) => Complex::with_val(p, (Float::with_val(p, 3u32) / (pi * 4u32)).sqrt() * z),
                (1, 1) => {
                    let k = (Float::with_val(p, 3u32) / (pi * 8u32)).sqrt() * (-m.signum());
                    Complex::with_val(p, &xp * &k)
                }
                (2, 0) => {
                    let k = (Float::with_val(p, 5u32) / pi).sqrt() / 4u32;
                    Complex::with_val(p, (Float::with_val(p, z.square_ref()) * 3u32 - 1u32) * k)
                }
                (2, 1) => {
                    let k = (Float::with_val(p, 15u32) / (pi * 2u32)).sqrt() / 2u32 * (-m.signum());
                    Complex::with_val(p, &xp * Float::with_val(p, z * k))
                }
                (2, 2) => {
                    let k = (Float::with_val(p, 15u32) / (pi * 2u32)).sqrt() / 4u32;
                    Complex::with_val(p, xp.square_ref()) * k
                }
                _ => unreachable!(),
            }
        };
        let dirs = [[0.3, -0.5, 0.8], [-0.9, 0.1, 0.2], [0.0, 0.0, 1.0]];
        for dir in dirs {
            let v: [Float; 3] = dir.map(|c| Float::with_val(p, c));
            let n = Float::with_val(p, v[0].square_ref())
                + Float::with_val(p, v[1].square_ref())
                + Float::with_val(p, v[2].square_ref());
            let n = n.sqrt();
            let w: [Float; 3] = v.map(|c| c / &n);
            // R^-1 w = Rz(-g) Ry(-b) Rz(-a) w.
            let rinv_w = rz(&neg(&g), ry(&neg(&b), rz(&neg(&a), w.clone())));
            for l in 1..=2i32 {
                for mp in -l..=l {
                    let lhs = y(l, mp, &rinv_w);
                    let mut rhs = Complex::new(p);
                    for m in -l..=l {
                        let dd = big_d(l as u32, m, mp, &a, &b, &g, 160);
                        rhs += Complex::with_val(p, &y(l, m, &w) * &dd);
                    }
                    let diff = Complex::with_val(p, &lhs - &rhs);
                    let err = Float::with_val(p, diff.abs_ref()).to_f64();
                    assert!(err < 1e-45, "l={l} mp={mp}: {err:e}");
                }
            }
        }
    }

    /// The committed fixture `tests/fixtures/wigner_d.json` is what this oracle produces
    /// today: every entry with `l <= 6` and every 7th entry at `l = 100, 1000` is
    /// recomputed and must match character for character.
    #[test]
    fn committed_fixture_matches_oracle() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/wigner_d.json");
        let text = std::fs::read_to_string(path).expect("fixture present");
        let fx: serde_json::Value = serde_json::from_str(&text).expect("fixture parses");
        let digits = fx["digits"].as_u64().expect("digits") as usize;
        assert!(digits >= 40);
        let mut n = 0;
        for case in fx["cases"].as_array().expect("cases") {
            let l = case["l"].as_u64().expect("l") as u32;
            let bits = case["beta"]["bits"].as_str().expect("bits");
            let b = f64::from_bits(u64::from_str_radix(&bits[2..], 16).expect("hex"));
            let beta = float_from_f64(b);
            let entries = case["entries"].as_array().expect("entries");
            let step = if l <= 6 { 1 } else { 7 };
            let pairs: Vec<(i32, i32)> = entries
                .iter()
                .step_by(step)
                .map(|e| (e[0].as_i64().unwrap() as i32, e[1].as_i64().unwrap() as i32))
                .collect();
            let vals = small_d_many(l, &pairs, &beta, 160);
            for (e, v) in entries.iter().step_by(step).zip(&vals) {
                let got = super::super::to_sci_string(v, digits);
                assert_eq!(got, e[2].as_str().unwrap(), "l={l} beta={b:e} entry {e}");
                n += 1;
            }
        }
        assert!(n > 1365 + 6 * 25, "{n}");
    }
}
