//! Projection of sampled images onto SH: `f_lm ~ sum_i Omega_i f(w_i) Y_lm(w_i)`, the
//! texel-wise quadrature of PSH (3) with exact per-texel solid angles `Omega_i`
//! ([`crate::geometry::image_grid`]), summed order by order ([`crate::sh::transform::texel_sums`]). Not
//! exact (an image is not band-limited): the error is that of the midpoint rule per texel.

use crate::error::{check_len, finite, Result};
use crate::geometry::image_grid::PixelGrid;
use crate::sh::index::{check_lmax, lm_index, num_coeffs};
use crate::sh::recursion::lambda::Columns;
use crate::sh::transform::texel_sums::{order_sums, Site};
use num_complex::Complex64;
use std::f64::consts::SQRT_2;
use std::sync::Mutex;

/// The texels of a grid on the sphere (non-zero solid angle: those off a cube cross are
/// not), in grid order.
pub(crate) struct Texels {
    /// Index in the grid.
    pub(crate) index: Vec<usize>,
    /// Solid angle.
    pub(crate) omega: Vec<f64>,
    pub(crate) sites: Vec<Site>,
}

impl Texels {
    pub(crate) fn of(grid: &impl PixelGrid) -> Self {
        let (index, omega): (Vec<usize>, Vec<f64>) = (0..grid.len())
            .map(|i| (i, grid.solid_angle(i)))
            .filter(|&(_, w)| w > 0.0)
            .unzip();
        let sites = index
            .iter()
            .map(|&i| Site::new(grid.direction(i)))
            .collect();
        Self {
            index,
            omega,
            sites,
        }
    }
}

/// Real SH coefficients (PSH (12)) of real images: `v[i * rows + r]` is image `r` at
/// `sites[i]` (weights folded in; real values, as complex numbers); `put(r, lm, f_lm)` for
/// each coefficient of `l <= lmax` (flat index `lm`), `put` locked once per order. From
/// the sums `a_lm = sum_i conj(Y_lm(w_i)) v_i` of the orders `m >= 0` ([`order_sums`]) and
/// `Y^R_lm = sqrt(2) Re Y_lm`, `Y_l0`, `sqrt(2) Im Y_{l|m|}` (`m > 0`, `0`, `< 0`;
/// [`crate::sh::evaluation::harmonics`]): `f_l0 = Re a_l0`, `f_lm = sqrt(2) Re a_lm`,
/// `f_{l,-m} = -sqrt(2) Im a_lm`.
pub(crate) fn real_sums(
    lmax: usize,
    sites: &[Site],
    v: &[Complex64],
    put: &Mutex<impl FnMut(usize, usize, f64) + Send>,
) {
    let rows = v.len() / sites.len().max(1);
    order_sums(
        &Columns::new(0, lmax),
        sites,
        v,
        |m| m >= 0,
        |m, l0, a| {
            let mut put = put.lock().unwrap_or_else(|e| e.into_inner());
            for (k, ar) in a.chunks_exact(rows).enumerate() {
                for (r, x) in ar.iter().enumerate() {
                    if m == 0 {
                        put(r, lm_index(l0 + k, 0), x.re);
                    } else {
                        put(r, lm_index(l0 + k, m), SQRT_2 * x.re);
                        put(r, lm_index(l0 + k, -m), -SQRT_2 * x.im);
                    }
                }
            }
        },
    );
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
/// recursion: one coefficient vector per channel, summed order by order.
pub fn project_real_channels(
    grid: &(impl PixelGrid + Sync),
    channels: &[&[f64]],
    lmax: usize,
) -> Result<Vec<Vec<f64>>> {
    check_lmax(lmax)?;
    for c in channels {
        check_len("image values", grid.len(), c.len())?;
    }
    let nch = channels.len();
    let texels = Texels::of(grid);
    // The coefficients, the weighted values (as complex numbers) and the sums of the
    // ranges of orders in flight (less than the coefficients again).
    crate::budget::check(
        "the work space of an SH projection",
        &[2 * num_coeffs(lmax) + 2 * texels.index.len(), nch],
        8,
    )?;
    let mut v = Vec::with_capacity(texels.index.len() * nch);
    for (&i, &w) in texels.index.iter().zip(&texels.omega) {
        for c in channels {
            v.push(Complex64::new(finite("texel value", c[i])? * w, 0.0));
        }
    }
    let mut out = vec![vec![0.0; num_coeffs(lmax)]; nch];
    real_sums(
        lmax,
        &texels.sites,
        &v,
        &Mutex::new(|r: usize, lm: usize, x: f64| out[r][lm] = x),
    );
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::image_grid::{CubeCross, Equirect};
    use crate::sh::evaluation::harmonics::ShEvaluator;
    use crate::sh::index::{lm_index, num_coeffs};

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

    /// Each coefficient summed by one task in texel order: the same bits on 1, 2 and 3
    /// threads.
    #[test]
    fn sums_are_identical_across_thread_counts() {
        let g = Equirect::new(24, 48).unwrap();
        let v = crate::random::pseudo_random(g.len(), 3);
        let run = |threads: usize| {
            crate::testing::on_threads(threads, || project_real(&g, &v, 70).unwrap())
        };
        let one = run(1);
        assert_eq!(one, run(2));
        assert_eq!(one, run(3));
    }

    /// The order-major sums against the texel-major quadrature with the real SH of
    /// [`ShEvaluator`] (their own recursion and the complex-to-real step of PSH (12)), two
    /// channels, on a cube cross (poles and seams among the texels) to degree 40.
    #[test]
    fn sums_equal_the_texel_quadrature_of_the_real_sh() {
        let lmax = 40;
        let g = CubeCross::new(12).unwrap();
        let ev = ShEvaluator::new(lmax).unwrap();
        let a = crate::random::pseudo_random(g.len(), 7);
        let b = crate::random::pseudo_random(g.len(), 8);
        let got = project_real_channels(&g, &[&a, &b], lmax).unwrap();
        let mut want = vec![vec![0.0; num_coeffs(lmax)]; 2];
        let mut y = vec![0.0; num_coeffs(lmax)];
        for i in (0..g.len()).filter(|&i| g.solid_angle(i) > 0.0) {
            ev.real_batch(&[g.direction(i)], &mut y).unwrap();
            for (w, v) in want.iter_mut().zip([&a, &b]) {
                for (x, yk) in w.iter_mut().zip(&y) {
                    *x += g.solid_angle(i) * v[i] * yk;
                }
            }
        }
        for (gc, wc) in got.iter().zip(&want) {
            for (k, (x, y)) in gc.iter().zip(wc).enumerate() {
                assert!((x - y).abs() < 1e-13, "coefficient {k}: {x} vs {y}");
            }
        }
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
