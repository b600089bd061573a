//! Order-major texel sums, the core of the projections PSH (3) and PSH (32): for texels at
//! directions `w_i` and complex rows of values `z_{ir}` (weights folded in),
//!
//! ```text
//! a_{lm r} = sum_i conj(sY_lm(w_i)) z_{ir} = sum_i Lambda_lm(theta_i) e^{-i m phi_i} z_{ir}
//! ```
//!
//! (`sY_lm = Lambda_lm(theta) e^{i m phi}`, [`crate::sh::recursion::lambda`]) for every
//! `l <= lmax` of the orders chosen. The orders are split into ranges of about equal work,
//! run in parallel. A range's task walks the texels, [`LANES`] at a time, runs the
//! recursion of its own orders only and holds the sums of its own coefficients: the work
//! space is about that of the output, not one partial sum of every coefficient per thread.
//! Where the output is small (low degrees), the texels are split into blocks as well, their
//! partial sums added in block order. The ranges and blocks depend on the sizes only, so
//! that the result is the same bit for bit for any number of threads.

use crate::sh::recursion::lambda::{Columns, HalfAngle};
use num_complex::Complex64;
use rayon::prelude::*;
use std::ops::Range;

/// Texels per lane block of the recursion.
const LANES: usize = 16;

/// Ranges of orders at most.
const RANGES: usize = 32;

/// Sums per texel of a range at least (below, the walk to the range's orders and the
/// loading of its texels would cost as much as its recursion).
const RANGE_SUMS: usize = 2048;

/// Blocks of texels at most.
const BLOCKS: usize = 8;

/// Partial sums held by the blocks at most (each 64 bytes in the lanes).
const PARTIAL_SUMS: usize = 1 << 17;

/// A texel's direction as the recursion takes it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Site {
    half: HalfAngle,
    /// The azimuth `phi` and `e^{i phi}`, with `phi = 0` at the poles
    /// (docs/conventions.md Sec. 1).
    phi: f64,
    cis: Complex64,
}

impl Site {
    /// Of a unit direction `w`.
    pub(crate) fn new(w: [f64; 3]) -> Self {
        let rho = w[0].hypot(w[1]);
        let (phi, cis) = if rho > 0.0 {
            (w[1].atan2(w[0]), Complex64::new(w[0] / rho, w[1] / rho))
        } else {
            (0.0, Complex64::new(1.0, 0.0))
        };
        Self {
            half: HalfAngle::from_z_rho(w[2], rho),
            phi,
            cis,
        }
    }

    /// `e^{i phi}`.
    pub(crate) fn cis(&self) -> Complex64 {
        self.cis
    }
}

/// The sums `a_{lm r}` for the orders `m` of `columns` with `keep(m)`, `z[i * rows + r]`
/// the value of row `r` at `sites[i]`: `store(m, l0, a)` once per order, with
/// `a[(l - l0) * rows + r] = a_{lm r}`, `l0 = max(|m|, |s|)`. Orders in parallel (`store`
/// is called from several threads, each order once; nothing for no sites).
pub(crate) fn order_sums(
    columns: &Columns,
    sites: &[Site],
    z: &[Complex64],
    keep: impl Fn(i64) -> bool + Sync,
    store: impl Fn(i64, usize, &[Complex64]) + Sync,
) {
    let rows = z.len() / sites.len().max(1);
    if rows == 0 || sites.is_empty() {
        return;
    }
    let work: Vec<usize> = columns
        .list
        .iter()
        .map(|c| {
            if keep(c.m) {
                (columns.lmax + 1 - c.l0) * rows
            } else {
                0
            }
        })
        .collect();
    let total: usize = work.iter().sum();
    let per_block = sites
        .len()
        .div_ceil((PARTIAL_SUMS / total.max(1)).clamp(1, BLOCKS))
        .next_multiple_of(LANES)
        .max(LANES);
    let blocks: Vec<Range<usize>> = (0..sites.len())
        .step_by(per_block)
        .map(|a| a..(a + per_block).min(sites.len()))
        .collect();
    ranges(&work, (total / RANGE_SUMS).clamp(1, RANGES))
        .into_par_iter()
        .for_each(|range| {
            let parts: Vec<Vec<Complex64>> = blocks
                .par_iter()
                .map(|b| {
                    let zb = &z[b.start * rows..b.end * rows];
                    task(columns, &sites[b.clone()], zb, rows, range.clone(), &keep)
                })
                .collect();
            let mut parts = parts.into_iter();
            let mut sums = parts.next().unwrap_or_default();
            for p in parts {
                sums.iter_mut().zip(p).for_each(|(a, b)| *a += b);
            }
            let mut o = 0;
            for c in &columns.list[range] {
                if keep(c.m) {
                    let n = (columns.lmax + 1 - c.l0) * rows;
                    store(c.m, c.l0, &sums[o..o + n]);
                    o += n;
                }
            }
        });
}

/// At most `count` contiguous ranges of the walk order with about equal `work`.
fn ranges(work: &[usize], count: usize) -> Vec<Range<usize>> {
    let per = work.iter().sum::<usize>().div_ceil(count).max(1);
    let (mut out, mut start, mut acc) = (Vec::new(), 0, 0);
    for (i, w) in work.iter().enumerate() {
        acc += w;
        if acc >= per {
            out.push(start..i + 1);
            (start, acc) = (i + 1, 0);
        }
    }
    if start < work.len() {
        out.push(start..work.len());
    }
    out
}

/// The sums of the kept orders of `range` over `sites`, order after order.
fn task(
    columns: &Columns,
    sites: &[Site],
    z: &[Complex64],
    rows: usize,
    range: Range<usize>,
    keep: &impl Fn(i64) -> bool,
) -> Vec<Complex64> {
    let lmax = columns.lmax;
    // Offset of each column of the range in the task's sums (real rows: re, im).
    let mut offsets = Vec::with_capacity(range.len());
    let mut len = 0;
    for c in &columns.list[range.clone()] {
        offsets.push(len);
        if keep(c.m) {
            len += (lmax + 1 - c.l0) * 2 * rows;
        }
    }
    // Four partial sums per value (the lanes of accumulate).
    let mut acc = vec![[0.0; 4]; len];
    let mut scratch = Vec::new();
    // Per row the real and imaginary parts of z and of g = z e^{-i m phi} in lanes.
    let mut zl = vec![[[0.0; LANES]; 2]; rows];
    let mut g = zl.clone();
    let first = columns.list[range.start].m.unsigned_abs();
    for (block, zb) in sites.chunks(LANES).zip(z.chunks(LANES * rows)) {
        let mut half = [HalfAngle::from_theta(0.0); LANES];
        // e^{i phi} and e^{i |m| phi} at the order of the walk, real and imaginary parts
        // apart (whole SIMD vectors).
        let (mut cis_re, mut cis_im) = ([1.0; LANES], [0.0; LANES]);
        let (mut pow_re, mut pow_im) = ([1.0; LANES], [0.0; LANES]);
        let mut phi = [0.0; LANES];
        zl.fill([[0.0; LANES]; 2]);
        for (j, s) in block.iter().enumerate() {
            (half[j], phi[j], cis_re[j], cis_im[j]) = (s.half, s.phi, s.cis.re, s.cis.im);
            (pow_im[j], pow_re[j]) = (first as f64 * s.phi).sin_cos();
            for (r, v) in zb[j * rows..(j + 1) * rows].iter().enumerate() {
                (zl[r][0][j], zl[r][1][j]) = (v.re, v.im);
            }
        }
        let mut at = first;
        columns.for_each_column_lanes(&half, range.clone(), keep, &mut scratch, |m, l0, col| {
            // |m| decreases only among the seeds (m = -|s|..=|s|): anew from the angle there,
            // by one factor per order after.
            if m.unsigned_abs() < at {
                at = m.unsigned_abs();
                for j in 0..LANES {
                    (pow_im[j], pow_re[j]) = (at as f64 * phi[j]).sin_cos();
                }
            }
            while at < m.unsigned_abs() {
                for j in 0..LANES {
                    (pow_re[j], pow_im[j]) = (
                        pow_re[j] * cis_re[j] - pow_im[j] * cis_im[j],
                        pow_re[j] * cis_im[j] + pow_im[j] * cis_re[j],
                    );
                }
                at += 1;
            }
            // g = z e^{-i m phi}: the conjugate power for m >= 0.
            let c = pow_re;
            let s = pow_im.map(|x| if m >= 0 { -x } else { x });
            for (zr, gr) in zl.iter().zip(g.iter_mut()) {
                phase(zr, gr, &c, &s);
            }
            let o = offsets[columns.index(m) - range.start];
            let n = (lmax + 1 - l0) * 2 * rows;
            accumulate(col, g.as_flattened(), &mut acc[o..o + n]);
        });
    }
    let sum = |v: [f64; 4]| (v[0] + v[1]) + (v[2] + v[3]);
    acc.chunks_exact(2)
        .map(|p| Complex64::new(sum(p[0]), sum(p[1])))
        .collect()
}

/// `g = z (c + i s)` in lanes (one row; a function of its own, so that the lanes, not the
/// rows, are the SIMD vectors).
#[inline(never)]
fn phase(z: &[[f64; LANES]; 2], g: &mut [[f64; LANES]; 2], c: &[f64; LANES], s: &[f64; LANES]) {
    let ([zr, zi], [gr, gi]) = (z, g);
    for j in 0..LANES {
        gr[j] = zr[j] * c[j] - zi[j] * s[j];
        gi[j] = zi[j] * c[j] + zr[j] * s[j];
    }
}

/// `acc[k * rows + r] += ` the four partial sums over the lanes of `col[k][lane] g[r][lane]`,
/// `rows = g.len()`: four rows at a time, so that a column value is loaded once for four
/// products (the same sums, in the same order, as row by row).
#[inline(never)]
fn accumulate(col: &[[f64; LANES]], g: &[[f64; LANES]], acc: &mut [[f64; 4]]) {
    let rows = g.len();
    let mut r = 0;
    while r + 4 <= rows {
        accumulate_rows::<4>(col, &g[r..r + 4], acc, r, rows);
        r += 4;
    }
    while r < rows {
        accumulate_rows::<1>(col, &g[r..r + 1], acc, r, rows);
        r += 1;
    }
}

/// [`accumulate`] of the `B` rows `g` from row `r0` on.
#[inline(always)]
fn accumulate_rows<const B: usize>(
    col: &[[f64; LANES]],
    g: &[[f64; LANES]],
    acc: &mut [[f64; 4]],
    r0: usize,
    rows: usize,
) {
    let g: [[f64; LANES]; B] = std::array::from_fn(|i| g[i]);
    for (k, p) in col.iter().enumerate() {
        let ar = &mut acc[k * rows + r0..][..B];
        for (a, gr) in ar.iter_mut().zip(&g) {
            for t in 0..4 {
                a[t] += (p[t] * gr[t] + p[4 + t] * gr[4 + t])
                    + (p[8 + t] * gr[8 + t] + p[12 + t] * gr[12 + t]);
            }
        }
    }
}
