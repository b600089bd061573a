//! Projection of sampled images onto SH: `f_lm ~ sum_i Omega_i f(w_i) Y_lm(w_i)`, the
//! texel-wise quadrature of PSH (3) with exact per-texel solid angles `Omega_i`
//! ([`crate::geometry::image_grid`]). Not exact (an image is not band-limited): the
//! error is that of the midpoint rule per texel.

use super::harmonics::ShEvaluator;
use crate::error::{check_len, finite, Result};
use crate::geometry::image_grid::PixelGrid;
use nalgebra::{DMatrix, DMatrixView};

/// Texels evaluated per batch at most (bounds the scratch to `CHUNK (lmax+1)^2` values).
const CHUNK: usize = 1024;

/// Values of the SH scratch of one worker at most: high degrees take fewer texels per
/// batch ([`texels_per_batch`]), so that the scratch stays within 32 MB.
const SCRATCH_VALUES: usize = 1 << 22;

/// Blocks of a parallel texel sum: a fixed number, so that the sum's rounding does not
/// depend on the number of threads.
const BLOCKS: usize = 8;

/// Texels per batch for `n` SH values per texel: [`CHUNK`], fewer when `CHUNK n` would
/// exceed [`SCRATCH_VALUES`], at least one.
fn texels_per_batch(n: usize) -> usize {
    (SCRATCH_VALUES / n.max(1)).clamp(1, CHUNK)
}

/// Partial sums [`block_sum`] holds at once: one per worker thread.
pub(crate) fn partials_at_once() -> usize {
    rayon::current_num_threads().clamp(1, BLOCKS)
}

/// `sum_b partial(block_b)` element-wise over at most [`BLOCKS`] contiguous blocks of
/// `items` (whole multiples of `chunk` items), the blocks in parallel and their partial
/// sums added in block order (deterministic). Blocks run in waves of
/// [`partials_at_once`], so at most that many partials (of `len` values) are held besides
/// the sum. Error: the first partial's error.
pub(crate) fn block_sum<T: Sync>(
    items: &[T],
    chunk: usize,
    len: usize,
    partial: impl Fn(&[T]) -> Result<Vec<f64>> + Sync,
) -> Result<Vec<f64>> {
    use rayon::prelude::*;
    let per_block = items.len().div_ceil(BLOCKS).div_ceil(chunk).max(1) * chunk;
    let blocks: Vec<&[T]> = items.chunks(per_block).collect();
    let mut sum = vec![0.0; len];
    for wave in blocks.chunks(partials_at_once()) {
        let parts = wave
            .par_iter()
            .map(|b| partial(b))
            .collect::<Result<Vec<_>>>()?;
        for p in parts {
            check_len("partial sum", len, p.len())?;
            sum.iter_mut().zip(p).for_each(|(a, b)| *a += b);
        }
    }
    Ok(sum)
}

/// Real SH coefficients (PSH (12)) of `l <= lmax` of one real image on `grid`.
/// Values of texels with zero solid angle (off the cube cross) are ignored; NaN or
/// infinite values elsewhere are an error naming the texel.
pub fn project_real(
    grid: &(impl PixelGrid + Sync),
    values: &[f64],
    lmax: usize,
) -> Result<Vec<f64>> {
    Ok(project_real_channels(grid, &[values], lmax)?.remove(0))
}

/// Real SH coefficients of several images (channels) on the same grid, sharing the SH
/// evaluation: one coefficient vector per channel. Per chunk of texels the sums are one
/// matrix product `F += Y^T (Omega v)` (nalgebra's `gemm`).
pub fn project_real_channels(
    grid: &(impl PixelGrid + Sync),
    channels: &[&[f64]],
    lmax: usize,
) -> Result<Vec<Vec<f64>>> {
    for c in channels {
        check_len("image values", grid.len(), c.len())?;
    }
    let ev = ShEvaluator::new(lmax)?;
    let (n, nch) = (ev.len(), channels.len());
    let batch = texels_per_batch(n);
    // Per worker the scratch and a partial sum; the sum and the coefficients returned.
    let workers = partials_at_once();
    crate::budget::check(
        "the work space of an SH projection",
        &[n, workers * (batch + nch) + 2 * nch],
        8,
    )?;
    let texels: Vec<(usize, f64)> = (0..grid.len())
        .map(|i| (i, grid.solid_angle(i)))
        .filter(|&(_, w)| w > 0.0)
        .collect();
    // Column-major n x nch.
    let sum = block_sum(&texels, batch, n * nch, |block| {
        let mut out = DMatrix::<f64>::zeros(n, nch);
        let mut y = vec![0.0; batch * n];
        for chunk in block.chunks(batch) {
            let dirs: Vec<[f64; 3]> = chunk.iter().map(|&(i, _)| grid.direction(i)).collect();
            let y = &mut y[..chunk.len() * n];
            ev.real_batch(&dirs, y)?;
            let mut v = DMatrix::<f64>::zeros(chunk.len(), nch);
            for (c, vals) in channels.iter().enumerate() {
                for (k, &(i, w)) in chunk.iter().enumerate() {
                    v[(k, c)] = finite("texel value", vals[i])? * w;
                }
            }
            // Y (chunk x n, row-major) is Y^T column-major.
            let yt = DMatrixView::from_slice(y, n, chunk.len());
            out.gemm(1.0, &yt, &v, 1.0);
        }
        Ok(out.as_slice().to_vec())
    })?;
    Ok(sum.chunks_exact(n).map(<[f64]>::to_vec).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::image_grid::{CubeCross, Equirect};
    use crate::sh::harmonics::ShEvaluator;
    use crate::sh::{lm_index, num_coeffs};

    /// A low-order function sampled on fine images projects to its coefficients up to the
    /// midpoint-rule error, which falls like 1/edge^2.
    #[test]
    fn projection_converges_to_the_coefficients() {
        let lmax = 3;
        let ev = ShEvaluator::new(lmax).unwrap();
        let target = lm_index(2, -1);
        let sample = |g: &dyn PixelGrid| -> Vec<f64> {
            let mut y = vec![0.0; ev.len()];
            (0..g.len())
                .map(|i| {
                    let w = g.direction(i);
                    ev.real_batch(&[w], &mut y)
                        .map(|_| y[target])
                        .unwrap_or(0.0)
                })
                .collect()
        };
        let mut errs = vec![];
        for e in [16usize, 32] {
            let g = CubeCross::new(e).unwrap();
            let c = project_real(&g, &sample(&g), lmax).unwrap();
            let err: f64 = c
                .iter()
                .enumerate()
                .map(|(i, v)| (v - if i == target { 1.0 } else { 0.0 }).abs())
                .fold(0.0, f64::max);
            errs.push(err);
        }
        assert!(errs[0] < 1e-2 && errs[1] < errs[0] / 3.0, "{errs:?}");
        let g = Equirect::new(64, 128).unwrap();
        let c = project_real(&g, &sample(&g), lmax).unwrap();
        assert!((c[target] - 1.0).abs() < 1e-3);
    }

    /// Fixed blocks added in order: the same bits on 1, 2 and 3 threads, also where high
    /// degrees take fewer texels per batch (lmax 70: 832 texels of 5041 values).
    #[test]
    fn sums_are_identical_across_thread_counts() {
        assert_eq!(texels_per_batch(num_coeffs(70)), 832);
        assert_eq!(texels_per_batch(num_coeffs(1000)), 4);
        assert_eq!(texels_per_batch(1), CHUNK);
        let g = Equirect::new(24, 48).unwrap();
        let v = crate::random::pseudo_random(g.len(), 3);
        let run = |threads: usize| {
            crate::testing::on_threads(threads, || project_real(&g, &v, 70).unwrap())
        };
        let one = run(1);
        assert_eq!(one, run(2));
        assert_eq!(one, run(3));
    }

    #[test]
    fn non_finite_texels_are_errors() {
        let g = Equirect::new(2, 4).unwrap();
        let mut v = vec![1.0; 8];
        v[3] = f64::NAN;
        assert!(project_real(&g, &v, 2).is_err());
        assert!(project_real(&g, &v[..5], 2).is_err());
    }
}
