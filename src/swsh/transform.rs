//! Spin-s transforms on the exact grid: synthesis `f = sum a_lm sY_lm` and analysis
//! `a_lm = <sY_lm, f>` (PSH (32) for one spin component), with
//! `sY_lm = Lambda_lm(theta) e^{i m phi}`, `Lambda_lm = (-1)^s sqrt((2l+1)/(4 pi)) d^l_{m,-s}`
//! from the recursion of `swsh::recursion`.
//!
//! The grid is the one of [`crate::sh::grid`]: `d^l_{m,-s} d^l'_{m,-s}` is a polynomial of
//! degree `l + l'` in `cos theta`, so `lmax + 1` rings integrate the analysis exactly. Its
//! rings come in mirror pairs `theta, pi - theta`, on which
//! `Lambda_lm(pi - theta) = (-1)^{l+s} Lambda_{l,-m}(theta)` (`proofs/swsh.md`): the column
//! of order `m` at a northern ring serves order `-m` at its southern mirror.
//!
//! The transforms run order by order (orders in parallel, so that each coefficient and
//! each ring value is summed by one task in a fixed order, whatever the thread count): one
//! recursion over all northern rings at once, four rings per SIMD vector (`wide::f64x4`,
//! fused multiply-adds where the target has them), two degrees per pass, leaving out the
//! rings near the poles while their values are negligible (below `2^-64`, bound in
//! `proofs/swsh.md`).

use super::evaluator::SpinEvaluator;
use super::recursion::{Column, HalfAngle, StartWalk};
use crate::error::{check_len, finite_complex, Result};
use crate::sh::grid::SphereGrid;
use crate::sh::legendre::{lane_scale, rescale_lanes, LANE_BLOCK};
use crate::sh::{lm_index, num_coeffs};
use num_complex::Complex64;
use rayon::prelude::*;
use rustfft::{Fft, FftPlanner};
use std::sync::Arc;
use wide::f64x4;

/// A planned spin-`s` transform pair for band limit `lmax`.
pub struct SpinTransform {
    eval: SpinEvaluator,
    grid: SphereGrid,
    rings: RingLanes,
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

/// Band limits below this run on the calling thread: handing so little work to the thread
/// pool costs more than the work (measured on 2 vCPUs: 2.5x slower at `lmax = 8`).
const PARALLEL_LMAX: usize = 32;

/// Lanes (polar angles) per vector of the sweeps.
const LANES: usize = 4;

/// A recursion start per lane of a vector: mantissa and binary exponent.
type LaneStart = (f64x4, [i32; LANES]);

/// The grid's mirror ring pairs `theta, pi - theta` in chunks of [`LANES`] (a short last
/// chunk repeats its last ring; those lanes carry zero data and their results are dropped),
/// with what the sweeps of all orders share: `u = 1 - cos theta` of the northern rings and
/// the start of every column's recursion (walk order) at every chunk.
struct RingLanes {
    /// `(north, south)` ring indices (`north == south` for the equator ring of an odd rule).
    pairs: Vec<(usize, usize)>,
    u: Vec<f64x4>,
    /// Quadrature weights of the pairs (the same for both rings; the mirror weight is zero
    /// for the equator ring of an odd rule, which the north weight covers, and in padding
    /// lanes): `[north, north, mirror, mirror]` per lane vector, for `[re, im]` of both.
    weights: Vec<[f64x4; 4]>,
    starts: Vec<Vec<LaneStart>>,
}

impl RingLanes {
    fn new(eval: &SpinEvaluator, grid: &SphereGrid) -> Self {
        let r = &grid.rings;
        let n = r.theta.len();
        let pairs: Vec<(usize, usize)> = (0..n.div_ceil(2)).map(|j| (j, n - 1 - j)).collect();
        let half: Vec<[HalfAngle; LANES]> = pairs
            .chunks(LANES)
            .map(|c| {
                std::array::from_fn(|j| HalfAngle::from_theta(r.theta[c[j.min(c.len() - 1)].0]))
            })
            .collect();
        let u = half.iter().map(|h| f64x4::new(h.map(|h| h.u()))).collect();
        let mut starts = vec![Vec::with_capacity(half.len()); eval.columns.len()];
        for h in &half {
            let mut walk = StartWalk::new(h, eval.spin);
            for (col, s) in eval.columns.iter().zip(&mut starts) {
                let (p, e) = walk.next(col);
                s.push((f64x4::new(p), e));
            }
        }
        let weights = pairs
            .chunks(LANES)
            .map(|c| {
                let w = |mirror: bool| {
                    f64x4::new(std::array::from_fn(|j| match c.get(j) {
                        Some(&(jn, js)) if !mirror || js != jn => grid.weight(jn),
                        _ => 0.0,
                    }))
                };
                [w(false), w(false), w(true), w(true)]
            })
            .collect();
        Self {
            pairs,
            u,
            weights,
            starts,
        }
    }

    /// The ring pairs of lane `j` of chunk `c`, if in use.
    fn pair(&self, c: usize, j: usize) -> Option<(usize, usize)> {
        self.pairs.get(c * LANES + j).copied()
    }
}

impl SpinTransform {
    /// Spin-`s` transform for band limit `lmax` on the smallest exact grid.
    pub fn new(spin: i64, lmax: usize) -> Result<Self> {
        Self::with_grid(spin, lmax, SphereGrid::for_band_limit(lmax)?)
    }

    /// Spin-`s` transform on a given grid (checked to resolve `lmax`). `1 <= |s| <= lmax`
    /// (spin 0 is the scalar transform of [`crate::sh::ShTransform`]).
    pub fn with_grid(spin: i64, lmax: usize, grid: SphereGrid) -> Result<Self> {
        let eval = SpinEvaluator::new(spin, lmax)?;
        grid.check_band_limit(lmax)?;
        let mut planner = FftPlanner::new();
        Ok(Self {
            rings: RingLanes::new(&eval, &grid),
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

    /// `(-1)^{l+s}`, the mirror sign.
    fn mirror_sign(&self, l: usize) -> f64 {
        if (l as i64 + self.eval.spin) % 2 == 0 {
            1.0
        } else {
            -1.0
        }
    }

    /// `f(column, state)` for every column, in parallel by the pairs of orders `m`, `-m`
    /// (whose columns have the same length), with the column of each result.
    fn par_columns<T: Send>(
        &self,
        f: impl Fn(&Column, &mut ColumnState) -> T + Sync,
    ) -> Vec<(&Column, T)> {
        let e = &self.eval;
        let pair = |state: &mut ColumnState, m: i64| -> Vec<(&Column, T)> {
            let orders: &[i64] = if m == 0 { &[0] } else { &[m, -m] };
            orders
                .iter()
                .map(|&m| {
                    let col = &e.columns[e.column_index(m)];
                    (col, f(col, state))
                })
                .collect()
        };
        let orders = 0..=e.lmax as i64;
        let pairs: Vec<Vec<(&Column, T)>> = if e.lmax < PARALLEL_LMAX {
            let mut state = ColumnState::default();
            orders.map(|m| pair(&mut state, m)).collect()
        } else {
            orders
                .into_par_iter()
                .map_init(ColumnState::default, pair)
                .collect()
        };
        pairs.into_iter().flatten().collect()
    }

    /// `fft` of every ring of `values` (ring-major), in place.
    fn ring_ffts(&self, fft: &dyn Fft<f64>, values: &mut [Complex64]) {
        let scratch = || vec![Complex64::default(); fft.get_inplace_scratch_len()];
        if self.eval.lmax < PARALLEL_LMAX {
            let mut scratch = scratch();
            let rings = values.chunks_mut(self.grid.n_phi);
            rings.for_each(|ring| fft.process_with_scratch(ring, &mut scratch));
        } else {
            let rings = values.par_chunks_mut(self.grid.n_phi);
            rings.for_each_init(scratch, |s, ring| fft.process_with_scratch(ring, s));
        }
    }

    /// Runs the recursion of `col` over every ring pair, handing the degrees to `sweep`.
    fn sweep_column<S: Sweep>(&self, col: &Column, state: &mut ColumnState, sweep: &mut S) {
        let starts = &self.rings.starts[self.eval.column_index(col.m)];
        sweep_column(col, &self.rings.u, starts, state, sweep);
    }

    /// Synthesis: `f(theta_j, phi_k) = sum_{l >= |s|, m} a_lm sY_lm` onto the grid; entries
    /// of `coeffs` with `l < |s|` are ignored.
    ///
    /// Order by order (orders in parallel): the north ring takes
    /// `F_j(m) = sum_l a_lm Lambda_lm(theta_j)` and its mirror
    /// `F_j'(-m) = sum_l a_{l,-m} Lambda_{l,-m}(pi - theta_j) = sum_l (-1)^{l+s} a_{l,-m} Lambda_lm(theta_j)`;
    /// then one inverse FFT per ring.
    pub fn synthesis(&self, coeffs: &[Complex64], out: &mut [Complex64]) -> Result<()> {
        check_len("coefficients", num_coeffs(self.eval.lmax), coeffs.len())?;
        check_len("grid values", self.grid.len(), out.len())?;
        finite_complex("spin SH coefficient", coeffs)?;
        let np = self.grid.n_phi;
        let chunks = self.rings.u.len();
        let orders = self.par_columns(|col, state| {
            let mut coef: Vec<[f64; 4]> = (col.l0..=self.eval.lmax)
                .map(|l| {
                    let (n, s) = (
                        coeffs[lm_index(l, col.m)],
                        coeffs[lm_index(l, -col.m)] * self.mirror_sign(l),
                    );
                    [n.re, n.im, s.re, s.im]
                })
                .collect();
            coef.resize(col.coeffs.len(), [0.0; 4]);
            let mut sweep = SynthesisSweep {
                coef: &coef,
                rings: vec![[f64x4::ZERO; 4]; chunks],
            };
            self.sweep_column(col, state, &mut sweep);
            sweep.rings
        });
        out.fill(Complex64::default());
        for (col, rings) in &orders {
            let (bn, bs) = (self.bin(col.m), self.bin(-col.m));
            for (c, v) in rings.iter().enumerate() {
                let v = v.map(f64x4::to_array);
                for j in 0..LANES {
                    let Some((jn, js)) = self.rings.pair(c, j) else {
                        break;
                    };
                    out[jn * np + bn] = Complex64::new(v[0][j], v[1][j]);
                    if js != jn {
                        out[js * np + bs] = Complex64::new(v[2][j], v[3][j]);
                    }
                }
            }
        }
        self.ring_ffts(self.inverse.as_ref(), out);
        Ok(())
    }

    /// Analysis: `a_lm = <sY_lm, f>` by the exact rule; zeros where `l < |s|`.
    ///
    /// One FFT per ring gives `G_j(m)`; then order by order (orders in parallel)
    /// `a_lm = sum_j w_j (Lambda_lm(theta_j) G_j(m) + (-1)^{l+s} Lambda_{l,-m}(theta_j) G_j'(m))`
    /// over northern rings `j` with mirrors `j'`: the column of order `m` gives the north
    /// sum of `a_{l,m}` and the mirror sum of `a_{l,-m}`. Each coefficient is summed by one
    /// task in a fixed order, so the result does not depend on the thread count.
    pub fn analysis(&self, values: &[Complex64], out: &mut [Complex64]) -> Result<()> {
        check_len("grid values", self.grid.len(), values.len())?;
        check_len("coefficients", num_coeffs(self.eval.lmax), out.len())?;
        finite_complex("grid value", values)?;
        let np = self.grid.n_phi;
        let mut spectra = values.to_vec();
        self.ring_ffts(self.forward.as_ref(), &mut spectra);
        let sums = self.par_columns(|col, state| {
            let (bn, bs) = (self.bin(col.m), self.bin(-col.m));
            // [re, im] of the north spectra at m and of the mirror spectra at -m, weighted.
            let phases: Vec<[f64x4; 4]> = self
                .rings
                .weights
                .iter()
                .enumerate()
                .map(|(c, &w)| {
                    let mut g = [[0.0; LANES]; 4];
                    for j in 0..LANES {
                        let Some((jn, js)) = self.rings.pair(c, j) else {
                            break;
                        };
                        let (n, s) = (spectra[jn * np + bn], spectra[js * np + bs]);
                        [g[0][j], g[1][j], g[2][j], g[3][j]] = [n.re, n.im, s.re, s.im];
                    }
                    std::array::from_fn(|q| f64x4::new(g[q]) * w[q])
                })
                .collect();
            let mut sweep = AnalysisSweep {
                phases: &phases,
                sums: vec![[Complex64::default(); 2]; col.coeffs.len()],
            };
            self.sweep_column(col, state, &mut sweep);
            sweep.sums
        });
        out.fill(Complex64::default());
        // a_{l,m}: the north sum of column m plus the mirror sum of column -m.
        for (col, s) in &sums {
            for (l, [north, south]) in (col.l0..=self.eval.lmax).zip(s) {
                out[lm_index(l, col.m)] += north;
                out[lm_index(l, -col.m)] += south * self.mirror_sign(l);
            }
        }
        Ok(())
    }
}

/// What a sweep does with the values `Lambda_lm(theta_j)` of one column at every lane
/// vector, two degrees at a time (`k = l - l0` and `k + 1`, `k` even), vector by vector. The
/// last pair may reach `l = lmax + 1`, where the values are zero.
trait Sweep {
    /// Per-pair state, held in registers over the vectors.
    type Degrees;
    /// Before the vectors of degrees `k`, `k + 1`.
    fn begin(&mut self, k: usize) -> Self::Degrees;
    /// The values of vector `c` at the two degrees.
    fn chunk(&mut self, d: &mut Self::Degrees, c: usize, values: [f64x4; 2]);
    /// After the vectors of degrees `k`, `k + 1`.
    fn end(&mut self, k: usize, d: Self::Degrees);
}

/// Synthesis: per vector, `[re, im]` of `sum_l a_lm Lambda_lm` (north) and of
/// `sum_l (-1)^{l+s} a_{l,-m} Lambda_lm` (mirror), from `coef[k] = [a.re, a.im, b.re, b.im]`
/// (padded with zeros to the pairs).
struct SynthesisSweep<'a> {
    coef: &'a [[f64; 4]],
    rings: Vec<[f64x4; 4]>,
}

impl Sweep for SynthesisSweep<'_> {
    type Degrees = [[f64x4; 4]; 2];

    #[inline(always)]
    fn begin(&mut self, k: usize) -> Self::Degrees {
        [
            self.coef[k].map(f64x4::splat),
            self.coef[k + 1].map(f64x4::splat),
        ]
    }

    #[inline(always)]
    fn chunk(&mut self, d: &mut Self::Degrees, c: usize, [v0, v1]: [f64x4; 2]) {
        for ((acc, a0), a1) in self.rings[c].iter_mut().zip(&d[0]).zip(&d[1]) {
            *acc = v0.mul_add(*a0, v1.mul_add(*a1, *acc));
        }
    }

    #[inline(always)]
    fn end(&mut self, _: usize, _: Self::Degrees) {}
}

/// Analysis: `sums[k] = [sum_j Lambda G_j(m) w_j, sum_j Lambda G_j'(-m) w_j]` from
/// `phases[c] = [re, im]` of the weighted north and mirror spectra of vector `c` (`sums`
/// padded to the pairs).
struct AnalysisSweep<'a> {
    phases: &'a [[f64x4; 4]],
    sums: Vec<[Complex64; 2]>,
}

impl Sweep for AnalysisSweep<'_> {
    type Degrees = [[f64x4; 4]; 2];

    #[inline(always)]
    fn begin(&mut self, _: usize) -> Self::Degrees {
        [[f64x4::ZERO; 4]; 2]
    }

    #[inline(always)]
    fn chunk(&mut self, d: &mut Self::Degrees, c: usize, values: [f64x4; 2]) {
        for (dk, v) in d.iter_mut().zip(values) {
            for (acc, g) in dk.iter_mut().zip(&self.phases[c]) {
                *acc = v.mul_add(*g, *acc);
            }
        }
    }

    #[inline(always)]
    fn end(&mut self, k: usize, d: Self::Degrees) {
        for (sum, dk) in self.sums[k..k + 2].iter_mut().zip(d) {
            let s = dk.map(f64x4::reduce_add);
            *sum = [Complex64::new(s[0], s[1]), Complex64::new(s[2], s[3])];
        }
    }
}

/// The recursion state of one column at every lane vector (reused between columns).
#[derive(Default)]
struct ColumnState {
    p1: Vec<f64x4>,
    p2: Vec<f64x4>,
    exp: Vec<[i32; LANES]>,
    fac: Vec<f64x4>,
}

/// Values `|Lambda_lm(theta_j)| < 2^-64` that a sweep may leave out: the lane vectors of
/// the rings nearest the poles while all their values are below it (the decaying side of the
/// turning point `|m| ~ l sin theta`). Leaving them out changes an analysis coefficient by
/// less than `2^-64 sum_j w_j (|G_j(m)| + |G_j'(m)|) <= 2^-64 * 4 pi max |f|` and a
/// synthesis value by less than `2^-64 sum_lm |a_lm|`, far below rounding (proofs/swsh.md).
const NEGLIGIBLE: f64 = f64::from_bits((1023 - 64) << 52);

/// Runs the recursion of `col` at every lane vector (`u`, `starts` per vector) and hands
/// the degrees pair by pair to `sweep`.
///
/// Values below the f64 range carry a binary exponent (a multiple of `SCALE_BITS`) and
/// reach `sweep` times their output factor ([`lane_scale`]: values still below
/// `2^-SCALE_BITS` are negligible and come out as zero or subnormal). The vectors
/// `0..scaled` (rings from the pole) are those with such lanes: their exponents are
/// checked every [`LANE_BLOCK`] degrees, and the others run without the factors.
///
/// The vectors `0..live` only run the recursion while
/// all their values at both degrees of each pair are below [`NEGLIGIBLE`]; `live` starts
/// past the last vector and moves to the first vector that reaches it (checked at every
/// pair, so nothing at or above it is left out).
fn sweep_column<S: Sweep>(
    col: &Column,
    u: &[f64x4],
    starts: &[LaneStart],
    st: &mut ColumnState,
    sweep: &mut S,
) {
    // p_{-1} = 0, p_{-2} = -start: the first step [1, 1, 0] gives the start.
    st.p1.clear();
    st.p1.resize(starts.len(), f64x4::ZERO);
    st.p2.clear();
    st.p2.extend(starts.iter().map(|s| -s.0));
    st.exp.clear();
    st.exp.extend(starts.iter().map(|s| s.1));
    st.fac.clear();
    st.fac
        .extend(st.exp.iter().map(|e| f64x4::new(lane_scale(e))));
    let scaled_end = |exp: &[[i32; LANES]]| {
        exp.iter()
            .rposition(|e| e.iter().any(|&e| e < 0))
            .map_or(0, |c| c + 1)
    };
    let mut scaled = scaled_end(&st.exp);
    let mut live = starts.len();
    let n = col.coeffs.len();
    let mut k = 0;
    while k < n {
        let end = if scaled > 0 {
            (k + LANE_BLOCK).min(n)
        } else {
            n
        };
        sweep_degrees(&col.coeffs, u, st, sweep, k..end, scaled, &mut live);
        if scaled > 0 {
            let lanes = st.p1.iter_mut().zip(&mut st.p2);
            let state = lanes.zip(st.exp.iter_mut().zip(&mut st.fac)).take(scaled);
            for ((p1, p2), (e, f)) in state {
                let (mut a, mut b) = (p1.to_array(), p2.to_array());
                rescale_lanes(&mut a, &mut b, e);
                (*p1, *p2, *f) = (f64x4::new(a), f64x4::new(b), f64x4::new(lane_scale(e)));
            }
            scaled = scaled_end(&st.exp[..scaled]);
        }
        k = end;
    }
}

/// Degrees `range` (even bounds) of the recursion
/// `p_l = A_l ((c_l - u) p_{l-1} - B_l p_{l-2})`, two per pass over the vectors; the
/// vectors `0..scaled` take their output factors, the vectors `0..live` only recurse while
/// negligible (see [`sweep_column`]).
#[inline(always)]
fn sweep_degrees<S: Sweep>(
    coeffs: &[[f64; 3]],
    u: &[f64x4],
    st: &mut ColumnState,
    sweep: &mut S,
    range: std::ops::Range<usize>,
    scaled: usize,
    live: &mut usize,
) {
    let (p1, p2, fac) = (&mut st.p1[..], &mut st.p2[..], &st.fac[..]);
    for k in range.step_by(2) {
        let [a0, b0, c0] = coeffs[k].map(f64x4::splat);
        let [a1, b1, c1] = coeffs[k + 1].map(f64x4::splat);
        let step = |p1: &mut f64x4, p2: &mut f64x4, u: f64x4| {
            let p = a0 * b0.mul_neg_add(*p2, (c0 - u) * *p1);
            let q = a1 * b1.mul_neg_add(*p1, (c1 - u) * p);
            *p2 = p;
            *p1 = q;
        };
        // Near the poles: the largest value of vector c at either degree, per lane.
        let peak = |p: f64x4, q: f64x4, f: f64x4| (p * f).abs().fast_max((q * f).abs());
        let reaches = |v: f64x4| v.to_array().iter().any(|&b| b >= NEGLIGIBLE);
        let mut big = f64x4::ZERO;
        let near = p1[..*live].iter_mut().zip(&mut p2[..*live]);
        for ((p1, p2), (&u, &f)) in near.zip(u.iter().zip(fac)) {
            step(p1, p2, u);
            big = big.fast_max(peak(*p1, *p2, f));
        }
        let mut d = sweep.begin(k);
        let mid = scaled.clamp(*live, u.len());
        for c in *live..mid {
            step(&mut p1[c], &mut p2[c], u[c]);
            sweep.chunk(&mut d, c, [p2[c] * fac[c], p1[c] * fac[c]]);
        }
        let far = p1[mid..].iter_mut().zip(&mut p2[mid..]).zip(&u[mid..]);
        for (i, ((p1, p2), &u)) in far.enumerate() {
            step(p1, p2, u);
            sweep.chunk(&mut d, mid + i, [*p2, *p1]);
        }
        if reaches(big) {
            let was = *live;
            *live = (0..was)
                .find(|&c| reaches(peak(p1[c], p2[c], fac[c])))
                .unwrap_or(was);
            for c in *live..was {
                sweep.chunk(&mut d, c, [p2[c] * fac[c], p1[c] * fac[c]]);
            }
        }
        sweep.end(k, d);
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
            let re = crate::random::pseudo_random(num_coeffs(lmax), 3);
            let im = crate::random::pseudo_random(num_coeffs(lmax), 4);
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
            let re = crate::random::pseudo_random(num_coeffs(lmax), 5);
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

    /// Every coefficient and ring value is summed by one task in a fixed order.
    #[test]
    fn results_do_not_depend_on_the_thread_count() {
        let lmax = 40;
        let t = SpinTransform::new(2, lmax).unwrap();
        let re = crate::random::pseudo_random(num_coeffs(lmax), 8);
        let c: Vec<Complex64> = re.iter().map(|&a| Complex64::new(a, -0.3 * a)).collect();
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut f = vec![Complex64::default(); t.grid().len()];
                t.synthesis(&c, &mut f).unwrap();
                let mut back = vec![Complex64::default(); c.len()];
                t.analysis(&f, &mut back).unwrap();
                (f, back)
            })
        };
        assert_eq!(run(1), run(3));
    }

    #[test]
    fn bad_spins_are_errors() {
        assert!(SpinTransform::new(0, 4).is_err());
        assert!(SpinTransform::new(5, 4).is_err());
    }

    #[test]
    fn non_finite_inputs_are_errors_naming_the_value() {
        let t = SpinTransform::new(2, 4).unwrap();
        let mut c = vec![Complex64::default(); num_coeffs(4)];
        let mut f = vec![Complex64::default(); t.grid().len()];
        c[9] = Complex64::new(f64::NAN, 0.0);
        let e = t.synthesis(&c, &mut f).unwrap_err().to_string();
        assert!(
            e.contains("spin SH coefficient") && e.contains("NaN"),
            "{e}"
        );
        f[3] = Complex64::new(0.0, f64::INFINITY);
        let e = t.analysis(&f, &mut c).unwrap_err().to_string();
        assert!(e.contains("grid value") && e.contains("inf"), "{e}");
    }
}
