//! The Wigner small d `d^l_mm'(beta)`, of which the Wigner D matrices of rotations
//! ([`super::wigner_d`], PSH (9)) are made.
//!
//! PSH (9): `<Y_lm, R_F[Y_l'm']> = delta_ll' D^l_mm'(R)` with `R_F[f](w) = f(R^-1 w)`
//! (PSH (8)). For `R = Rz(alpha) Ry(beta) Rz(gamma)` this is
//! `D^l_mm' = e^{-i m alpha} d^l_mm'(beta) e^{-i m' gamma}` with the real Wigner small d
//! of quantum mechanics (`d^1_{10}(beta) = -sin(beta)/sqrt(2)`).
//!
//! The small d are built by Risbo's recursion in half-integer steps (Risbo, J. Geodesy 70
//! (1996)), derived in `proofs/wigner-recursion.md` from the coupling
//! `j = (j - 1/2) + 1/2`: with `a = j - m`, `b = j - m'`, `J = 2j`, `p = cos(beta/2)`,
//! `q = sin(beta/2)`,
//!
//! `d^j[a][b] = ( sqrt(J-a) (sqrt(J-b) p d'[a][b] - sqrt(b) q d'[a][b-1])
//!              + sqrt(a)   (sqrt(J-b) q d'[a-1][b] + sqrt(b) p d'[a-1][b-1]) ) / J`,
//!
//! where `d'` is level `j - 1/2`. Each step is a partial isometry (Clebsch-Gordan
//! coupling), so rounding errors do not grow exponentially; the error measured at
//! `l = 1000` is a few `1e-14` (see `psh verify`). Only the rows `a <= J/2 + 1` are
//! computed; the others follow from `d[a][b] = (-1)^{b-a} d[J-a][J-b]`.

use crate::error::{check_len, finite, Result};
use crate::sh::index::check_lmax;
use multiversion::multiversion;

/// Risbo's recursion for `d^l(beta)`, `l = 0, 1, ...`, one block at a time in `O(l^2)`
/// memory; use it to stream blocks at degrees where storing them all is too much.
pub struct SmallDRecursion {
    steps: HalfSteps,
    /// The stored half of level `J = 2l` (the current block), the rows of level `J + 1`
    /// in flight ([`Rows::Ring`]) and level `J + 2` of the next step, so that the next
    /// step can run while the current block is read.
    cur: Vec<f64>,
    ring: Vec<f64>,
    next: Vec<f64>,
    /// Level `J = 2l` held in `cur`.
    level: usize,
    started: bool,
}

/// The constants of Risbo's half-integer steps and their scratch.
struct HalfSteps {
    lmax: usize,
    p: f64,
    q: f64,
    sq: Vec<f64>,
    /// Row length of the buffers: `b = -1..=2 lmax + 1`.
    stride: usize,
    /// `sqrt(J - b)`, `sqrt(b)` of the two levels of a degree step.
    e: [Vec<f64>; 4],
}

impl SmallDRecursion {
    /// Recursion for `d^l(beta)`, `l <= lmax`.
    pub fn new(beta: f64, lmax: usize) -> Result<Self> {
        finite("beta", beta)?;
        check_lmax(lmax)?;
        let stride = 2 * lmax + 3;
        // Rows a = -1..=lmax + 2: the stored half and the row the next step reads past it.
        let mut cur = vec![0.0; stride * (lmax + 4)];
        cur[stride + 1] = 1.0;
        let (q, p) = (0.5 * beta).sin_cos();
        let sq = (0..=2 * lmax + 1).map(|k| (k as f64).sqrt()).collect();
        let e = std::array::from_fn(|_| vec![0.0; 2 * lmax + 2]);
        Ok(Self {
            steps: HalfSteps {
                lmax,
                p,
                q,
                sq,
                stride,
                e,
            },
            ring: vec![0.0; stride * (RING + 1)],
            next: vec![0.0; cur.len()],
            cur,
            level: 0,
            started: false,
        })
    }

    /// Advances to the next integer degree `l` (the first call gives `l = 0`), or `None`
    /// past `lmax`.
    pub fn advance(&mut self) -> Option<usize> {
        if self.started {
            if self.level + 2 > 2 * self.steps.lmax {
                return None;
            }
            let (steps, cur) = (&mut self.steps, &self.cur);
            let (ring, next, level) = (&mut self.ring, &mut self.next, self.level);
            crate::lanes::dispatch!(degree_step_simd | degree_step(steps, cur, ring, next, level));
            self.finish_step();
        }
        self.started = true;
        Some(self.level / 2)
    }

    /// Makes the level computed by [`degree_step`] into `next` the current one.
    fn finish_step(&mut self) {
        std::mem::swap(&mut self.cur, &mut self.next);
        self.level += 2;
    }

    /// The current block, read-only.
    fn current(&self) -> Level<'_> {
        Level {
            data: &self.cur,
            level: self.level,
            stride: self.steps.stride,
        }
    }

    /// Writes the current block `d^l` into `out` (row-major `(2l+1)^2`, rows `m`,
    /// columns `m'`, both from `-l`).
    pub fn block(&self, out: &mut Vec<f64>) {
        let n = self.level + 1;
        out.clear();
        out.resize(n * n, 0.0);
        let current = self.current();
        for (i, o) in out.chunks_exact_mut(n).enumerate() {
            match current.row(i) {
                (row, false) => o
                    .iter_mut()
                    .zip(row.iter().rev())
                    .for_each(|(o, &r)| *o = r),
                (row, true) => {
                    for (k, (o, &r)) in o.iter_mut().zip(row).enumerate() {
                        *o = if (i + k) % 2 == 0 { r } else { -r };
                    }
                }
            }
        }
    }

    /// Advances to the next integer degree and writes `d^l` into `out` (see [`Self::block`]);
    /// returns `l`, or `None` past `lmax`.
    pub fn next_block(&mut self, out: &mut Vec<f64>) -> Option<usize> {
        let l = self.advance()?;
        self.block(out);
        Some(l)
    }
}

/// The stored half of one level `J = 2l` of the recursion.
pub(crate) struct Level<'a> {
    data: &'a [f64],
    pub(crate) level: usize,
    stride: usize,
}

impl Level<'_> {
    /// Row `i` (`m = i - l`) of the block, as a slice of the stored half and whether it
    /// is read reversed with the sign `(-1)^{i+k}` applied (the lower rows, by
    /// `d[a][b] = (-1)^{a+b} d[J-a][J-b]`). Element `k` (`m' = k - l`) is
    /// `row[n - 1 - k]` in the first case and `(-1)^{i+k} row[k]` in the second.
    pub(crate) fn row(&self, i: usize) -> (&[f64], bool) {
        let (big_j, s) = (self.level, self.stride);
        let a = big_j - i;
        if a <= big_j / 2 + 1 {
            (&self.data[(a + 1) * s + 1..(a + 1) * s + big_j + 2], false)
        } else {
            (&self.data[(i + 1) * s + 1..(i + 1) * s + big_j + 2], true)
        }
    }
}

/// Two half-integer steps: level `J = 2l` in `cur` to `J + 2` in `next`, through level
/// `J + 1` kept a few rows at a time in `ring` (rows [`Rows::Ring`]): each row of `J + 1`
/// is computed just before the rows of `J + 2` that read it, while it is in the cache.
#[inline(always)]
fn degree_step<'a>(
    steps: &'a mut HalfSteps,
    cur: &[f64],
    ring: &mut [f64],
    next: &mut [f64],
    level: usize,
) {
    let s = steps.stride;
    let (j1, j2) = (level + 1, level + 2);
    let (sq, p, q) = (&steps.sq, steps.p, steps.q);
    let [rev1, fwd1, rev2, fwd2] = &mut steps.e;
    for (rev, fwd, big_j) in [(&mut *rev1, &mut *fwd1, j1), (&mut *rev2, &mut *fwd2, j2)] {
        for b in 0..=big_j {
            rev[b] = sq[big_j - b];
            fwd[b] = sq[b];
        }
    }
    let step = |big_j: usize, rev: &'a [f64], fwd: &'a [f64]| StepConsts {
        big_j,
        rev: &rev[..=big_j],
        fwd: &fwd[..=big_j],
        inv: 1.0 / big_j as f64,
        p,
        q,
        sq,
    };
    let (first, second) = (step(j1, rev1, fwd1), step(j2, rev2, fwd2));
    // Rows a <= h of each level, plus row h + 1 by symmetry (what the next level reads).
    let (h1, h2) = ((j1 / 2 + 1).min(j1), (j2 / 2 + 1).min(j2));
    // Rows 0..done of level J + 1 are in the ring.
    let mut done = 0;
    let mut a = 0;
    while a <= h2 {
        let two = a < h2;
        // Rows a (and a + 1) of level J + 2 read rows a - 1..=a (a + 1) of level J + 1.
        while done <= a + usize::from(two) {
            if done < h1 {
                first.rows(cur, Rows::Full, ring, Rows::Ring, s, done, true);
                done += 2;
            } else if done == h1 {
                first.rows(cur, Rows::Full, ring, Rows::Ring, s, done, false);
                done += 1;
            } else if done <= j1 {
                first.mirror_row(ring, Rows::Ring, s, done);
                done += 1;
            } else {
                // Past the block (only at J + 1 = 1): a row of zeros.
                let o = Rows::Ring.slot(done + 1) * s;
                ring[o..o + s].fill(0.0);
                done += 1;
            }
        }
        second.rows(ring, Rows::Ring, next, Rows::Full, s, a, two);
        a += 2;
    }
    if h2 < j2 {
        second.mirror_row(next, Rows::Full, s, h2 + 1);
    }
}

/// [`degree_step`] compiled per instruction set ([`crate::lanes`]; the rows' loops
/// vectorize).
#[multiversion(targets = "simd")]
fn degree_step_simd(
    steps: &mut HalfSteps,
    cur: &[f64],
    ring: &mut [f64],
    next: &mut [f64],
    level: usize,
) {
    degree_step(steps, cur, ring, next, level)
}

/// Where the rows of a level are kept: row `a >= -1` of the recursion (buffer row
/// `i = a + 1`, row `-1` the zero border) at `slot(i) * stride`, columns `b >= -1` at
/// `b + 1` within it.
#[derive(Clone, Copy)]
enum Rows {
    /// Every row at its own place.
    Full,
    /// The zero border at 0 and the rows `a >= 0` in turn in [`RING`] places after it
    /// (two rows `a`, `a + 1` with `a` even are always neighbours).
    Ring,
}

/// Rows of the ring of [`Rows::Ring`] (even, and at least the four rows in flight:
/// `a - 1..=a + 2` and, for the row by symmetry, `h - 2..=h + 1`).
const RING: usize = 8;

impl Rows {
    /// The place of buffer row `i` (recursion row `i - 1`).
    #[inline(always)]
    fn slot(self, i: usize) -> usize {
        match self {
            Rows::Full => i,
            Rows::Ring if i == 0 => 0,
            Rows::Ring => 1 + (i - 1) % RING,
        }
    }
}

/// The constants of one half-integer step to level `J`.
struct StepConsts<'a> {
    big_j: usize,
    /// `sqrt(J - b)` and `sqrt(b)` over `b = 0..=J`.
    rev: &'a [f64],
    fwd: &'a [f64],
    inv: f64,
    p: f64,
    q: f64,
    sq: &'a [f64],
}

impl StepConsts<'_> {
    /// Row constants of the recursion: `sqrt(J-a)/J {p, q}`, `sqrt(a)/J {q, p}`.
    #[inline(always)]
    fn row(&self, a: usize) -> [f64; 4] {
        let (ca, cb) = (self.sq[self.big_j - a] * self.inv, self.sq[a] * self.inv);
        [ca * self.p, ca * self.q, cb * self.q, cb * self.p]
    }

    /// Row `a` of level `J` into `dst` from level `J - 1` in `src`, and with `two` row
    /// `a + 1` in the same pass, sharing the loads of their common source row (`a` even).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn rows(
        &self,
        src: &[f64],
        src_rows: Rows,
        dst: &mut [f64],
        dst_rows: Rows,
        s: usize,
        a: usize,
        two: bool,
    ) {
        let n = self.big_j + 1;
        let (rev, fwd) = (self.rev, self.fwd);
        // Source row `a - 1` (buffer row `i = a`) at columns b and b - 1, as equal-length
        // slices over b = 0..=J: the loops below run in SIMD lanes.
        let src_row = |i: usize| {
            let o = src_rows.slot(i) * s;
            let x = &src[o..o + n + 1];
            (&x[1..], &x[..n])
        };
        let ((y1, y0), (x1, x0)) = (src_row(a), src_row(a + 1));
        let o = dst_rows.slot(a + 1) * s;
        if two {
            debug_assert!(a.is_multiple_of(2) && dst_rows.slot(a + 2) == dst_rows.slot(a + 1) + 1);
            let (c0, c1) = (self.row(a), self.row(a + 1));
            let (z1, z0) = src_row(a + 2);
            let (upper, lower) = dst[o..o + 2 * s].split_at_mut(s);
            let (row, row1) = (&mut upper[1..1 + n], &mut lower[1..1 + n]);
            for b in 0..n {
                row[b] = risbo(c0, rev[b], fwd[b], x1[b], x0[b], y1[b], y0[b]);
                row1[b] = risbo(c1, rev[b], fwd[b], z1[b], z0[b], x1[b], x0[b]);
            }
        } else {
            let c = self.row(a);
            let row = &mut dst[o + 1..o + 1 + n];
            for b in 0..n {
                row[b] = risbo(c, rev[b], fwd[b], x1[b], x0[b], y1[b], y0[b]);
            }
        }
    }

    /// Row `a` of level `J` from row `J - a` by `d[a][b] = (-1)^{a+b} d[J-a][J-b]`.
    #[inline(always)]
    fn mirror_row(&self, dst: &mut [f64], rows: Rows, s: usize, a: usize) {
        let big_j = self.big_j;
        let (from, to) = (rows.slot(big_j - a + 1) * s, rows.slot(a + 1) * s);
        for b in 0..=big_j {
            let v = dst[from + (big_j - b) + 1];
            dst[to + b + 1] = if (a + b).is_multiple_of(2) { v } else { -v };
        }
    }
}

/// Risbo's recursion for one entry `d[a][b]` of level `J` from `x = d'[a]` and
/// `y = d'[a-1]` at columns `b` (`x1`, `y1`) and `b - 1` (`x0`, `y0`), with the row
/// constants `c = [sqrt(J-a) p, sqrt(J-a) q, sqrt(a) q, sqrt(a) p] / J`,
/// `rev = sqrt(J-b)` and `fwd = sqrt(b)` (`proofs/wigner-recursion.md` §2).
#[inline(always)]
fn risbo(c: [f64; 4], rev: f64, fwd: f64, x1: f64, x0: f64, y1: f64, y0: f64) -> f64 {
    let [ap, aq, bq, bp] = c;
    rev * (ap * x1 + bq * y1) + fwd * (bp * y0 - aq * x0)
}

/// `d^l_{m m'}(beta)` for one pair `(m, m')` and all `l <= lmax` (zero below
/// `l0 = max(|m|, |m'|)`), by the three-term recursion in `l` (Edmonds (4.1.23); the
/// Jacobi-polynomial recursion, stable forward):
/// `l sqrt(((l+1)^2 - m^2)((l+1)^2 - m'^2)) d^{l+1} = (2l+1)(l(l+1) cos beta - m m') d^l
///  - (l+1) sqrt((l^2 - m^2)(l^2 - m'^2)) d^{l-1}`,
/// started from Risbo's blocks `d^{l0}`, `d^{l0+1}` so that the convention is theirs.
/// `O(lmax)` per angle.
pub fn small_d_column(m: i64, mp: i64, lmax: usize, beta: f64) -> Result<Vec<f64>> {
    finite("beta", beta)?;
    check_lmax(lmax)?;
    let l0 = m.unsigned_abs().max(mp.unsigned_abs()) as usize;
    let mut out = vec![0.0; lmax + 1];
    if l0 > lmax {
        return Ok(out);
    }
    let mut rec = SmallDRecursion::new(beta, (l0 + 1).min(lmax))?;
    let mut block = Vec::new();
    while let Some(l) = rec.next_block(&mut block) {
        if l >= l0 {
            let n = 2 * l as i64 + 1;
            out[l] = block[((m + l as i64) * n + mp + l as i64) as usize];
        }
    }
    let (c, mm) = (beta.cos(), (m * mp) as f64);
    let (m2, mp2) = ((m * m) as f64, (mp * mp) as f64);
    for l in l0 + 1..lmax {
        let lf = l as f64;
        let l1 = lf + 1.0;
        let a = (2.0 * lf + 1.0) * (lf * l1 * c - mm);
        let b = l1 * ((lf * lf - m2) * (lf * lf - mp2)).sqrt();
        let d = lf * ((l1 * l1 - m2) * (l1 * l1 - mp2)).sqrt();
        out[l + 1] = (a * out[l] - b * out[l - 1]) / d;
    }
    Ok(out)
}

/// `d^l(beta)` alone (row-major `(2l+1)^2`, rows `m`, columns `m'`, both from `-l`).
pub fn small_d_block(l: usize, beta: f64) -> Result<Vec<f64>> {
    let mut rec = SmallDRecursion::new(beta, l)?;
    let mut out = Vec::new();
    while rec.next_block(&mut out) != Some(l) {}
    Ok(out)
}

/// `sum_{l <= lmax} (2l+1)^2` entries (the whole blocks) or `sum (l+1)(2l+1)` (their
/// halves, [`SmallDHalf`]) of `entry_bytes` each, checked against the budget.
pub(crate) fn check_block_memory(lmax: usize, half: bool, entry_bytes: usize) -> Result<usize> {
    let entries = (0..=lmax).try_fold(0usize, |total, l| {
        let rows = if half { l + 1 } else { 2 * l + 1 };
        total.checked_add(rows.checked_mul(2 * l + 1)?)
    });
    crate::budget::check(
        "the stored Wigner blocks of a rotation (stream them one degree at a time)",
        &[entries.unwrap_or(usize::MAX), 1],
        entry_bytes,
    )
}

/// Degrees from which [`for_each_small_d`] overlaps the next recursion step with the
/// current block (below, a degree is too little work to share between threads).
pub(crate) const PIPELINE_DEGREE: usize = 128;

/// The rows `m = 0..=l` of `d^l(beta)`, each in the order `m' = l, l-1, ..., -l`: the
/// half of the block from which the rest follows by
/// `d_{-m,-m'} = (-1)^{m-m'} d_{m m'}` (PSH (9); `proofs/wigner-recursion.md`).
#[derive(Clone, Copy, Debug)]
pub struct SmallDHalf<'a> {
    l: usize,
    /// Row `m` starts at `(l - m) stride`.
    data: &'a [f64],
    stride: usize,
}

impl<'a> SmallDHalf<'a> {
    /// The half stored contiguously: `(l + 1) (2l + 1)` entries, rows `m = l, l-1, ..., 0`
    /// (the layout of [`Self::to_vec`]). Error: a length that is not that.
    pub fn from_rows(l: usize, data: &'a [f64]) -> Result<Self> {
        check_len("small-d half block", (l + 1) * (2 * l + 1), data.len())?;
        Ok(Self {
            l,
            data,
            stride: 2 * l + 1,
        })
    }

    /// The degree `l`.
    pub fn degree(&self) -> usize {
        self.l
    }

    /// Row `m` (`0 <= m <= l`): `d^l_{m m'}` for `m' = l, l-1, ..., -l`.
    pub fn row(&self, m: usize) -> &'a [f64] {
        let start = (self.l - m) * self.stride;
        &self.data[start..start + 2 * self.l + 1]
    }

    /// The rows `m = l, l-1, ..., 0` one after another.
    pub fn to_vec(&self) -> Vec<f64> {
        (0..=self.l)
            .rev()
            .flat_map(|m| self.row(m))
            .copied()
            .collect()
    }
}

impl Level<'_> {
    /// The rows `m >= 0` of this level's block (the stored rows `a = l - m <= l`).
    fn half(&self) -> SmallDHalf<'_> {
        let s = self.stride;
        SmallDHalf {
            l: self.level / 2,
            data: &self.data[s + 1..],
            stride: s,
        }
    }
}

/// Streams the halves of `d^l(beta)`, `l = 0..=lmax`, calling `f(half)` in order of `l`
/// (memory `O(lmax^2)`). With more than one thread, the recursion step to degree `l + 1`
/// runs while `f` reads degree `l`; the values are the same to the bit.
pub fn for_each_small_d(
    beta: f64,
    lmax: usize,
    mut f: impl FnMut(SmallDHalf<'_>) + Send,
) -> Result<()> {
    for_each_level(beta, lmax, |level| f(level.half()))
}

/// Streams the levels `J = 2l` of Risbo's recursion, `l = 0..=lmax`, to `f`, the next
/// step overlapped with `f` from [`PIPELINE_DEGREE`].
pub(crate) fn for_each_level(
    beta: f64,
    lmax: usize,
    mut f: impl FnMut(&Level<'_>) + Send,
) -> Result<()> {
    let mut rec = SmallDRecursion::new(beta, lmax)?;
    rec.advance();
    // On a worker thread, so that each join below hands its second half to the other
    // worker instead of going through the pool's queue.
    rayon::scope(|_| loop {
        let l = rec.level / 2;
        let SmallDRecursion {
            steps,
            cur,
            ring,
            next,
            level,
            ..
        } = &mut rec;
        let cur: &[f64] = cur;
        let current = Level {
            data: cur,
            level: *level,
            stride: steps.stride,
        };
        if l == lmax {
            f(&current);
            return;
        }
        let mut step = || {
            crate::lanes::dispatch!(degree_step_simd | degree_step(steps, cur, ring, next, *level))
        };
        if l >= PIPELINE_DEGREE {
            rayon::join(|| f(&current), step);
        } else {
            f(&current);
            step();
        }
        rec.finish_step();
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fixed-order recursion equals Risbo's blocks, at the poles and to l = 1500.
    #[test]
    fn small_d_column_matches_risbo() {
        for &beta in &[
            0.0,
            1e-9,
            0.3,
            1.2,
            std::f64::consts::FRAC_PI_2,
            2.9,
            std::f64::consts::PI,
        ] {
            let lmax = 60;
            let mut rec = SmallDRecursion::new(beta, lmax).unwrap();
            let mut blocks = Vec::new();
            let mut b = Vec::new();
            while rec.next_block(&mut b).is_some() {
                blocks.push(b.clone());
            }
            for (m, mp) in [
                (0, 0),
                (0, -2),
                (-2, 0),
                (2, 2),
                (-2, 2),
                (2, -2),
                (-2, -2),
                (3, 1),
            ] {
                let col = small_d_column(m, mp, lmax, beta).unwrap();
                for (l, blk) in blocks.iter().enumerate() {
                    let li = l as i64;
                    let want = if m.abs().max(mp.abs()) > li {
                        0.0
                    } else {
                        blk[((m + li) * (2 * li + 1) + mp + li) as usize]
                    };
                    assert!(
                        (col[l] - want).abs() < 1e-13,
                        "{m} {mp} {beta} {l}: {} {want}",
                        col[l]
                    );
                }
            }
        }
        let (beta, l) = (0.7, 1500);
        let want = small_d_block(l, beta).unwrap();
        let n = 2 * l as i64 + 1;
        for (m, mp) in [(0, 0), (-2, 2), (2, 2), (0, 2)] {
            let col = small_d_column(m, mp, l, beta).unwrap();
            let w = want[((m + l as i64) * n + mp + l as i64) as usize];
            assert!((col[l] - w).abs() < 1e-12, "{m} {mp}: {} {w}", col[l]);
        }
    }

    #[test]
    fn closed_forms_of_small_d() {
        let b = 0.7f64;
        let d1 = small_d_block(1, b).unwrap();
        // rows m = 1, 0, -1 (top to bottom is m = -1, 0, 1 here), columns likewise.
        let (c, s) = (b.cos(), b.sin());
        let expect = [
            [(1.0 + c) / 2.0, s / 2f64.sqrt(), (1.0 - c) / 2.0],
            [-s / 2f64.sqrt(), c, s / 2f64.sqrt()],
            [(1.0 - c) / 2.0, -s / 2f64.sqrt(), (1.0 + c) / 2.0],
        ];
        for i in 0..3 {
            for k in 0..3 {
                assert!((d1[i * 3 + k] - expect[i][k]).abs() < 1e-15, "{i} {k}");
            }
        }
    }
}
