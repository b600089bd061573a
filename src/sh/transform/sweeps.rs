//! The order-major transforms on the exact grid, for any spin `s` (spin 0: the scalar SH
//! of [`crate::sh::ShTransform`], `Lambda_lm = Pbar_lm`; spin `s`: `crate::swsh::SpinTransform`):
//! synthesis `f = sum a_lm sY_lm` and analysis `a_lm = <sY_lm, f>` (PSH (2), (3), and
//! PSH (32) for one spin component), `sY_lm = Lambda_lm(theta) e^{i m phi}` with the
//! recursion of [`crate::sh::recursion::lambda`].
//!
//! The grid is the one of [`crate::sh::transform::grid`]: `Lambda_lm Lambda_l'm` is a polynomial of
//! degree `l + l'` in `cos theta` (times `sin^2s`-free half-angle powers that pair up,
//! `proofs/swsh.md`), so `lmax + 1` rings integrate the analysis exactly. Its rings come
//! in mirror pairs `theta, pi - theta`, on which
//! `Lambda_lm(pi - theta) = (-1)^{l+s} Lambda_{l,-m}(theta)` (`proofs/swsh.md`): the column
//! of order `m` at a northern ring serves order `-m` at its southern mirror. At spin 0
//! `Lambda_{l,-m} = (-1)^m Lambda_lm`, so a column serves its own order at the mirror with
//! the sign `(-1)^{l+m}` (DLMF 14.7.17): a real field needs the orders `m >= 0` only, and
//! per degree one of the two parity sums `north +- south`.
//!
//! The transforms run order by order (orders in parallel, so that each coefficient and
//! each ring value is summed by one task in a fixed order, whatever the thread count): one
//! recursion over all northern rings at once, four rings per vector (AVX's or the
//! compiled lanes, chosen at run time: `crate::lanes`; no fused multiply-adds, so the
//! same bits on every CPU), two degrees per pass, leaving out the
//! rings near the poles while their values are negligible (below `2^-64`, bound in
//! `proofs/swsh.md`).

use crate::error::Result;
use crate::lanes::{with_lanes, F64x4, LaneSet, WithLanes};
use crate::sh::index::lm_index;
use crate::sh::recursion::lambda::{Column, Columns, HalfAngle, StartWalk};
use crate::sh::recursion::legendre::{lane_scale, rescale_lanes, LANE_BLOCK};
use crate::sh::transform::grid::SphereGrid;
use num_complex::Complex64;
use rayon::prelude::*;
use rustfft::{Fft, FftPlanner};
use std::sync::Arc;

/// Band limits below this run on the calling thread: handing so little work to the thread
/// pool costs more than the work (measured on 2 vCPUs: 2.5x slower at `lmax = 8`).
const PARALLEL_LMAX: usize = 32;

/// Lanes (polar angles) per vector of the sweeps.
const LANES: usize = 4;

/// A recursion start per lane of a vector: mantissa and binary exponent.
type LaneStart = (F64x4, [i32; LANES]);

/// The grid's mirror ring pairs `theta, pi - theta` in chunks of [`LANES`] (a short last
/// chunk repeats its last ring; those lanes carry zero data and their results are dropped),
/// with what the sweeps of all orders share: `u = 1 - cos theta` of the northern rings and
/// the start of every column's recursion (walk order) at every chunk.
struct RingLanes {
    /// `(north, south)` ring indices (`north == south` for the equator ring of an odd rule).
    pairs: Vec<(usize, usize)>,
    u: Vec<F64x4>,
    /// Quadrature weights of the pairs (the same for both rings; the mirror weight is zero
    /// for the equator ring of an odd rule, which the north weight covers, and both are
    /// zero in padding lanes): `[north, mirror]` per lane vector.
    weights: Vec<[F64x4; 2]>,
    starts: Vec<Vec<LaneStart>>,
}

impl RingLanes {
    fn new(columns: &Columns, grid: &SphereGrid) -> Self {
        let r = &grid.rings;
        let n = r.theta.len();
        let pairs: Vec<(usize, usize)> = (0..n.div_ceil(2)).map(|j| (j, n - 1 - j)).collect();
        let half: Vec<[HalfAngle; LANES]> = pairs
            .chunks(LANES)
            .map(|c| {
                std::array::from_fn(|j| HalfAngle::from_theta(r.theta[c[j.min(c.len() - 1)].0]))
            })
            .collect();
        let u = half.iter().map(|h| F64x4::new(h.map(|h| h.u()))).collect();
        let mut starts = vec![Vec::with_capacity(half.len()); columns.list.len()];
        for h in &half {
            let mut walk = StartWalk::new(h, columns.spin);
            for (col, s) in columns.list.iter().zip(&mut starts) {
                let (p, e) = walk.next(col);
                s.push((F64x4::new(p), e));
            }
        }
        let weights = pairs
            .chunks(LANES)
            .map(|c| {
                let w = |mirror: bool| {
                    F64x4::new(std::array::from_fn(|j| match c.get(j) {
                        Some(&(jn, js)) if !mirror || js != jn => grid.weight(jn),
                        _ => 0.0,
                    }))
                };
                [w(false), w(true)]
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

/// A planned transform pair of one spin on a grid: the columns of the recursion, the
/// ring pairs with every column's starts, and the ring FFTs.
pub(crate) struct OrderTransform {
    columns: Arc<Columns>,
    grid: SphereGrid,
    rings: RingLanes,
    forward: Arc<dyn Fft<f64>>,
    inverse: Arc<dyn Fft<f64>>,
}

/// Checks the memory of the recursion tables of a transform of band limit `lmax` on `grid`
/// against [`crate::budget`] before they are built: per order at most `lmax + 2` steps
/// `[A, B, c]` and a start per lane vector of ring pairs (`2 * 24` bytes), `2 lmax + 1`
/// orders.
pub(crate) fn check_tables(lmax: usize, grid: &SphereGrid) -> Result<()> {
    let vectors = grid.rings.len().div_ceil(2).div_ceil(LANES);
    let per_order = (lmax + 2).saturating_add(vectors.saturating_mul(2));
    crate::budget::check(
        "the transform's recursion tables",
        &[2 * lmax + 1, per_order],
        24,
    )?;
    Ok(())
}

impl OrderTransform {
    /// The transforms of `columns` on `grid` (checked to resolve their band limit).
    pub(crate) fn new(columns: Arc<Columns>, grid: SphereGrid) -> Result<Self> {
        grid.check_band_limit(columns.lmax)?;
        let mut planner = FftPlanner::new();
        Ok(Self {
            rings: RingLanes::new(&columns, &grid),
            forward: planner.plan_fft_forward(grid.n_phi),
            inverse: planner.plan_fft_inverse(grid.n_phi),
            columns,
            grid,
        })
    }

    /// The grid (values ring-major).
    pub(crate) fn grid(&self) -> &SphereGrid {
        &self.grid
    }

    /// The band limit.
    pub(crate) fn lmax(&self) -> usize {
        self.columns.lmax
    }

    fn bin(&self, m: i64) -> usize {
        m.rem_euclid(self.grid.n_phi as i64) as usize
    }

    /// `(-1)^{l+s}`, the mirror sign.
    fn mirror_sign(&self, l: usize) -> f64 {
        parity(l as i64 + self.columns.spin)
    }

    /// `f(column, state)` for the columns of `orders` (each with its column), in parallel
    /// by the entries of `orders`.
    fn par_columns<T: Send>(
        &self,
        orders: &[&[i64]],
        f: impl Fn(&Column, &mut ColumnState) -> T + Sync,
    ) -> Vec<(&Column, T)> {
        let run = |state: &mut ColumnState, ms: &&[i64]| -> Vec<(&Column, T)> {
            ms.iter()
                .map(|&m| {
                    let col = self.columns.of(m);
                    (col, f(col, state))
                })
                .collect()
        };
        let results: Vec<Vec<(&Column, T)>> = if self.lmax() < PARALLEL_LMAX {
            let mut state = ColumnState::default();
            orders.iter().map(|ms| run(&mut state, ms)).collect()
        } else {
            orders
                .par_iter()
                .map_init(ColumnState::default, run)
                .collect()
        };
        results.into_iter().flatten().collect()
    }

    /// `fft` of every ring of `values` (ring-major, `n_phi` per ring), in place, each ring
    /// first set by `prepare(ring index, ring)` (rings in parallel).
    fn ring_ffts(
        &self,
        fft: &dyn Fft<f64>,
        values: &mut [Complex64],
        prepare: impl Fn(usize, &mut [Complex64]) + Sync,
    ) {
        let scratch = || vec![Complex64::default(); fft.get_inplace_scratch_len()];
        let run = |s: &mut Vec<Complex64>, (r, ring): (usize, &mut [Complex64])| {
            prepare(r, ring);
            fft.process_with_scratch(ring, s)
        };
        if self.lmax() < PARALLEL_LMAX {
            let mut scratch = scratch();
            let rings = values.chunks_mut(self.grid.n_phi).enumerate();
            rings.for_each(|r| run(&mut scratch, r));
        } else {
            let rings = values.par_chunks_mut(self.grid.n_phi).enumerate();
            rings.for_each_init(scratch, run);
        }
    }

    /// Runs the recursion of `col` over every ring pair, handing the degrees to `sweep`, in
    /// the CPU's best lanes.
    fn sweep_column<S: Sweep>(&self, col: &Column, st: &mut ColumnState, sweep: &mut S) {
        let starts = &self.rings.starts[self.columns.index(col.m)];
        with_lanes(ColumnSweep {
            col,
            unit_c: self.columns.spin == 0,
            u: &self.rings.u,
            starts,
            st,
            sweep,
        });
    }

    /// Synthesis `f(theta_j, phi_k) = sum_{l >= |s|, m} a_lm sY_lm` onto the grid (lengths
    /// unchecked); entries of `coeffs` with `l < |s|` are ignored.
    ///
    /// Order by order (the pairs `m`, `-m` in parallel): the north ring takes
    /// `F_j(m) = sum_l a_lm Lambda_lm(theta_j)` and its mirror
    /// `F_j'(-m) = sum_l a_{l,-m} Lambda_{l,-m}(pi - theta_j) = sum_l (-1)^{l+s} a_{l,-m} Lambda_lm(theta_j)`;
    /// then one inverse FFT per ring.
    pub(crate) fn synthesis(&self, coeffs: &[Complex64], out: &mut [Complex64]) {
        let (lmax, np) = (self.lmax(), self.grid.n_phi);
        let chunks = self.rings.u.len();
        let pairs = signed_order_pairs(lmax);
        let pairs: Vec<&[i64]> = pairs.iter().map(|p| p.as_slice()).collect();
        let orders = self.par_columns(&pairs, |col, state| {
            let mut coef: Vec<[f64; 4]> = (col.l0..=lmax)
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
                rings: vec![[F64x4::ZERO; 4]; chunks],
            };
            self.sweep_column(col, state, &mut sweep);
            sweep.rings
        });
        out.fill(Complex64::default());
        for (col, rings) in &orders {
            let (bn, bs) = (self.bin(col.m), self.bin(-col.m));
            for (c, v) in rings.iter().enumerate() {
                let v = v.map(F64x4::to_array);
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
        self.ring_ffts(self.inverse.as_ref(), out, |_, _| {});
    }

    /// Analysis `a_lm = <sY_lm, f>` by the exact rule (lengths unchecked); zeros where
    /// `l < |s|`.
    ///
    /// One FFT per ring gives `G_j(m)`; then order by order (the pairs `m`, `-m` in
    /// parallel)
    /// `a_lm = sum_j w_j (Lambda_lm(theta_j) G_j(m) + (-1)^{l+s} Lambda_{l,-m}(theta_j) G_j'(m))`
    /// over northern rings `j` with mirrors `j'`: the column of order `m` gives the north
    /// sum of `a_{l,m}` and the mirror sum of `a_{l,-m}`.
    pub(crate) fn analysis(&self, values: &[Complex64], out: &mut [Complex64]) {
        let (lmax, np) = (self.lmax(), self.grid.n_phi);
        let mut spectra = values.to_vec();
        self.ring_ffts(self.forward.as_ref(), &mut spectra, |_, _| {});
        let pairs = signed_order_pairs(lmax);
        let pairs: Vec<&[i64]> = pairs.iter().map(|p| p.as_slice()).collect();
        let sums = self.par_columns(&pairs, |col, state| {
            let (bn, bs) = (self.bin(col.m), self.bin(-col.m));
            // [re, im] of the north spectra at m and of the mirror spectra at -m, weighted.
            let phases = self.weighted_phases(true, |c, j| {
                let (jn, js) = self.rings.pair(c, j)?;
                let (n, s) = (spectra[jn * np + bn], spectra[js * np + bs]);
                Some([n.re, n.im, s.re, s.im])
            });
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
            for (l, [north, south]) in (col.l0..=lmax).zip(s) {
                out[lm_index(l, col.m)] += north;
                out[lm_index(l, -col.m)] += south * self.mirror_sign(l);
            }
        }
    }

    /// Synthesis of a real field from its orders `m >= 0` (spin 0 only, lengths
    /// unchecked): `f = Re sum_{m >= 0} eps_m e^{i m phi} sum_l a_lm Pbar_lm(theta)` with
    /// `eps_0 = 1`, `eps_m = 2`, where `half(l, m)` gives `a_lm` (`m = 0`: its real part is
    /// used).
    ///
    /// Order by order (in parallel): the even and odd degree sums
    /// `E_j(m) = sum_{l - m even} a_lm Pbar_lm(theta_j)`, `O_j(m)` likewise, give the north
    /// ring `E + O` and its mirror `E - O`; the two rings of a pair share one complex
    /// inverse FFT (`north + i south`).
    pub(crate) fn synthesis_real(
        &self,
        half: impl Fn(usize, usize) -> Complex64 + Sync,
        out: &mut [f64],
    ) {
        let (lmax, np) = (self.lmax(), self.grid.n_phi);
        let chunks = self.rings.u.len();
        let orders: Vec<[i64; 1]> = (0..=lmax as i64).map(|m| [m]).collect();
        let orders: Vec<&[i64]> = orders.iter().map(|m| m.as_slice()).collect();
        let columns = self.par_columns(&orders, |col, state| {
            let m = col.m as usize;
            let mut coef: Vec<[f64; 2]> = (m..=lmax)
                .map(|l| {
                    let a = half(l, m);
                    [a.re, if m == 0 { 0.0 } else { a.im }]
                })
                .collect();
            coef.resize(col.coeffs.len(), [0.0; 2]);
            let mut sweep = ParitySynthesisSweep {
                coef: &coef,
                rings: vec![[F64x4::ZERO; 4]; chunks],
            };
            self.sweep_column(col, state, &mut sweep);
            sweep.rings
        });
        // Per ring pair p (lane j of vector c): north + i south at m, its conjugate
        // combination at -m, then the inverse FFT; pairs in parallel.
        let mut z = vec![Complex64::default(); self.rings.pairs.len() * np];
        let i = Complex64::i();
        self.ring_ffts(self.inverse.as_ref(), &mut z, |p, ring| {
            let (c, j) = (p / LANES, p % LANES);
            let (jn, js) = self.rings.pairs[p];
            for (col, rings) in &columns {
                let v = rings[c].map(|x| x.to_array()[j]);
                let (e, o) = (Complex64::new(v[0], v[1]), Complex64::new(v[2], v[3]));
                let north = e + o;
                let south = if js == jn {
                    Complex64::default()
                } else {
                    e - o
                };
                if col.m == 0 {
                    ring[0] = Complex64::new(north.re, south.re);
                } else {
                    ring[self.bin(col.m)] = north + i * south;
                    ring[self.bin(-col.m)] = north.conj() + i * south.conj();
                }
            }
        });
        // Ring r is the real part of its pair if northern, the imaginary part if southern.
        let pairs = self.rings.pairs.len();
        let n = self.grid.rings.len();
        let copy = |(r, ring): (usize, &mut [f64])| {
            let (p, south) = if r < pairs {
                (r, false)
            } else {
                (n - 1 - r, true)
            };
            let z = &z[p * np..(p + 1) * np];
            for (o, v) in ring.iter_mut().zip(z) {
                *o = if south { v.im } else { v.re };
            }
        };
        if lmax < PARALLEL_LMAX {
            out.chunks_mut(np).enumerate().for_each(copy);
        } else {
            out.par_chunks_mut(np).enumerate().for_each(copy);
        }
    }

    /// Analysis of a real field into its orders `m >= 0` (spin 0 only, lengths unchecked):
    /// `set(l, m, a_lm)` with `a_lm = <Y_lm, f>`.
    ///
    /// One complex FFT per ring pair (`north + i south`) gives both spectra `G_j(m)`,
    /// `G_j'(m)`; then order by order (in parallel)
    /// `a_lm = sum_j w_j Pbar_lm(theta_j) (G_j(m) +- G_j'(m))`, `+` where `l - m` is even.
    pub(crate) fn analysis_real(
        &self,
        values: &[f64],
        mut set: impl FnMut(usize, usize, Complex64),
    ) {
        let (lmax, np) = (self.lmax(), self.grid.n_phi);
        // Per ring pair: north + i south, then the forward FFT; pairs in parallel.
        let mut z = vec![Complex64::default(); self.rings.pairs.len() * np];
        self.ring_ffts(self.forward.as_ref(), &mut z, |p, ring| {
            let (jn, js) = self.rings.pairs[p];
            let north = &values[jn * np..(jn + 1) * np];
            if js == jn {
                for (z, &n) in ring.iter_mut().zip(north) {
                    *z = Complex64::new(n, 0.0);
                }
            } else {
                let south = &values[js * np..(js + 1) * np];
                for ((z, &n), &s) in ring.iter_mut().zip(north).zip(south) {
                    *z = Complex64::new(n, s);
                }
            }
        });
        let orders: Vec<[i64; 1]> = (0..=lmax as i64).map(|m| [m]).collect();
        let orders: Vec<&[i64]> = orders.iter().map(|m| m.as_slice()).collect();
        let sums = self.par_columns(&orders, |col, state| {
            let (bp, bm) = (self.bin(col.m), self.bin(-col.m));
            // [re, im] of the even and odd combinations of the north and mirror spectra.
            let phases = self.weighted_phases(false, |c, j| {
                self.rings.pair(c, j)?;
                let ring = &z[(c * LANES + j) * np..];
                let (zp, zm) = (ring[bp], ring[bm].conj());
                let gn = 0.5 * (zp + zm);
                let gs = Complex64::new(0.0, -0.5) * (zp - zm);
                let (e, o) = (gn + gs, gn - gs);
                Some([e.re, e.im, o.re, o.im])
            });
            let mut sweep = ParityAnalysisSweep {
                phases: &phases,
                sums: vec![Complex64::default(); col.coeffs.len()],
            };
            self.sweep_column(col, state, &mut sweep);
            sweep.sums
        });
        for (col, s) in &sums {
            let m = col.m as usize;
            for (l, &a) in (m..=lmax).zip(s) {
                set(l, m, a);
            }
        }
    }

    /// Per lane vector, `g(chunk, lane)` (four values, `None` past the last pair) times the
    /// quadrature weights of the lanes: `[north, north, mirror, mirror]` if `mirrored`
    /// (the last two values belong to the mirror rings), else the north weight for all.
    fn weighted_phases(
        &self,
        mirrored: bool,
        g: impl Fn(usize, usize) -> Option<[f64; 4]>,
    ) -> Vec<[F64x4; 4]> {
        let weights = self.rings.weights.iter().enumerate();
        weights
            .map(|(c, &[north, mirror])| {
                let w = [
                    north,
                    north,
                    if mirrored { mirror } else { north },
                    if mirrored { mirror } else { north },
                ];
                let mut v = [[0.0; LANES]; 4];
                for j in 0..LANES {
                    let Some(g) = g(c, j) else { break };
                    for q in 0..4 {
                        v[q][j] = g[q];
                    }
                }
                std::array::from_fn(|q| F64x4::new(std::array::from_fn(|j| v[q][j] * w[q].0[j])))
            })
            .collect()
    }
}

/// `(-1)^n`.
fn parity(n: i64) -> f64 {
    if n % 2 == 0 {
        1.0
    } else {
        -1.0
    }
}

/// The orders in pairs `[m, -m]` (`[0]` alone), `m = 0..=lmax`: the columns of a pair have
/// the same length.
fn signed_order_pairs(lmax: usize) -> Vec<Vec<i64>> {
    (0..=lmax as i64)
        .map(|m| if m == 0 { vec![0] } else { vec![m, -m] })
        .collect()
}

/// What a sweep does with the values `Lambda_lm(theta_j)` of one column at every lane
/// vector, two degrees at a time (`k = l - l0` and `k + 1`, `k` even), vector by vector, in
/// the lanes of a [`LaneSet`]. The last pair may reach `l = lmax + 1`, where the values are
/// zero.
trait Sweep {
    /// Per-pair state, held in registers over the vectors.
    type Degrees<L: LaneSet>;
    /// Before the vectors of degrees `k`, `k + 1`.
    fn begin<L: LaneSet>(&mut self, set: L, k: usize) -> Self::Degrees<L>;
    /// The values of vector `c` at the two degrees.
    fn chunk<L: LaneSet>(&mut self, set: L, d: &mut Self::Degrees<L>, c: usize, values: [L::V; 2]);
    /// After the vectors of degrees `k`, `k + 1`.
    fn end<L: LaneSet>(&mut self, set: L, k: usize, d: Self::Degrees<L>);
}

/// Real synthesis: per vector, `[re, im]` of the even-degree sum `sum_{k even} a_k Lambda_k`
/// and of the odd-degree sum, from `coef[k] = [a.re, a.im]` (padded with zeros to the pairs;
/// `k = l - l0` and `l0 = m` at spin 0, so the parity of `k` is that of `l + m`).
struct ParitySynthesisSweep<'a> {
    coef: &'a [[f64; 2]],
    rings: Vec<[F64x4; 4]>,
}

impl Sweep for ParitySynthesisSweep<'_> {
    type Degrees<L: LaneSet> = [L::V; 4];

    #[inline(always)]
    fn begin<L: LaneSet>(&mut self, set: L, k: usize) -> [L::V; 4] {
        let [e, o] = [self.coef[k], self.coef[k + 1]];
        [e[0], e[1], o[0], o[1]].map(|x| set.splat(x))
    }

    #[inline(always)]
    fn chunk<L: LaneSet>(&mut self, set: L, d: &mut [L::V; 4], c: usize, [v0, v1]: [L::V; 2]) {
        let acc = &mut self.rings[c];
        for (q, v) in [v0, v0, v1, v1].into_iter().enumerate() {
            acc[q] = set.store(set.mul_add(v, d[q], set.load(&acc[q])));
        }
    }

    #[inline(always)]
    fn end<L: LaneSet>(&mut self, _: L, _: usize, _: [L::V; 4]) {}
}

/// Real analysis: `sums[k] = sum_j Lambda_k(theta_j) P_j` with `P` the weighted even
/// combination of the north and mirror spectra for even `k`, the odd one for odd `k`, from
/// `phases[c] = [even.re, even.im, odd.re, odd.im]` (`sums` padded to the pairs).
struct ParityAnalysisSweep<'a> {
    phases: &'a [[F64x4; 4]],
    sums: Vec<Complex64>,
}

impl Sweep for ParityAnalysisSweep<'_> {
    type Degrees<L: LaneSet> = [L::V; 4];

    #[inline(always)]
    fn begin<L: LaneSet>(&mut self, set: L, _: usize) -> [L::V; 4] {
        [set.zero(); 4]
    }

    #[inline(always)]
    fn chunk<L: LaneSet>(&mut self, set: L, d: &mut [L::V; 4], c: usize, [v0, v1]: [L::V; 2]) {
        let g = &self.phases[c];
        for (q, v) in [v0, v0, v1, v1].into_iter().enumerate() {
            d[q] = set.mul_add(v, set.load(&g[q]), d[q]);
        }
    }

    #[inline(always)]
    fn end<L: LaneSet>(&mut self, set: L, k: usize, d: [L::V; 4]) {
        let s = d.map(|v| set.reduce_add(v));
        self.sums[k] = Complex64::new(s[0], s[1]);
        self.sums[k + 1] = Complex64::new(s[2], s[3]);
    }
}

/// Synthesis: per vector, `[re, im]` of `sum_l a_lm Lambda_lm` (north) and of
/// `sum_l (-1)^{l+s} a_{l,-m} Lambda_lm` (mirror), from `coef[k] = [a.re, a.im, b.re, b.im]`
/// (padded with zeros to the pairs).
struct SynthesisSweep<'a> {
    coef: &'a [[f64; 4]],
    rings: Vec<[F64x4; 4]>,
}

impl Sweep for SynthesisSweep<'_> {
    type Degrees<L: LaneSet> = [[L::V; 4]; 2];

    #[inline(always)]
    fn begin<L: LaneSet>(&mut self, set: L, k: usize) -> [[L::V; 4]; 2] {
        [
            self.coef[k].map(|x| set.splat(x)),
            self.coef[k + 1].map(|x| set.splat(x)),
        ]
    }

    #[inline(always)]
    fn chunk<L: LaneSet>(&mut self, set: L, d: &mut [[L::V; 4]; 2], c: usize, [v0, v1]: [L::V; 2]) {
        for ((acc, &a0), &a1) in self.rings[c].iter_mut().zip(&d[0]).zip(&d[1]) {
            *acc = set.store(set.mul_add(v0, a0, set.mul_add(v1, a1, set.load(acc))));
        }
    }

    #[inline(always)]
    fn end<L: LaneSet>(&mut self, _: L, _: usize, _: [[L::V; 4]; 2]) {}
}

/// Analysis: `sums[k] = [sum_j Lambda G_j(m) w_j, sum_j Lambda G_j'(-m) w_j]` from
/// `phases[c] = [re, im]` of the weighted north and mirror spectra of vector `c` (`sums`
/// padded to the pairs).
struct AnalysisSweep<'a> {
    phases: &'a [[F64x4; 4]],
    sums: Vec<[Complex64; 2]>,
}

impl Sweep for AnalysisSweep<'_> {
    type Degrees<L: LaneSet> = [[L::V; 4]; 2];

    #[inline(always)]
    fn begin<L: LaneSet>(&mut self, set: L, _: usize) -> [[L::V; 4]; 2] {
        [[set.zero(); 4]; 2]
    }

    #[inline(always)]
    fn chunk<L: LaneSet>(&mut self, set: L, d: &mut [[L::V; 4]; 2], c: usize, values: [L::V; 2]) {
        for (dk, v) in d.iter_mut().zip(values) {
            for (acc, g) in dk.iter_mut().zip(&self.phases[c]) {
                *acc = set.mul_add(v, set.load(g), *acc);
            }
        }
    }

    #[inline(always)]
    fn end<L: LaneSet>(&mut self, set: L, k: usize, d: [[L::V; 4]; 2]) {
        for (sum, dk) in self.sums[k..k + 2].iter_mut().zip(d) {
            let s = dk.map(|v| set.reduce_add(v));
            *sum = [Complex64::new(s[0], s[1]), Complex64::new(s[2], s[3])];
        }
    }
}

/// The recursion state of one column at every lane vector (reused between columns).
#[derive(Default)]
struct ColumnState {
    p1: Vec<F64x4>,
    p2: Vec<F64x4>,
    exp: Vec<[i32; LANES]>,
    fac: Vec<F64x4>,
}

/// Values `|Lambda_lm(theta_j)| < 2^-64` that a sweep may leave out: the lane vectors of
/// the rings nearest the poles while all their values are below it (the decaying side of the
/// turning point `|m| ~ l sin theta`). Leaving them out changes an analysis coefficient by
/// less than `2^-64 sum_j w_j (|G_j(m)| + |G_j'(m)|) <= 2^-64 * 4 pi max |f|` and a
/// synthesis value by less than `2^-64 sum_lm |a_lm|`, far below rounding (proofs/swsh.md).
const NEGLIGIBLE: f64 = f64::from_bits((1023 - 64) << 52);

/// One column's sweep as a kernel over the lane sets ([`with_lanes`]).
struct ColumnSweep<'a, S> {
    col: &'a Column,
    /// Spin 0: every step's `c` is 1 (but the first, whose `p_{l-1}` is 0, and the
    /// padding, whose `A` is 0), so `c p_{l-1}` is `p_{l-1}`, bit for bit.
    unit_c: bool,
    u: &'a [F64x4],
    starts: &'a [LaneStart],
    st: &'a mut ColumnState,
    sweep: &'a mut S,
}

impl<S: Sweep> WithLanes for ColumnSweep<'_, S> {
    type Output = ();

    #[inline(always)]
    fn run<L: LaneSet>(self, set: L) {
        if self.unit_c {
            sweep_column::<L, S, true>(set, self.col, self.u, self.starts, self.st, self.sweep)
        } else {
            sweep_column::<L, S, false>(set, self.col, self.u, self.starts, self.st, self.sweep)
        }
    }
}

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
/// pair, so nothing at or above it is left out). `UNIT_C`: every `c` is 1 (spin 0), its
/// product left out.
#[inline(always)]
fn sweep_column<L: LaneSet, S: Sweep, const UNIT_C: bool>(
    set: L,
    col: &Column,
    u: &[F64x4],
    starts: &[LaneStart],
    st: &mut ColumnState,
    sweep: &mut S,
) {
    // p_{-1} = 0, p_{-2} = -start: the first step [1, 1, 0] gives the start.
    st.p1.clear();
    st.p1.resize(starts.len(), F64x4::ZERO);
    st.p2.clear();
    st.p2
        .extend(starts.iter().map(|s| F64x4(s.0 .0.map(|x| -x))));
    st.exp.clear();
    st.exp.extend(starts.iter().map(|s| s.1));
    st.fac.clear();
    st.fac.extend(st.exp.iter().map(|e| F64x4(lane_scale(e))));
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
        sweep_degrees::<L, S, UNIT_C>(set, &col.coeffs, u, st, sweep, k..end, scaled, &mut live);
        if scaled > 0 {
            let lanes = st.p1.iter_mut().zip(&mut st.p2);
            let state = lanes.zip(st.exp.iter_mut().zip(&mut st.fac)).take(scaled);
            for ((p1, p2), (e, f)) in state {
                rescale_lanes(&mut p1.0, &mut p2.0, e);
                *f = F64x4(lane_scale(e));
            }
            scaled = scaled_end(&st.exp[..scaled]);
        }
        k = end;
    }
}

/// Degrees `range` (even bounds) of the recursion
/// `p_l = A_l ((c_l p_{l-1} - B_l p_{l-2}) - u p_{l-1})`, two per pass over the vectors; the
/// vectors `0..scaled` take their output factors, the vectors `0..live` only recurse while
/// negligible (see [`sweep_column`]).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn sweep_degrees<L: LaneSet, S: Sweep, const UNIT_C: bool>(
    set: L,
    coeffs: &[[f64; 3]],
    u: &[F64x4],
    st: &mut ColumnState,
    sweep: &mut S,
    range: std::ops::Range<usize>,
    scaled: usize,
    live: &mut usize,
) {
    let (p1, p2, fac) = (&mut st.p1[..], &mut st.p2[..], &st.fac[..]);
    for k in range.step_by(2) {
        let [a0, b0, c0] = coeffs[k].map(|x| set.splat(x));
        let [a1, b1, c1] = coeffs[k + 1].map(|x| set.splat(x));
        let times_c = |c: L::V, x: L::V| if UNIT_C { x } else { c * x };
        // The values at degrees k, k + 1 of a vector, stored as its new state.
        let step = |p1: &mut F64x4, p2: &mut F64x4, u: &F64x4| {
            let (q1, q2, u) = (set.load(p1), set.load(p2), set.load(u));
            // (c p1 - B p2) - u p1, not (c - u) p1 - B p2: at c = 1 (spin 0) `1 - u` would
            // round cos(theta) and lose near the poles what u keeps (`sh::recursion::legendre`).
            let p = a0 * set.mul_neg_add(u, q1, set.mul_neg_add(b0, q2, times_c(c0, q1)));
            let q = a1 * set.mul_neg_add(u, p, set.mul_neg_add(b1, q1, times_c(c1, p)));
            (*p2, *p1) = (set.store(p), set.store(q));
            [p, q]
        };
        // Near the poles: per lane, the largest value of vector c at either degree (one
        // product per vector).
        let peak = |[p, q]: [L::V; 2], x: &F64x4| set.max(set.abs(p), set.abs(q)) * set.load(x);
        let reaches = |v: L::V| set.store(v).0.iter().any(|&b| b >= NEGLIGIBLE);
        let scaled_values = |p1: &F64x4, p2: &F64x4, x: &F64x4| {
            let x = set.load(x);
            [set.load(p2) * x, set.load(p1) * x]
        };
        let mut big = set.zero();
        let near = p1[..*live].iter_mut().zip(&mut p2[..*live]);
        for ((p1, p2), (u, x)) in near.zip(u.iter().zip(fac)) {
            big = set.max(big, peak(step(p1, p2, u), x));
        }
        let mut d = sweep.begin(set, k);
        let mid = scaled.clamp(*live, u.len());
        for c in *live..mid {
            step(&mut p1[c], &mut p2[c], &u[c]);
            sweep.chunk(set, &mut d, c, scaled_values(&p1[c], &p2[c], &fac[c]));
        }
        let far = p1[mid..].iter_mut().zip(&mut p2[mid..]).zip(&u[mid..]);
        for (i, ((p1, p2), u)) in far.enumerate() {
            let values = step(p1, p2, u);
            sweep.chunk(set, &mut d, mid + i, values);
        }
        if reaches(big) {
            let was = *live;
            *live = (0..was)
                .find(|&c| reaches(peak([set.load(&p1[c]), set.load(&p2[c])], &fac[c])))
                .unwrap_or(was);
            for c in *live..was {
                sweep.chunk(set, &mut d, c, scaled_values(&p1[c], &p2[c], &fac[c]));
            }
        }
        sweep.end(set, k, d);
    }
}
