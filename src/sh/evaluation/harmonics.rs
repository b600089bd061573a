//! Complex SH `Y_lm` (PSH (1)) and real SH `Y^R_lm` (PSH (12)) at one direction or many.
//!
//! - `Y_lm(theta, phi) = Pbar_lm(theta) e^{i m phi}` for `m >= 0` and
//!   `Y_{l,-m} = (-1)^m conj(Y_lm)`;
//! - `Y^R_lm = sqrt(2) Re Y_lm` (m > 0), `Y_l0` (m = 0), `sqrt(2) Im Y_{l|m|}` (m < 0).
//!
//! Values are stored in flat order `l*l + l + m` ([`crate::sh::lm_index`]).

use crate::error::{check_len, finite, Result};
use crate::geometry::{check_direction, check_theta, direction_angles, UNIT_TOLERANCE};
use crate::sh::evaluation::cartesian;
use crate::sh::index::{lm_index, num_coeffs};
use crate::sh::recursion::legendre::{for_each_column_accurate, Legendre, Polar};
use multiversion::multiversion;
use num_complex::Complex64;
use rayon::prelude::*;
use std::f64::consts::SQRT_2;

/// Entry `U_{m mu}` of the unitary complex-to-real change of basis of PSH (12):
/// `Y^R_{lm} = sum_mu U_{m mu} Y_{l mu}`; nonzero only for `mu = ±m`.
pub fn real_from_complex(m: i64, mu: i64) -> Complex64 {
    use std::f64::consts::FRAC_1_SQRT_2 as R;
    let parity = if m.rem_euclid(2) == 1 { -1.0 } else { 1.0 };
    match m.cmp(&0) {
        std::cmp::Ordering::Equal => Complex64::new(if mu == 0 { 1.0 } else { 0.0 }, 0.0),
        std::cmp::Ordering::Greater => {
            if mu == m {
                Complex64::new(R, 0.0)
            } else if mu == -m {
                Complex64::new(parity * R, 0.0)
            } else {
                Complex64::new(0.0, 0.0)
            }
        }
        std::cmp::Ordering::Less => {
            if mu == m {
                Complex64::new(0.0, parity * R)
            } else if mu == -m {
                Complex64::new(0.0, -R)
            } else {
                Complex64::new(0.0, 0.0)
            }
        }
    }
}

/// `(cos(m phi), sin(m phi))` accurate to a few ulps for any `m`: the product `m phi`
/// is split exactly into `hi + lo` (an FMA gives the rounding error `lo`), and the
/// angle-sum formula corrects `cis(hi)` by `lo`.
#[inline]
pub fn cis_m(m: usize, phi: f64) -> (f64, f64) {
    let mf = m as f64;
    let hi = mf * phi;
    let lo = mf.mul_add(phi, -hi);
    let (s, c) = hi.sin_cos();
    (c - lo * s, s + lo * c)
}

/// Orders between exact restarts of [`CisWalk`] (bounds its rounding drift to a few tens
/// of ulps).
const CIS_RESTART: usize = 32;

/// `(cos(m phi), sin(m phi))` for a walk over orders `m`: one multiplication by
/// `e^{i phi}` when `m` follows the previous order, the cached value when it repeats it,
/// and an exact [`cis_m`] every `CIS_RESTART` orders or after any other jump.
#[derive(Clone, Copy, Debug)]
pub struct CisWalk {
    phi: f64,
    step: Complex64,
    last: Option<(usize, Complex64)>,
}

impl CisWalk {
    /// A walk at the azimuth `phi`.
    pub fn new(phi: f64) -> Self {
        let (c, s) = cis_m(1, phi);
        Self {
            phi,
            step: Complex64::new(c, s),
            last: None,
        }
    }

    /// `(cos(m phi), sin(m phi))`.
    #[inline]
    pub fn at(&mut self, m: usize) -> (f64, f64) {
        let e = match self.last {
            Some((k, e)) if k == m => e,
            Some((k, e)) if k + 1 == m && !m.is_multiple_of(CIS_RESTART) => e * self.step,
            _ => {
                let (c, s) = cis_m(m, self.phi);
                Complex64::new(c, s)
            }
        };
        self.last = Some((m, e));
        (e.re, e.im)
    }
}

/// Evaluator of complex and real SH up to a fixed degree.
///
/// [`ShEvaluator::new`] holds `f64` Legendre tables (the fast path): within `10 l eps` of
/// `sqrt((2l+1)/(4 pi))` to `l = 4096` at every angle measured, the poles included (0.72
/// `l eps` to `l = 2048` at the edge angles, check `sh.fast_path_l2048`; 5.2 `l eps` at
/// `l = 2048`, `theta = 1e-3`, order 1; the zonal column runs in Reinsch's difference
/// form, `proofs/legendre-recursion.md` §4a). Beyond, the low orders' rounding in the
/// polar caps grows like `l^2 eps`: 14 `l eps` at `l = 8192`, `theta = 2e-4`, order 1
/// (docs/stability.md). [`ShEvaluator::accurate`] runs the double-double recursion (a few
/// `1e-16` at any degree, about ten times slower).
///
/// # Example
///
/// `Y_00 = 1/sqrt(4 pi)`, `Y_10 = sqrt(3/(4 pi)) cos theta` (PSH (12)), and the addition
/// theorem `sum_m Y_lm^2 = (2l + 1)/(4 pi)`.
///
/// ```
/// use psh::sh::{lm_index, ShEvaluator};
/// use std::f64::consts::PI;
///
/// let sh = ShEvaluator::new(2)?;
/// let mut y = vec![0.0; sh.len()];
/// let (theta, phi) = (0.7, 1.9);
/// sh.real(theta, phi, &mut y)?;
/// assert!((y[0] - 1.0 / (4.0 * PI).sqrt()).abs() < 1e-16);
/// assert!((y[lm_index(1, 0)] - (3.0 / (4.0 * PI)).sqrt() * theta.cos()).abs() < 1e-15);
/// let band2: f64 = (-2..=2).map(|m| y[lm_index(2, m)].powi(2)).sum();
/// assert!((band2 - 5.0 / (4.0 * PI)).abs() < 1e-15);
/// # Ok::<(), psh::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct ShEvaluator {
    lmax: usize,
    /// `None` for the accurate evaluator.
    legendre: Option<Legendre>,
}

impl ShEvaluator {
    /// A fast evaluator for all degrees `l <= lmax`.
    pub fn new(lmax: usize) -> Result<Self> {
        Ok(Self {
            lmax,
            legendre: Some(Legendre::new(lmax)?),
        })
    }

    /// An accurate (double-double) evaluator for all degrees `l <= lmax`; its batch
    /// evaluation is not vectorized.
    pub fn accurate(lmax: usize) -> Result<Self> {
        crate::sh::check_lmax(lmax)?;
        Ok(Self {
            lmax,
            legendre: None,
        })
    }

    /// The largest degree.
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// Walks the Legendre columns at `theta` with the evaluator's precision.
    fn columns(&self, theta: f64, f: impl FnMut(usize, &[f64])) {
        match &self.legendre {
            Some(t) => t.for_each_column(Polar::from_theta(theta), f),
            None => for_each_column_accurate(self.lmax, Polar::from_theta_accurate(theta), f),
        }
    }

    /// Number of coefficients `(lmax + 1)^2`.
    pub fn len(&self) -> usize {
        num_coeffs(self.lmax())
    }

    /// Never empty (degree 0 is always there); for clippy's `len` convention.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Complex SH PSH (1) at `(theta, phi)` into `out` (flat order, length `(lmax+1)^2`).
    pub fn complex(&self, theta: f64, phi: f64, out: &mut [Complex64]) -> Result<()> {
        check_theta(theta)?;
        finite("phi", phi)?;
        check_len("SH output", self.len(), out.len())?;
        let mut cis = CisWalk::new(phi);
        self.columns(theta, |m, col| {
            let (cm, sm) = cis.at(m);
            let sign = if m % 2 == 0 { 1.0 } else { -1.0 };
            for (k, &p) in col.iter().enumerate() {
                let l = m + k;
                let y = Complex64::new(p * cm, p * sm);
                out[lm_index(l, m as i64)] = y;
                if m > 0 {
                    out[lm_index(l, -(m as i64))] = sign * y.conj();
                }
            }
        });
        Ok(())
    }

    /// Real SH PSH (12) at `(theta, phi)` into `out` (flat order, length `(lmax+1)^2`).
    pub fn real(&self, theta: f64, phi: f64, out: &mut [f64]) -> Result<()> {
        check_theta(theta)?;
        finite("phi", phi)?;
        check_len("SH output", self.len(), out.len())?;
        let mut cis = CisWalk::new(phi);
        self.columns(theta, |m, col| {
            let (cm, sm) = cis.at(m);
            write_real_column(m, col, cm, sm, out);
        });
        Ok(())
    }

    /// Real SH at a batch of unit directions `dirs` (world Cartesian; theta measured from +z,
    /// phi from +x towards +y), into `out` of length `dirs.len() * (lmax+1)^2`, one row of
    /// coefficients per direction.
    ///
    /// Directions are processed `LANES` at a time with the Legendre recursions in lock
    /// step ([`Legendre::for_each_column_lanes`]). The accurate evaluator evaluates them
    /// one by one.
    pub fn real_batch(&self, dirs: &[[f64; 3]], out: &mut [f64]) -> Result<()> {
        let n = self.len();
        check_len("SH batch output", dirs.len() * n, out.len())?;
        let Some(table) = &self.legendre else {
            for (w, row) in dirs.iter().zip(out.chunks_exact_mut(n)) {
                let (theta, phi) = direction_angles(*w)?;
                self.real(theta, phi, row)?;
            }
            return Ok(());
        };
        // Blocks of directions in parallel: each row is computed by one task, the same bits
        // on any thread count.
        let block = |(chunk, rows): (&[[f64; 3]], &mut [f64])| -> Result<()> {
            if self.lmax <= cartesian::CARTESIAN_LMAX {
                cartesian_block(table, n, chunk, rows)
            } else {
                crate::lanes::dispatch!(polar_simd | polar_block(table, n, chunk, rows))
            }
        };
        if dirs.len() <= BATCH_BLOCK {
            return block((dirs, out));
        }
        let blocks = dirs
            .par_chunks(BATCH_BLOCK)
            .zip(out.par_chunks_mut(BATCH_BLOCK * n));
        // The first bad direction in input order names the error, whatever the threads.
        let results: Vec<Result<()>> = blocks.map(block).collect();
        results.into_iter().collect()
    }
}

/// Real SH of degrees `<= table.lmax() <= CARTESIAN_LMAX` at the directions `chunk`
/// into `rows` (one row of `n = (lmax+1)^2` per direction), four at a time by the Cartesian
/// kernel, in the CPU's best lanes ([`crate::lanes`]).
fn cartesian_block(table: &Legendre, n: usize, chunk: &[[f64; 3]], rows: &mut [f64]) -> Result<()> {
    crate::lanes::with_lanes(CartesianBlock {
        table,
        n,
        chunk,
        rows,
    })
}

/// [`cartesian_block`] as a kernel over the lane sets.
struct CartesianBlock<'a> {
    table: &'a Legendre,
    n: usize,
    chunk: &'a [[f64; 3]],
    rows: &'a mut [f64],
}

impl crate::lanes::WithLanes for CartesianBlock<'_> {
    type Output = Result<()>;

    #[inline(always)]
    fn run<L: crate::lanes::LaneSet>(self, set: L) -> Result<()> {
        let n = self.n;
        let mut tile = vec![crate::lanes::F64x4::ZERO; n];
        let blocks = self.chunk.chunks(cartesian::LANES);
        for (chunk, rows) in blocks.zip(self.rows.chunks_mut(cartesian::LANES * n)) {
            for &w in chunk {
                check_unit(w)?;
            }
            let last = chunk[chunk.len() - 1];
            let lanes = std::array::from_fn(|j| *chunk.get(j).unwrap_or(&last));
            cartesian::real_lanes(set, self.table, &lanes, &mut tile);
            // Lane j of every value into row j: four values of four rows at a time by a
            // 4 x 4 transpose (read lane by lane, row after row, the compiler gathered them).
            let mut rows = rows.chunks_exact_mut(n);
            match (rows.next(), rows.next(), rows.next(), rows.next()) {
                (Some(r0), Some(r1), Some(r2), Some(r3)) => {
                    let quads = tile.chunks_exact(4).enumerate();
                    for (q, t) in quads {
                        let v = set.transpose([0, 1, 2, 3].map(|k| set.load(&t[k])));
                        for (r, v) in [&mut *r0, &mut *r1, &mut *r2, &mut *r3].into_iter().zip(v) {
                            r[4 * q..4 * q + 4].copy_from_slice(&set.store(v).0);
                        }
                    }
                    for i in n - n % 4..n {
                        [r0[i], r1[i], r2[i], r3[i]] = tile[i].0;
                    }
                }
                (r0, r1, r2, _) => {
                    for (j, row) in [r0, r1, r2].into_iter().flatten().enumerate() {
                        for (o, t) in row.iter_mut().zip(&tile) {
                            *o = t.0[j];
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

/// Real SH at the directions `chunk` into `rows` as [`cartesian_block`], by the
/// recursions in `u` of [`Legendre::for_each_column_lanes`] (any band limit).
#[inline(always)]
fn polar_block(table: &Legendre, n: usize, chunk: &[[f64; 3]], rows: &mut [f64]) -> Result<()> {
    let mut tile = vec![[0.0; LANES]; n];
    let mut scratch = Vec::new();
    for (chunk, rows) in chunk.chunks(LANES).zip(rows.chunks_mut(LANES * n)) {
        let mut polars = [Polar::from_z_rho(1.0, 0.0); LANES];
        let mut cis = [(1.0, 0.0); LANES];
        for (j, &w) in chunk.iter().enumerate() {
            check_unit(w)?;
            // Normalized: a direction within the unit tolerance is taken as its unit
            // vector, as by `real` (through its angles).
            let inv = 1.0 / (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
            let rho = (w[0] * w[0] + w[1] * w[1]).sqrt();
            polars[j] = Polar::from_z_rho(w[2] * inv, rho * inv);
            if rho > 0.0 {
                let inv = 1.0 / rho;
                cis[j] = (w[0] * inv, w[1] * inv);
            }
        }
        real_lanes(table, &polars, &cis, &mut scratch, &mut tile);
        for (j, row) in rows.chunks_exact_mut(n).enumerate() {
            for (o, t) in row.iter_mut().zip(&tile) {
                *o = t[j];
            }
        }
    }
    Ok(())
}

/// [`polar_block`] compiled per instruction set ([`crate::lanes`]).
#[multiversion(targets = "simd")]
fn polar_simd(table: &Legendre, n: usize, chunk: &[[f64; 3]], rows: &mut [f64]) -> Result<()> {
    polar_block(table, n, chunk, rows)
}

/// Checks a direction of a batch: a cheap test of its squared norm, the full check (and
/// its error) only when that fails.
#[inline]
fn check_unit(w: [f64; 3]) -> Result<()> {
    let norm2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    if (norm2 - 1.0).abs().partial_cmp(&(2.0 * UNIT_TOLERANCE)) != Some(std::cmp::Ordering::Less) {
        check_direction(w)?;
    }
    Ok(())
}

/// Directions per parallel task of [`ShEvaluator::real_batch`].
const BATCH_BLOCK: usize = 32 * LANES;

/// Real SH of `LANES` directions (given as polar angles and `e^{i phi}`) into the tile
/// `tile[l*l + l + m][lane]`.
#[inline(always)]
fn real_lanes(
    table: &Legendre,
    polars: &[Polar; LANES],
    cis: &[(f64, f64); LANES],
    scratch: &mut Vec<[f64; LANES]>,
    tile: &mut [[f64; LANES]],
) {
    let (mut cm, mut sm) = ([1.0f64; LANES], [0.0f64; LANES]);
    table.for_each_column_lanes(polars, scratch, |m, col| {
        if m > 0 {
            for j in 0..LANES {
                let c = cm[j] * cis[j].0 - sm[j] * cis[j].1;
                sm[j] = cm[j] * cis[j].1 + sm[j] * cis[j].0;
                cm[j] = c;
            }
        }
        let rc: [f64; LANES] = std::array::from_fn(|j| SQRT_2 * cm[j]);
        let rs: [f64; LANES] = std::array::from_fn(|j| SQRT_2 * sm[j]);
        for (k, p) in col.iter().enumerate() {
            let l = m + k;
            if m == 0 {
                tile[lm_index(l, 0)] = *p;
            } else {
                let t = &mut tile[lm_index(l, m as i64)];
                for j in 0..LANES {
                    t[j] = p[j] * rc[j];
                }
                let t = &mut tile[lm_index(l, -(m as i64))];
                for j in 0..LANES {
                    t[j] = p[j] * rs[j];
                }
            }
        }
    });
}

/// Directions per lane group of the batch evaluation.
const LANES: usize = 8;

/// Writes the real SH of column m (`Pbar_lm` for `l >= m`) given `cos(m phi), sin(m phi)`.
#[inline]
fn write_real_column(m: usize, col: &[f64], cm: f64, sm: f64, out: &mut [f64]) {
    if m == 0 {
        for (l, &p) in col.iter().enumerate() {
            out[lm_index(l, 0)] = p;
        }
    } else {
        let (rc, rs) = (SQRT_2 * cm, SQRT_2 * sm);
        for (k, &p) in col.iter().enumerate() {
            let l = m + k;
            out[lm_index(l, m as i64)] = p * rc;
            out[lm_index(l, -(m as i64))] = p * rs;
        }
    }
}

/// Complex SH PSH (1) of all `l <= lmax` at `(theta, phi)`, flat order (accurate path).
pub fn sh_complex(lmax: usize, theta: f64, phi: f64) -> Result<Vec<Complex64>> {
    let ev = ShEvaluator::accurate(lmax)?;
    let mut out = vec![Complex64::default(); ev.len()];
    ev.complex(theta, phi, &mut out)?;
    Ok(out)
}

/// Real SH PSH (12) of all `l <= lmax` at `(theta, phi)`, flat order (accurate path).
pub fn sh_real(lmax: usize, theta: f64, phi: f64) -> Result<Vec<f64>> {
    let ev = ShEvaluator::accurate(lmax)?;
    let mut out = vec![0.0; ev.len()];
    ev.real(theta, phi, &mut out)?;
    Ok(out)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::geometry::direction;
    use std::f64::consts::PI;

    /// The polar angles of the edge checks: the poles, 1e-300, 1e-12, 1e-8 and 1e-4 from
    /// them, the equator.
    pub(crate) const EDGE_THETAS: [f64; 10] = [
        0.0,
        1e-300,
        1e-12,
        1e-8,
        1e-4,
        PI / 2.0,
        PI - 1e-4,
        PI - 1e-8,
        PI - 1e-12,
        PI,
    ];

    /// The fast evaluator (pointwise and batch) meets `10 l eps` of
    /// `sqrt((2l+1)/(4 pi))` at the edge angles, against the double-double path (checked
    /// against 40-digit values by `sh.legendre_oracle`). Before the zonal column's
    /// difference form it was 9.4e-12 off at `l = 1024`, `theta = 1e-8` (4x the bound).
    #[test]
    fn fast_path_meets_ten_l_eps_at_the_poles() {
        let lmax = 1024;
        let fast = ShEvaluator::new(lmax).unwrap();
        let n = fast.len();
        let dirs: Vec<[f64; 3]> = EDGE_THETAS.iter().map(|&t| direction(t, 0.7)).collect();
        let mut batch = vec![0.0; dirs.len() * n];
        fast.real_batch(&dirs, &mut batch).unwrap();
        let mut y = vec![0.0; n];
        for (k, &t) in EDGE_THETAS.iter().enumerate() {
            fast.real(t, 0.7, &mut y).unwrap();
            let want = sh_real(lmax, t, 0.7).unwrap();
            // The batch takes the direction, whose polar angle is that of `t` rounded
            // through cos and sin: compare it with the accurate values at its own angle.
            let (tb, pb) = crate::geometry::direction_angles(dirs[k]).unwrap();
            let want_batch = sh_real(lmax, tb, pb).unwrap();
            for l in 0..=lmax {
                let bound = 10.0
                    * l.max(1) as f64
                    * f64::EPSILON
                    * ((2 * l + 1) as f64 / (4.0 * PI)).sqrt();
                for i in l * l..(l + 1) * (l + 1) {
                    let e = (y[i] - want[i]).abs();
                    assert!(e <= bound, "theta {t} l {l} index {i}: {e:e} > {bound:e}");
                    let e = (batch[k * n + i] - want_batch[i]).abs();
                    assert!(e <= bound, "batch theta {t} l {l} index {i}: {e:e}");
                }
            }
        }
    }

    /// PSH (12) against its complex form, and Y_{l,-m} = (-1)^m conj(Y_lm).
    #[test]
    fn real_and_complex_agree_with_psh_12() {
        let lmax = 30;
        for &(t, p) in &[
            (0.3, 1.1),
            (PI / 2.0, -2.0),
            (0.0, 0.5),
            (PI, 3.0),
            (2.9, 0.0),
        ] {
            let yc = sh_complex(lmax, t, p).unwrap();
            let yr = sh_real(lmax, t, p).unwrap();
            for l in 0..=lmax {
                for m in -(l as i64)..=l as i64 {
                    let sign = if m % 2 == 0 { 1.0 } else { -1.0 };
                    let y = yc[lm_index(l, m)];
                    let ym = yc[lm_index(l, -m)];
                    assert!((ym - sign * y.conj()).norm() < 1e-15);
                    let expect = match m.signum() {
                        1 => (y + sign * ym) / SQRT_2,
                        0 => y,
                        _ => Complex64::i() * (sign * y - ym) / SQRT_2,
                    };
                    assert!(expect.im.abs() < 1e-14);
                    assert!(
                        (yr[lm_index(l, m)] - expect.re).abs() < 1e-14,
                        "l {l} m {m}"
                    );
                }
            }
        }
    }

    /// Both batch kernels (Cartesian up to `CARTESIAN_LMAX`, the Legendre lanes above),
    /// serial and parallel, against single directions: poles, near-poles, both hemispheres,
    /// slightly non-unit directions.
    #[test]
    fn batch_matches_single_direction_including_poles() {
        let mut dirs: Vec<[f64; 3]> = (0..37)
            .map(|i| direction(PI * i as f64 / 36.0, 0.7 * i as f64 - 3.0))
            .collect();
        dirs.extend([
            [0.0, 0.0, 1.0],
            [1e-200, 0.0, 1.0],
            [0.0, 0.0, -1.0],
            [-3e-9, 2e-9, -1.0],
            [0.6, 0.8 * (1.0 + 5e-11), 0.0],
        ]);
        dirs.extend(crate::random::pseudo_random(3 * 700, 4).chunks(3).map(|v| {
            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            [v[0] / n, v[1] / n, v[2] / n]
        }));
        for lmax in [
            0,
            4,
            cartesian::CARTESIAN_LMAX,
            cartesian::CARTESIAN_LMAX + 1,
        ] {
            let ev = ShEvaluator::new(lmax).unwrap();
            let n = ev.len();
            for count in [7, dirs.len()] {
                let dirs = &dirs[dirs.len() - count..];
                let mut batch = vec![0.0; dirs.len() * n];
                ev.real_batch(dirs, &mut batch).unwrap();
                let mut one = vec![0.0; n];
                for (i, &w) in dirs.iter().enumerate() {
                    let (t, p) = direction_angles(w).unwrap();
                    ev.real(t, p, &mut one).unwrap();
                    for j in 0..n {
                        assert!(
                            (batch[i * n + j] - one[j]).abs() < 1e-13,
                            "lmax {lmax} dir {i} index {j}: {} vs {}",
                            batch[i * n + j],
                            one[j]
                        );
                    }
                }
            }
        }
    }

    /// An empty batch is an empty result for both kernels (no block of zero rows).
    #[test]
    fn empty_batches_are_empty() {
        for lmax in [4, 40] {
            let sh = ShEvaluator::new(lmax).unwrap();
            assert!(sh.real_batch(&[], &mut []).is_ok());
        }
    }

    /// Blocks of directions run in parallel, each row by one task: the same bits on one
    /// thread and on three, for both kernels.
    #[test]
    fn batch_does_not_depend_on_the_thread_count() {
        let dirs: Vec<[f64; 3]> = crate::random::pseudo_random(3 * 2000, 8)
            .chunks(3)
            .map(|v| {
                let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                [v[0] / n, v[1] / n, v[2] / n]
            })
            .collect();
        for lmax in [4, 30] {
            let ev = ShEvaluator::new(lmax).unwrap();
            let run = |threads: usize| {
                let mut out = vec![0.0; dirs.len() * ev.len()];
                crate::testing::on_threads(threads, || ev.real_batch(&dirs, &mut out)).unwrap();
                out
            };
            assert_eq!(run(1), run(3), "lmax {lmax}");
        }
    }

    /// Increasing, repeated and jumping orders (the walks of the Legendre and spin
    /// recursions) against the direct [`cis_m`].
    #[test]
    fn cis_walk_stays_accurate() {
        for phi in [2.3, -3.1, 1e-9] {
            let mut walk = CisWalk::new(phi);
            let orders = (0..300)
                .chain([2, 1, 0, 1, 2, 3, 3, 4, 4])
                .chain((5..200).rev());
            for m in orders {
                let (c, s) = walk.at(m);
                let (ce, se) = cis_m(m, phi);
                assert!(
                    (c - ce).abs() < 1e-14 && (s - se).abs() < 1e-14,
                    "{phi} {m}"
                );
            }
        }
    }

    #[test]
    fn cis_m_is_accurate_at_high_order() {
        let phi = 2.9;
        for m in [1usize, 1000, 4096] {
            let (c, s) = cis_m(m, phi);
            assert!((c * c + s * s - 1.0).abs() < 1e-15);
        }
        let (c, s) = cis_m(3, PI / 2.0);
        assert!(c.abs() < 1e-15 && (s + 1.0).abs() < 1e-15);
    }

    #[test]
    fn bad_directions_are_errors() {
        let ev = ShEvaluator::new(2).unwrap();
        let mut out = vec![0.0; 9];
        assert!(ev.real_batch(&[[1.0, 1.0, 0.0]], &mut out).is_err());
        assert!(ev.real_batch(&[[f64::NAN, 0.0, 1.0]], &mut out).is_err());
        assert!(ev.real(f64::INFINITY, 0.0, &mut out).is_err());
        assert!(ev.real(0.1, 0.0, &mut out[..4]).is_err());
    }
}
