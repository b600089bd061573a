//! The recursion of the spin-weighted harmonics `Lambda_lm(theta)`, with
//! `sY_lm = Lambda_lm(theta) e^{i m phi}`,
//! `Lambda_lm = (-1)^s sqrt((2l+1)/(4 pi)) d^l_{m,-s}`: its coefficients and its starts.
//! At spin 0, `Lambda_lm = Pbar_lm` (`d^l_{m0} = sqrt((l-m)!/(l+m)!) P_l^m`): the scalar
//! transforms of [`crate::sh::ShTransform`] run on it as the spin transforms of
//! `crate::swsh` do.
//!
//! Per polar angle, `Lambda_lm` for `l = l0..=lmax` (`l0 = max(|m|, |s|)`) comes from the
//! three-term recursion of the Wigner d in `l` at fixed `(m, m')`, in the `u = 1 - cos theta`
//! form of [`crate::sh::recursion::legendre`] (derived in `proofs/swsh.md`):
//!
//! `d^l = A_l ((c_l - u) d^{l-1} - B_l d^{l-2})`, `A_l = l (2l-1) / sqrt((l^2-m^2)(l^2-m'^2))`,
//! `B_l = sqrt(((l-1)^2-m^2)((l-1)^2-m'^2)) / ((l-1)(2l-1))`, `c_l = 1 - m m' / (l (l-1))`,
//!
//! run on `Lambda` directly (the norms folded into `A_l`, `B_l`). The start `d^{l0}` has a
//! one-term closed form (half-angle powers times a square root of a binomial): for the
//! `2|s| + 1` orders `|m| <= |s|` it is evaluated through its logarithm, for `|m| > |s|` it
//! follows from the start of order `m -+ 1` by one factor (the diagonal step of
//! `proofs/swsh.md`). Starts and recursions carry the exponent scaling of the Legendre
//! recursion, so that nothing overflows or underflows, and run on many polar angles at
//! once in lock step (lanes), as [`crate::sh::recursion::legendre::Legendre::for_each_column_lanes`].

use crate::sh::recursion::legendre::{
    lane_scale, rescale_lanes, BIG, LANE_BLOCK, SCALE_BITS, SMALL,
};
use std::f64::consts::PI;
use std::ops::Range;

/// `cos(theta/2)`, `sin(theta/2)` of a polar angle in `[0, pi]`: the variables of the start
/// and of `u = 2 sin^2(theta/2)`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct HalfAngle {
    cos: f64,
    sin: f64,
}

impl HalfAngle {
    /// From the polar angle.
    pub(crate) fn from_theta(theta: f64) -> Self {
        let (sin, cos) = (0.5 * theta).sin_cos();
        Self { cos, sin }
    }

    /// The half angles of `pi - theta`: `cos` and `sin` swapped, exactly.
    pub(crate) fn mirrored(self) -> Self {
        Self {
            cos: self.sin,
            sin: self.cos,
        }
    }

    /// `cos(theta/2)`.
    pub(crate) fn cos(&self) -> f64 {
        self.cos
    }

    /// `u = 1 - cos theta = 2 sin^2(theta/2)`, the variable of the recursion.
    pub(crate) fn u(&self) -> f64 {
        2.0 * self.sin * self.sin
    }

    /// From `z = cos theta` and `rho = sin theta >= 0` of a unit direction:
    /// `cos^2(theta/2) = (1 + z)/2`, `sin^2(theta/2) = (1 - z)/2`, the smaller of the two
    /// from `sin theta = 2 sin(theta/2) cos(theta/2)` (no cancellation near the poles).
    pub(crate) fn from_z_rho(z: f64, rho: f64) -> Self {
        if z >= 0.0 {
            let cos = (0.5 * (1.0 + z)).sqrt();
            Self {
                cos,
                sin: 0.5 * rho / cos,
            }
        } else {
            let sin = (0.5 * (1.0 - z)).sqrt();
            Self {
                cos: 0.5 * rho / sin,
                sin,
            }
        }
    }
}

/// How the recursion of one order starts.
#[derive(Clone, Debug)]
enum Start {
    /// `Lambda_{l0,m} = sign 2^log cos^a(theta/2) sin^b(theta/2)` (`log` holds the norm and
    /// `0.5 log2 binom(2 l0, k)`; for the `(-sin)` powers of case (a) the sign applies to
    /// odd `b` only).
    Seed { log: f64, a: i32, b: i32, sign: f64 },
    /// `Lambda_{|m|,m} = g sin(theta)/2 Lambda_{|m|-1,m-+1}`: the diagonal step.
    Diagonal(f64),
}

/// Recursion data of one order `m`: its start degree and start, and the steps
/// `[A_l, B_l, c_l]` (norms folded in) of the degrees `k = l - l0` in pairs: `[1, 1, 0]` at
/// `k = 0` (from `p_{-1} = 0`, `p_{-2} = -start` it gives the start), then `l = l0 + 1..=lmax`,
/// then `[0, 0, 0]` if needed to make the count even (a zero value past `lmax`).
#[derive(Clone, Debug)]
pub(crate) struct Column {
    pub(crate) m: i64,
    pub(crate) l0: usize,
    start: Start,
    pub(crate) coeffs: Vec<[f64; 3]>,
}
/// The columns of spin `s` up to `lmax` (`|s| <= lmax`, unchecked), in walk order:
/// `m = -|s|..=|s|` (seeds), then `-(|s|+1), |s|+1, -(|s|+2), ...` (diagonal steps).
#[derive(Clone, Debug)]
pub(crate) struct Columns {
    pub(crate) spin: i64,
    pub(crate) lmax: usize,
    pub(crate) list: Vec<Column>,
}

impl Columns {
    pub(crate) fn new(spin: i64, lmax: usize) -> Self {
        Self {
            spin,
            lmax,
            list: columns(spin, lmax),
        }
    }

    /// The index of the column of order `m` in walk order.
    pub(crate) fn index(&self, m: i64) -> usize {
        column_index(self.spin, m)
    }

    /// The column of order `m`.
    pub(crate) fn of(&self, m: i64) -> &Column {
        &self.list[self.index(m)]
    }

    /// Walks the columns of walk-order indices `range` whose order `m` has `keep(m)`, at
    /// `N` polar angles at once (given by their half angles): `f(m, l0, column)` with
    /// `column[l - l0][j] = Lambda_lm` at `half[j]`, `l0 = max(|m|, |s|)`, in walk order
    /// (`|m|` increasing). The starts of the columns before are walked through (one factor
    /// each), the recursion runs for the columns handed over only.
    ///
    /// As in [`crate::sh::recursion::legendre::Legendre::for_each_column_lanes`], values below the f64
    /// range carry a binary exponent (a multiple of `SCALE_BITS`), checked once per
    /// [`LANE_BLOCK`] steps; values still below `2^-SCALE_BITS` when handed over are
    /// negligible (they come out as zero or subnormal). `scratch` holds the column.
    pub(crate) fn for_each_column_lanes<const N: usize>(
        &self,
        half: &[HalfAngle; N],
        range: Range<usize>,
        keep: impl Fn(i64) -> bool,
        scratch: &mut Vec<[f64; N]>,
        mut f: impl FnMut(i64, usize, &[[f64; N]]),
    ) {
        let lmax = self.lmax;
        scratch.resize(lmax + 1, [0.0; N]);
        let u = half.map(|h| h.u());
        let mut walk = StartWalk::new(half, self.spin);
        for (i, col) in self.list[..range.end].iter().enumerate() {
            let (mut p1, mut exp) = walk.next(col);
            if i < range.start || !keep(col.m) {
                continue;
            }
            let out = &mut scratch[..=lmax - col.l0];
            let mut p2 = [0.0; N];
            let mut scaled = exp.iter().any(|&e| e < 0);
            let mut fac = lane_scale(&exp);
            for j in 0..N {
                out[0][j] = p1[j] * fac[j];
            }
            // col.coeffs[0] is the start step, col.coeffs[k] the step to degree k.
            let mut k = 1;
            while k < out.len() {
                let end = (k + LANE_BLOCK).min(out.len());
                for (o, &[a, b, c]) in out[k..end].iter_mut().zip(&col.coeffs[k..end]) {
                    for j in 0..N {
                        let p = a * ((c * p1[j] - b * p2[j]) - u[j] * p1[j]);
                        p2[j] = p1[j];
                        p1[j] = p;
                        o[j] = p * fac[j];
                    }
                }
                if scaled {
                    scaled = rescale_lanes(&mut p1, &mut p2, &mut exp);
                    fac = lane_scale(&exp);
                }
                k = end;
            }
            f(col.m, col.l0, out);
        }
    }
}

fn columns(spin: i64, lmax: usize) -> Vec<Column> {
    let parity = if spin % 2 == 0 { 1.0 } else { -1.0 };
    // (-1)^s sqrt((2l+1)/(4 pi)), Lambda_lm = norm_l d^l_{m,-s}.
    let norms: Vec<f64> = (0..=lmax)
        .map(|l| parity * ((2 * l + 1) as f64 / (4.0 * PI)).sqrt())
        .collect();
    let (mp, s) = (-spin, spin.abs());
    let mut columns: Vec<Column> = (-s..=s).map(|m| seed_column(m, mp, lmax, &norms)).collect();
    for j in s + 1..=lmax as i64 {
        // Diagonal step from l0 = j - 1 to j (proofs/swsh.md): |d^j / d^{j-1}| =
        // sqrt(2j (2j-1) / ((j+m')(j-m'))) cos(theta/2) sin(theta/2), with the sign -1
        // on the side m > 0 (the (-sin) powers of case (a)).
        let jf = j as f64;
        let mpf = mp as f64;
        let g = (2.0 * jf * (2.0 * jf - 1.0) / ((jf + mpf) * (jf - mpf))).sqrt()
            * (norms[j as usize] / norms[j as usize - 1]);
        for (m, sign) in [(-j, 1.0), (j, -1.0)] {
            columns.push(Column {
                m,
                l0: j as usize,
                start: Start::Diagonal(sign * g),
                coeffs: recursion_coefficients(m, mp, j as usize, lmax, &norms),
            });
        }
    }
    columns
}

/// The index of the column of order `m` in the walk order of [`columns`].
fn column_index(spin: i64, m: i64) -> usize {
    let s = spin.abs();
    if m.abs() <= s {
        (m + s) as usize
    } else {
        (2 * s + 1 + 2 * (m.abs() - s - 1)) as usize + usize::from(m > 0)
    }
}

/// The starts of the columns' recursions at `N` polar angles, column after column in walk
/// order: seeds from their closed form, the others by the diagonal step from the outermost
/// start of their side.
pub(crate) struct StartWalk<const N: usize> {
    log_c: [f64; N],
    log_s: [f64; N],
    /// `cos(theta/2) sin(theta/2)`.
    cs: [f64; N],
    /// Starts (mantissa, exponent) of the outermost orders so far, `m < 0` and `m > 0`.
    edge: [([f64; N], [i32; N]); 2],
    spin: usize,
}

impl<const N: usize> StartWalk<N> {
    pub(crate) fn new(half: &[HalfAngle; N], spin: i64) -> Self {
        Self {
            log_c: half.map(|h| h.cos.log2()),
            log_s: half.map(|h| h.sin.log2()),
            cs: half.map(|h| h.cos * h.sin),
            edge: [([0.0; N], [0; N]); 2],
            spin: spin.unsigned_abs() as usize,
        }
    }

    /// The start `Lambda_{l0,m}` of `col`, the next column in walk order.
    pub(crate) fn next(&mut self, col: &Column) -> ([f64; N], [i32; N]) {
        let side = usize::from(col.m > 0);
        let start = match col.start {
            Start::Seed { log, a, b, sign } => {
                seed_lanes(log, a, b, sign, &self.log_c, &self.log_s)
            }
            Start::Diagonal(g) => {
                let (d, e) = &mut self.edge[side];
                for j in 0..N {
                    d[j] *= g * self.cs[j];
                    if d[j] != 0.0 && d[j].abs() < SMALL {
                        d[j] *= BIG;
                        e[j] -= SCALE_BITS;
                    }
                }
                (*d, *e)
            }
        };
        if col.m.unsigned_abs() as usize == self.spin {
            // Spin 0: the seed m = 0 starts both sides.
            if self.spin == 0 {
                self.edge = [start; 2];
            } else {
                self.edge[side] = start;
            }
        }
        start
    }
}

/// The seed start `sign 2^log cos^a sin^b` per lane, as a mantissa in `(2^-SCALE_BITS, 1]`
/// (or larger with exponent 0) times `2^exp`, `exp` a non-positive multiple of
/// `SCALE_BITS`; zero where a positive power meets a zero half-angle function (the poles).
fn seed_lanes<const N: usize>(
    log: f64,
    a: i32,
    b: i32,
    sign: f64,
    log_c: &[f64; N],
    log_s: &[f64; N],
) -> ([f64; N], [i32; N]) {
    let mut p = [0.0; N];
    let mut exp = [0; N];
    for j in 0..N {
        let mut lg = log;
        for (pow, l) in [(a, log_c[j]), (b, log_s[j])] {
            if pow > 0 {
                lg += pow as f64 * l;
            }
        }
        if lg == f64::NEG_INFINITY {
            continue;
        }
        let k = ((-lg) / SCALE_BITS as f64).floor().max(0.0) as i32;
        p[j] = sign * (lg + (k * SCALE_BITS) as f64).exp2();
        exp[j] = -k * SCALE_BITS;
    }
    (p, exp)
}

/// `0.5 log2 binom(n, k)`.
fn half_log2_binom(n: usize, k: usize) -> f64 {
    0.5 * (1..=k)
        .map(|i| (((n - k + i) as f64) / i as f64).log2())
        .sum::<f64>()
}

/// The steps of order `m` for `m'` (see [`Column`]), on `Lambda = norm d`:
/// `A_l norm_l / norm_{l-1}` and `B_l norm_{l-1} / norm_{l-2}` for `l = l0 + 1..=lmax`.
fn recursion_coefficients(m: i64, mp: i64, l0: usize, lmax: usize, norms: &[f64]) -> Vec<[f64; 3]> {
    let (mf, mpf) = (m as f64, mp as f64);
    let steps = (l0 + 1..=lmax).map(|l| {
        let lf = l as f64;
        let big_a = lf * (2.0 * lf - 1.0) / ((lf * lf - mf * mf) * (lf * lf - mpf * mpf)).sqrt();
        if l == 1 {
            // Only from l0 = 0 (spin 0, m = 0): d^1_00 = cos theta = 1 - u, and
            // d^{-1} = 0 (the limits of B_1 and c_1 are 0 and 1).
            return [big_a * (norms[1] / norms[0]), 0.0, 1.0];
        }
        let l1 = lf - 1.0;
        let big_b = ((l1 * l1 - mf * mf) * (l1 * l1 - mpf * mpf)).sqrt() / (l1 * (2.0 * lf - 1.0));
        let c = 1.0 - mf * mpf / (lf * l1);
        [
            big_a * (norms[l] / norms[l - 1]),
            big_b * (norms[l - 1] / norms[l - 2]),
            c,
        ]
    });
    let n = lmax + 1 - l0;
    let mut coeffs: Vec<[f64; 3]> = std::iter::once([1.0, 1.0, 0.0]).chain(steps).collect();
    coeffs.resize(n.next_multiple_of(2), [0.0; 3]);
    coeffs
}

/// The column of order `m`, `|m| <= |m'|`, for `m' = -s`, started from the closed form of
/// `d^{l0}_{m m'}` (`proofs/swsh.md`) times `norm_{l0}`.
fn seed_column(m: i64, mp: i64, lmax: usize, norms: &[f64]) -> Column {
    let j = m.abs().max(mp.abs());
    let l0 = j as usize;
    let (k, a, b, sign) = if m.abs() >= mp.abs() {
        if m >= 0 {
            // d^j_{j,m'} = sqrt(C(2j, j+m')) c^{j+m'} (-s)^{j-m'}
            let b = j - mp;
            (j + mp, j + mp, b, if b % 2 == 0 { 1.0 } else { -1.0 })
        } else {
            // d^j_{-j,m'} = sqrt(C(2j, j-m')) c^{j-m'} s^{j+m'}
            (j - mp, j - mp, j + mp, 1.0)
        }
    } else if mp > 0 {
        // d^j_{m,j} = sqrt(C(2j, j+m)) c^{j+m} s^{j-m}
        (j + m, j + m, j - m, 1.0)
    } else {
        // d^j_{m,-j} = (-1)^{m+j} sqrt(C(2j, j-m)) c^{j-m} s^{j+m}
        let sign = if (m + j) % 2 == 0 { 1.0 } else { -1.0 };
        (j - m, j - m, j + m, sign)
    };
    let norm = norms[l0];
    Column {
        m,
        l0,
        start: Start::Seed {
            log: half_log2_binom(2 * l0, k as usize) + norm.abs().log2(),
            a: a as i32,
            b: b as i32,
            sign: sign * norm.signum(),
        },
        coeffs: recursion_coefficients(m, mp, l0, lmax, norms),
    }
}
