//! Spin-s transforms on the exact grid: synthesis `f = sum a_lm sY_lm` and analysis
//! `a_lm = <sY_lm, f>` (PSH (32) for one spin component), with
//! `sY_lm = Lambda_lm(theta) e^{i m phi}`, `Lambda_lm = (-1)^s sqrt((2l+1)/(4 pi)) d^l_{m,-s}`.
//!
//! Per polar angle, `Lambda_lm` for `l = l0..=lmax` (`l0 = max(|m|, |s|)`) comes from the
//! three-term recursion of the Wigner d in `l` at fixed `(m, m')`, in the `u = 1 - cos theta`
//! form of [`crate::sh::legendre`] (derived in `proofs/swsh.md`):
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
//! once in lock step (lanes), as [`crate::sh::legendre::Legendre::for_each_column_lanes`].
//!
//! The grid is the one of [`crate::sh::grid`]: `d^l_{m,-s} d^l'_{m,-s}` is a polynomial of
//! degree `l + l'` in `cos theta`, so `lmax + 1` rings integrate the analysis exactly. Its
//! rings come in mirror pairs `theta, pi - theta`, on which
//! `Lambda_lm(pi - theta) = (-1)^{l+s} Lambda_{l,-m}(theta)` (`proofs/swsh.md`): the column
//! of order `m` at a northern ring serves order `-m` at its southern mirror.

use crate::error::{check_len, Error, Result};
use crate::sh::grid::SphereGrid;
use crate::sh::legendre::{lane_scale, rescale_lanes, BIG, LANE_BLOCK, SCALE_BITS, SMALL};
use crate::sh::transform::{forward_ring_pairs, OrderMajor};
use crate::sh::{lm_index, num_coeffs};
use num_complex::Complex64;
use rayon::prelude::*;
use rustfft::{Fft, FftPlanner};
use std::f64::consts::PI;
use std::sync::Arc;

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

/// Recursion data of one order `m`: its start degree and start, and `[A_l, B_l, c_l]`
/// (norms folded in) for `l = l0 + 1..=lmax`.
#[derive(Clone, Debug)]
struct Column {
    m: i64,
    l0: usize,
    start: Start,
    coeffs: Vec<[f64; 3]>,
}

/// The recursion tables of the spin-`s` harmonics up to `lmax`: evaluates
/// `Lambda_lm(theta)` for every order at any polar angle, `O(lmax^2)` per angle.
#[derive(Clone, Debug)]
pub struct SpinEvaluator {
    spin: i64,
    lmax: usize,
    /// In walk order: `m = -|s|..=|s|` (seeds), then `-(|s|+1), |s|+1, -(|s|+2), ...`.
    columns: Vec<Column>,
}

/// A planned spin-`s` transform pair for band limit `lmax`.
pub struct SpinTransform {
    eval: SpinEvaluator,
    grid: SphereGrid,
    forward: Arc<dyn Fft<f64>>,
    inverse: Arc<dyn Fft<f64>>,
}

impl std::fmt::Debug for SpinTransform {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SpinTransform")
            .field("spin", &self.eval.spin)
            .field("lmax", &self.eval.lmax)
            .finish()
    }
}

/// Ring pairs per lane block of the spin recursion.
const RINGS: usize = 16;

/// Groups of ring blocks summed in parallel by [`SpinTransform::analysis`]: a fixed
/// number, so that the result does not depend on the thread count. Each group keeps its
/// own coefficient sums (16 MB at l = 512) and streams them once per ring block, so more
/// groups cost memory traffic (measured on 2 vCPUs: 4 groups 57 ms, 8 groups 62 ms, 2
/// groups 48 ms at l = 512).
const GROUPS: usize = 2;

/// A block of ring pairs: the half angles of their northern rings, padded to `RINGS` lanes,
/// and the `(north, south)` ring indices of the lanes in use (`north == south` for the
/// equator ring of an odd rule).
type RingBlock = ([HalfAngle; RINGS], Vec<(usize, usize)>);

impl SpinTransform {
    /// Spin-`s` transform for band limit `lmax` on the smallest exact grid.
    pub fn new(spin: i64, lmax: usize) -> Result<Self> {
        Self::with_grid(spin, lmax, SphereGrid::for_band_limit(lmax)?)
    }

    /// Spin-`s` transform on a given grid (checked to resolve `lmax`). `1 <= |s| <= lmax`
    /// (spin 0 is the scalar transform of [`crate::sh::transform`]).
    pub fn with_grid(spin: i64, lmax: usize, grid: SphereGrid) -> Result<Self> {
        let eval = SpinEvaluator::new(spin, lmax)?;
        grid.check_band_limit(lmax)?;
        let mut planner = FftPlanner::new();
        Ok(Self {
            eval,
            forward: planner.plan_fft_forward(grid.n_phi),
            inverse: planner.plan_fft_inverse(grid.n_phi),
            grid,
        })
    }

    /// The grid (values ring-major).
    pub fn grid(&self) -> &SphereGrid {
        &self.grid
    }

    /// The spin weight.
    pub fn spin(&self) -> i64 {
        self.eval.spin
    }

    /// The evaluator of the harmonics.
    pub fn evaluator(&self) -> &SpinEvaluator {
        &self.eval
    }

    fn bin(&self, m: i64) -> usize {
        m.rem_euclid(self.grid.n_phi as i64) as usize
    }

    /// Mirror ring pairs in blocks of `RINGS` lanes; a short last block repeats its last
    /// ring in the unused lanes (their results are dropped).
    fn ring_blocks(&self) -> Vec<RingBlock> {
        let r = &self.grid.rings;
        let n = r.len();
        let pairs: Vec<(usize, usize)> = (0..n.div_ceil(2)).map(|j| (j, n - 1 - j)).collect();
        pairs
            .chunks(RINGS)
            .map(|c| {
                let half = std::array::from_fn(|j| {
                    HalfAngle::from_theta(r.theta[c[j.min(c.len() - 1)].0])
                });
                (half, c.to_vec())
            })
            .collect()
    }

    /// `(-1)^{l+s}`, the mirror sign.
    fn mirror_sign(&self, l: usize) -> f64 {
        if (l as i64 + self.eval.spin) % 2 == 0 {
            1.0
        } else {
            -1.0
        }
    }

    /// Synthesis: `f(theta_j, phi_k) = sum_{l >= |s|, m} a_lm sY_lm` onto the grid; entries
    /// of `coeffs` with `l < |s|` are ignored.
    pub fn synthesis(&self, coeffs: &[Complex64], out: &mut [Complex64]) -> Result<()> {
        check_len("coefficients", num_coeffs(self.eval.lmax), coeffs.len())?;
        check_len("grid values", self.grid.len(), out.len())?;
        let np = self.grid.n_phi;
        // North ring: sum_l a_lm Lambda_lm; south ring at order -m:
        // sum_l a_{l,-m} Lambda_{l,-m}(pi - theta) = sum_l (-1)^{l+s} a_{l,-m} Lambda_lm(theta).
        let north_c = self.eval.by_order(|l, m| coeffs[lm_index(l, m)]);
        let south_c = self
            .eval
            .by_order(|l, m| coeffs[lm_index(l, -m)] * self.mirror_sign(l));
        // Ring blocks in parallel, each with its own buffers; rings are disjoint.
        let rings: Vec<Vec<(usize, Vec<Complex64>)>> = self
            .ring_blocks()
            .par_iter()
            .map(|(half, pairs)| {
                let mut north = vec![vec![Complex64::default(); np]; RINGS];
                let mut south = north.clone();
                let mut scratch = Vec::new();
                self.eval
                    .for_each_order_lanes(half, &mut scratch, |m, _, col| {
                        let (n, s) = dot2_lanes(col, north_c.column(m), south_c.column(m));
                        let (bn, bs) = (self.bin(m), self.bin(-m));
                        for j in 0..pairs.len() {
                            north[j][bn] = n[j];
                            south[j][bs] = s[j];
                        }
                    });
                let mut done = Vec::with_capacity(2 * pairs.len());
                for ((&(jn, js), mut n), mut s) in pairs.iter().zip(north).zip(south) {
                    self.inverse.process(&mut n);
                    done.push((jn, n));
                    if js != jn {
                        self.inverse.process(&mut s);
                        done.push((js, s));
                    }
                }
                done
            })
            .collect();
        for (j, values) in rings.into_iter().flatten() {
            out[j * np..(j + 1) * np].copy_from_slice(&values);
        }
        Ok(())
    }

    /// Analysis: `a_lm = <sY_lm, f>` by the exact rule; zeros where `l < |s|`.
    pub fn analysis(&self, values: &[Complex64], out: &mut [Complex64]) -> Result<()> {
        check_len("grid values", self.grid.len(), values.len())?;
        check_len("coefficients", num_coeffs(self.eval.lmax), out.len())?;
        let np = self.grid.n_phi;
        // a_lm = sum_j w_j (Lambda_lm(theta_j) G_j(m) + (-1)^{l+s} Lambda_{l,-m}(theta_j) G'_j(m))
        // over northern rings j with mirrors j': the column of order m feeds the north sum
        // of a_{l,m} and the mirror sum of a_{l,-m}.
        let zero = |_, _| Complex64::default();
        // A fixed number of groups of ring blocks in parallel, each with its own sums,
        // added in group order (the rounding does not depend on the thread count).
        let blocks = self.ring_blocks();
        let per_group = blocks.len().div_ceil(GROUPS).max(1);
        let sums: Vec<(OrderMajor, OrderMajor)> = blocks
            .par_chunks(per_group)
            .map(|group| {
                let mut north_acc = self.eval.by_order(zero);
                let mut south_acc = self.eval.by_order(zero);
                let mut north = vec![vec![Complex64::default(); np]; RINGS];
                let mut south = north.clone();
                let mut scratch = Vec::new();
                for (half, pairs) in group {
                    let w: [f64; RINGS] = forward_ring_pairs(
                        &self.grid,
                        self.forward.as_ref(),
                        values,
                        pairs,
                        (&mut north, &mut south),
                    );
                    self.eval
                        .for_each_order_lanes(half, &mut scratch, |m, _, col| {
                            let (bn, bs) = (self.bin(m), self.bin(-m));
                            let mut gn = [Complex64::default(); RINGS];
                            let mut gs = [Complex64::default(); RINGS];
                            for j in 0..pairs.len() {
                                gn[j] = north[j][bn] * w[j];
                                gs[j] = south[j][bs] * w[j];
                            }
                            accumulate2_lanes(
                                col,
                                &gn,
                                &gs,
                                north_acc.column_mut(m),
                                south_acc.column_mut(-m),
                            );
                        });
                }
                (north_acc, south_acc)
            })
            .collect();
        let mut sums = sums.into_iter();
        let (mut north_acc, mut south_acc) = sums
            .next()
            .unwrap_or_else(|| (self.eval.by_order(zero), self.eval.by_order(zero)));
        for (n, s) in sums {
            north_acc.add(&n);
            south_acc.add(&s);
        }
        out.fill(Complex64::default());
        for col in &self.eval.columns {
            let (n, s) = (north_acc.column(col.m), south_acc.column(col.m));
            for (k, (a, b)) in n.iter().zip(s).enumerate() {
                let l = col.l0 + k;
                out[lm_index(l, col.m)] = a + b * self.mirror_sign(l);
            }
        }
        Ok(())
    }
}

/// Per lane, `(sum_k col[k][j] a[k], sum_k col[k][j] b[k])`.
#[inline]
fn dot2_lanes(
    col: &[[f64; RINGS]],
    a: &[Complex64],
    b: &[Complex64],
) -> ([Complex64; RINGS], [Complex64; RINGS]) {
    let (mut ar, mut ai, mut br, mut bi) = ([0.0; RINGS], [0.0; RINGS], [0.0; RINGS], [0.0; RINGS]);
    for ((p, x), y) in col.iter().zip(a).zip(b) {
        for j in 0..RINGS {
            ar[j] += p[j] * x.re;
            ai[j] += p[j] * x.im;
            br[j] += p[j] * y.re;
            bi[j] += p[j] * y.im;
        }
    }
    (
        std::array::from_fn(|j| Complex64::new(ar[j], ai[j])),
        std::array::from_fn(|j| Complex64::new(br[j], bi[j])),
    )
}

/// `acc_a[k] += sum_j col[k][j] ga[j]` and `acc_b[k] += sum_j col[k][j] gb[j]`.
#[inline]
fn accumulate2_lanes(
    col: &[[f64; RINGS]],
    ga: &[Complex64; RINGS],
    gb: &[Complex64; RINGS],
    acc_a: &mut [Complex64],
    acc_b: &mut [Complex64],
) {
    let g: [[f64; RINGS]; 4] = [
        std::array::from_fn(|j| ga[j].re),
        std::array::from_fn(|j| ga[j].im),
        std::array::from_fn(|j| gb[j].re),
        std::array::from_fn(|j| gb[j].im),
    ];
    for ((p, a), b) in col.iter().zip(acc_a).zip(acc_b) {
        // Four partial sums per dot, so that the reductions vectorize.
        let mut s = [[0.0; 4]; 4];
        for c in 0..RINGS / 4 {
            for (sr, gr) in s.iter_mut().zip(&g) {
                for q in 0..4 {
                    sr[q] += p[4 * c + q] * gr[4 * c + q];
                }
            }
        }
        let d = s.map(|v| (v[0] + v[1]) + (v[2] + v[3]));
        *a += Complex64::new(d[0], d[1]);
        *b += Complex64::new(d[2], d[3]);
    }
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
        Ok(Self {
            spin,
            lmax,
            columns,
        })
    }

    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// `f(l, m)` regrouped by order, `l = max(|m|, |s|)..=lmax` (the recursion's order).
    fn by_order(&self, f: impl Fn(usize, i64) -> Complex64) -> OrderMajor {
        let s = self.spin.unsigned_abs() as usize;
        OrderMajor::new(self.lmax, |m| (m.unsigned_abs() as usize).max(s), f)
    }

    /// Walks the orders at `N` polar angles at once (given by their half angles):
    /// `f(m, l0, column)` with `column[l - l0][j] = Lambda_lm` at `half[j]`,
    /// `l0 = max(|m|, |s|)`, in the walk order of the columns (`|m|` increasing).
    ///
    /// As in [`crate::sh::legendre::Legendre::for_each_column_lanes`], values below the
    /// f64 range carry a binary exponent (a multiple of `SCALE_BITS`), checked once per
    /// [`LANE_BLOCK`] steps; values still below `2^-SCALE_BITS` when handed over are
    /// negligible (they come out as zero or subnormal). `scratch` holds the column.
    pub(crate) fn for_each_order_lanes<const N: usize>(
        &self,
        half: &[HalfAngle; N],
        scratch: &mut Vec<[f64; N]>,
        mut f: impl FnMut(i64, usize, &[[f64; N]]),
    ) {
        scratch.resize(self.lmax + 1, [0.0; N]);
        let log_c = half.map(|h| h.cos.log2());
        let log_s = half.map(|h| h.sin.log2());
        let u: [f64; N] = std::array::from_fn(|j| 2.0 * half[j].sin * half[j].sin);
        let cs: [f64; N] = std::array::from_fn(|j| half[j].cos * half[j].sin);
        // Starts (mantissa, exponent) of the outermost orders so far, m < 0 and m > 0.
        let mut edge = [([0.0; N], [0i32; N]); 2];
        let s = self.spin.unsigned_abs() as usize;
        for col in &self.columns {
            let side = usize::from(col.m > 0);
            let (mut p1, mut exp) = match col.start {
                Start::Seed { log, a, b, sign } => seed_lanes(log, a, b, sign, &log_c, &log_s),
                Start::Diagonal(g) => {
                    let (d, e) = &mut edge[side];
                    for j in 0..N {
                        d[j] *= g * cs[j];
                        if d[j] != 0.0 && d[j].abs() < SMALL {
                            d[j] *= BIG;
                            e[j] -= SCALE_BITS;
                        }
                    }
                    (*d, *e)
                }
            };
            if col.m.unsigned_abs() as usize == s {
                edge[side] = (p1, exp);
            }
            let out = &mut scratch[..=self.lmax - col.l0];
            let mut p2 = [0.0; N];
            let mut scaled = exp.iter().any(|&e| e < 0);
            let mut fac = lane_scale(&exp);
            for j in 0..N {
                out[0][j] = p1[j] * fac[j];
            }
            let mut k = 1;
            while k < out.len() {
                let end = (k + LANE_BLOCK).min(out.len());
                for (o, &[a, b, c]) in out[k..end].iter_mut().zip(&col.coeffs[k - 1..end - 1]) {
                    for j in 0..N {
                        let p = a * ((c - u[j]) * p1[j] - b * p2[j]);
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

    /// Walks the orders at polar angle `theta` (in `[0, pi]`, unchecked): `f(m, l0, lambda)`
    /// with `lambda[l - l0] = Lambda_lm(theta)`, `l0 = max(|m|, |s|)` (one lane of
    /// [`SpinEvaluator::for_each_order_lanes`]).
    pub(crate) fn for_each_order(&self, theta: f64, mut f: impl FnMut(i64, usize, &[f64])) {
        let mut scratch = Vec::new();
        self.for_each_order_lanes(
            &[HalfAngle::from_theta(theta)],
            &mut scratch,
            |m, l0, col| f(m, l0, col.as_flattened()),
        );
    }

    /// `sY_lm(theta, phi)` for all `l <= lmax` in flat order (zeros where `l < |s|`), into
    /// `out` of length `(lmax+1)^2`: `O(lmax^2)`, against `O(lmax^3)` for [`crate::swsh::swsh`].
    pub fn values(&self, theta: f64, phi: f64, out: &mut [Complex64]) -> Result<()> {
        crate::sh::check_theta(theta)?;
        crate::error::finite("phi", phi)?;
        check_len("spin SH output", num_coeffs(self.lmax), out.len())?;
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

/// `[A_l, B_l, c_l]` of order `m` for `m'`, `l = l0 + 1..=lmax`, on `Lambda = norm d`:
/// `A_l norm_l / norm_{l-1}` and `B_l norm_{l-1} / norm_{l-2}`.
fn recursion_coefficients(m: i64, mp: i64, l0: usize, lmax: usize, norms: &[f64]) -> Vec<[f64; 3]> {
    let (mf, mpf) = (m as f64, mp as f64);
    (l0 + 1..=lmax)
        .map(|l| {
            let lf = l as f64;
            let big_a =
                lf * (2.0 * lf - 1.0) / ((lf * lf - mf * mf) * (lf * lf - mpf * mpf)).sqrt();
            let l1 = lf - 1.0;
            let big_b =
                ((l1 * l1 - mf * mf) * (l1 * l1 - mpf * mpf)).sqrt() / (l1 * (2.0 * lf - 1.0));
            let c = 1.0 - mf * mpf / (lf * l1);
            [
                big_a * (norms[l] / norms[l - 1]),
                big_b * (norms[l - 1] / norms[l - 2]),
                c,
            ]
        })
        .collect()
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::swsh::swsh;

    #[test]
    fn synthesis_matches_pointwise_swsh() {
        for spin in [2i64, -2, 1, 3] {
            let lmax = 9;
            let t = SpinTransform::new(spin, lmax).unwrap();
            let re = crate::verify::pseudo_random(num_coeffs(lmax), 3);
            let im = crate::verify::pseudo_random(num_coeffs(lmax), 4);
            let c: Vec<Complex64> = re
                .iter()
                .zip(&im)
                .map(|(&a, &b)| Complex64::new(a, b))
                .collect();
            let mut f = vec![Complex64::default(); t.grid().len()];
            t.synthesis(&c, &mut f).unwrap();
            for i in (0..t.grid().len()).step_by(7) {
                let (th, ph) = t.grid().angles(i).unwrap();
                let y = swsh(spin, lmax, th, ph).unwrap();
                let v: Complex64 = y.iter().zip(&c).map(|(a, b)| a * b).sum();
                let tol = 1e-13 * v.norm().max(1.0);
                assert!(
                    (v - f[i]).norm() < tol,
                    "spin {spin} point {i}: {v} vs {}",
                    f[i]
                );
            }
        }
    }

    #[test]
    fn round_trip_is_exact() {
        for (spin, lmax) in [(2i64, 2usize), (2, 33), (-2, 20), (1, 12)] {
            let t = SpinTransform::new(spin, lmax).unwrap();
            let re = crate::verify::pseudo_random(num_coeffs(lmax), 5);
            let c: Vec<Complex64> = re
                .iter()
                .enumerate()
                .map(|(i, &a)| {
                    let (l, _) = crate::sh::lm_of_index(i);
                    if (l as i64) < spin.abs() {
                        Complex64::default()
                    } else {
                        Complex64::new(a, 0.5 * a)
                    }
                })
                .collect();
            let mut f = vec![Complex64::default(); t.grid().len()];
            t.synthesis(&c, &mut f).unwrap();
            let mut back = vec![Complex64::default(); c.len()];
            t.analysis(&f, &mut back).unwrap();
            for (x, y) in c.iter().zip(&back) {
                assert!((x - y).norm() < 1e-13, "spin {spin} lmax {lmax}");
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

    /// The mirror relation `Lambda_lm(pi - theta) = (-1)^{l+s} Lambda_{l,-m}(theta)` that
    /// pairs the rings (proofs/swsh.md), on Risbo's values.
    #[test]
    fn mirror_rings_swap_orders() {
        let lmax = 12;
        for spin in [1i64, 2, -2, 3] {
            for theta in [0.0, 0.3, 1.2, std::f64::consts::FRAC_PI_2] {
                let north = swsh(spin, lmax, theta, 0.0).unwrap();
                let south = swsh(spin, lmax, std::f64::consts::PI - theta, 0.0).unwrap();
                for l in spin.unsigned_abs() as usize..=lmax {
                    let sign = if (l as i64 + spin) % 2 == 0 {
                        1.0
                    } else {
                        -1.0
                    };
                    for m in -(l as i64)..=l as i64 {
                        let (a, b) = (south[lm_index(l, m)], north[lm_index(l, -m)] * sign);
                        assert!((a - b).norm() < 1e-14, "spin {spin} l {l} m {m}");
                    }
                }
            }
        }
    }

    #[test]
    fn bad_spins_are_errors() {
        assert!(SpinTransform::new(0, 4).is_err());
        assert!(SpinTransform::new(5, 4).is_err());
    }
}
