//! Projection PSH (32) of Stokes images on pixel grids: the texel-wise quadrature
//! `f_lmp ~ sum_i Omega_i <Y_lmp(w_i), s_i>` with exact solid angles `Omega_i`
//! ([`crate::geometry::image_grid`]). Each texel's components are given in a frame field
//! (e.g. the cube-map frame field of the shared environment maps) and converted to the
//! theta-phi frame field of PSH (28) before they meet the basis (PSH (14)). Not exact (an
//! image is not band-limited): the error is that of the midpoint rule per texel.

use super::{Codomain, PshVector};
use crate::error::{check_len, Error, Result};
use crate::geometry::frame::FrameField;
use crate::geometry::image_grid::PixelGrid;
use crate::sh::lm_index;
use crate::sh::pixel::{block_sum, partials_at_once, project_real_channels};
use crate::stokes::StokesComponents;
use crate::swsh::{HalfAngle, SpinEvaluator};
use num_complex::Complex64;

/// Texels per lane block of the spin-2 recursion.
const LANES: usize = 16;

/// PSH coefficients of `l <= lmax` of Stokes images (one slice of texels per
/// channel, row-major over `grid`, components `[s0, s1, s2, s3]` in `frames`), for the
/// components of `codomain`. Texels of zero solid angle (off the cube cross) are ignored;
/// a NaN or infinite component elsewhere is an error naming the texel.
pub fn project_image(
    grid: &(impl PixelGrid + Sync),
    frames: &(impl FrameField + Sync),
    channels: &[&[[f64; 4]]],
    codomain: Codomain,
    lmax: usize,
) -> Result<PshVector> {
    let mut out = PshVector::zeros(lmax, codomain, channels.len())?;
    for ch in channels {
        check_len("Stokes image", grid.len(), ch.len())?;
    }
    // Spin 0: s0 and s3 are frame independent; one projection of all of them shares the
    // SH evaluation.
    let spin0: Vec<(usize, usize)> = codomain
        .components()
        .iter()
        .copied()
        .enumerate()
        .filter(|&(_, p)| p == 0 || p == 3)
        .collect();
    let images: Vec<Vec<f64>> = spin0
        .iter()
        .flat_map(|&(_, p)| {
            channels
                .iter()
                .map(move |ch| ch.iter().map(|s| s[p]).collect())
        })
        .collect();
    if !images.is_empty() {
        let refs: Vec<&[f64]> = images.iter().map(|v| v.as_slice()).collect();
        for (i, coeffs) in project_real_channels(grid, &refs, lmax)?.iter().enumerate() {
            out.set_component(i % channels.len(), spin0[i / channels.len()].0, coeffs);
        }
    }
    // Spin 2: a_lm = sum_i Omega_i conj(2Y_lm(w_i)) z_i, z = s1 + i s2 in the theta-phi frame
    // (nothing below l = 2, PSH (31)).
    if lmax < 2 {
        return Ok(out);
    }
    let eval = SpinEvaluator::new(2, lmax)?;
    let rows = 2 * channels.len();
    let texels: Vec<(usize, f64)> = (0..grid.len())
        .map(|i| (i, grid.solid_angle(i)))
        .filter(|&(_, omega)| omega > 0.0)
        .collect();
    // Per worker four partial sums per coefficient and row (re, im of each channel),
    // returned as their sum; the sum of the blocks.
    let n = crate::sh::num_coeffs(lmax);
    crate::budget::check(
        "the work space of a spin-2 projection",
        &[n, rows, 5 * partials_at_once() + 1],
        8,
    )?;
    let acc = block_sum(&texels, LANES, n * rows, |block| {
        let mut acc = vec![[0.0; 4]; n * rows];
        let mut scratch = Vec::new();
        let mut z = vec![[0.0; LANES]; rows];
        let mut g = z.clone();
        // cos(m phi), sin(m phi) per lane, m = 0..=lmax.
        let mut cos_m = vec![[1.0; LANES]; lmax + 1];
        let mut sin_m = vec![[0.0; LANES]; lmax + 1];
        for chunk in block.chunks(LANES) {
            let mut half = [HalfAngle::from_theta(0.0); LANES];
            z.iter_mut().for_each(|r| r.fill(0.0));
            for (j, &(i, omega)) in chunk.iter().enumerate() {
                let w = grid.direction(i);
                let rho = w[0].hypot(w[1]);
                half[j] = HalfAngle::from_z_rho(w[2], rho);
                // e^{i phi}, with phi = 0 at the poles (docs/conventions.md Sec. 1).
                let (cp, sp) = if rho > 0.0 {
                    (w[0] / rho, w[1] / rho)
                } else {
                    (1.0, 0.0)
                };
                (cos_m[1][j], sin_m[1][j]) = (cp, sp);
                let rot = to_theta_phi(&frames.frame(w)?, [w[2] * cp, w[2] * sp, -rho]);
                for (c, ch) in channels.iter().enumerate() {
                    let s = StokesComponents::new(ch[i]).map_err(|_| Error::InvalidArgument {
                        name: "Stokes texel",
                        value: format!("channel {c}, texel {i}: {:?}", ch[i]),
                        reason: "components must be finite".into(),
                    })?;
                    let v = rot * Complex64::new(s.s1(), s.s2()) * omega;
                    z[2 * c][j] = v.re;
                    z[2 * c + 1][j] = v.im;
                }
            }
            // e^{i m phi} = e^{i (m-1) phi} e^{i phi}.
            for m in 2..=lmax {
                for j in 0..LANES {
                    let (c, s) = (cos_m[m - 1][j], sin_m[m - 1][j]);
                    cos_m[m][j] = c * cos_m[1][j] - s * sin_m[1][j];
                    sin_m[m][j] = s * cos_m[1][j] + c * sin_m[1][j];
                }
            }
            eval.for_each_order_lanes(&half, &mut scratch, |m, l0, col| {
                // g = z e^{-i m phi} per lane, with sin(-m phi) = -sin(m phi).
                let (cm, sm) = (
                    &cos_m[m.unsigned_abs() as usize],
                    &sin_m[m.unsigned_abs() as usize],
                );
                let sign = if m >= 0 { -1.0 } else { 1.0 };
                for (zc, gc) in z.chunks_exact(2).zip(g.chunks_exact_mut(2)) {
                    for j in 0..LANES {
                        let (zr, zi, s) = (zc[0][j], zc[1][j], sign * sm[j]);
                        gc[0][j] = zr * cm[j] - zi * s;
                        gc[1][j] = zi * cm[j] + zr * s;
                    }
                }
                accumulate(col, &g, &mut acc, |k| lm_index(l0 + k, m));
            });
        }
        Ok(acc.iter().map(|v| (v[0] + v[1]) + (v[2] + v[3])).collect())
    })?;
    for c in 0..channels.len() {
        let a: Vec<Complex64> = acc
            .chunks_exact(rows)
            .map(|r| Complex64::new(r[2 * c], r[2 * c + 1]))
            .collect();
        out.set_spin2(c, &a);
    }
    Ok(out)
}

/// `acc[index(k) * rows + r] += ` the four partial sums over the lanes of
/// `col[k][lane] * g[r][lane]`, `rows = g.len()`.
#[inline(never)]
fn accumulate(
    col: &[[f64; LANES]],
    g: &[[f64; LANES]],
    acc: &mut [[f64; 4]],
    index: impl Fn(usize) -> usize,
) {
    let rows = g.len();
    for (r, gr) in g.iter().enumerate() {
        for (k, p) in col.iter().enumerate() {
            let ar = &mut acc[index(k) * rows + r];
            for t in 0..4 {
                ar[t] += (p[t] * gr[t] + p[4 + t] * gr[4 + t])
                    + (p[8 + t] * gr[8 + t] + p[12 + t] * gr[12 + t]);
            }
        }
    }
}

/// The factor `e^{-2 i vartheta}` that takes `s1 + i s2` from frame `from` to the frame of
/// the same ray with `x` axis `x_to` (PSH (14)), with `vartheta` the angle from `x` of
/// `from` to `x_to`: `cos vartheta = x_to . x`, `sin vartheta = x_to . y`. For the
/// theta-phi frame `x_to = e_theta = (cos theta cos phi, cos theta sin phi, -sin theta)`
/// (PSH Sec. 5.1), so no frame object is built per texel.
fn to_theta_phi(from: &crate::geometry::frame::Frame, x_to: [f64; 3]) -> Complex64 {
    let x_to = nalgebra::Vector3::from(x_to);
    let (c, s) = (x_to.dot(&from.x()), x_to.dot(&from.y()));
    let n2 = c * c + s * s;
    Complex64::new((c * c - s * s) / n2, -2.0 * c * s / n2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::frame::CubeMapFrameField;
    use crate::geometry::image_grid::CubeCross;

    /// A band-limited field sampled on cube maps (components in the cube-map frame field)
    /// projects back to its coefficients up to the midpoint-rule error, falling like 1/e^2.
    #[test]
    fn cube_map_projection_converges() {
        let lmax = 4;
        let v = crate::testing::random_psh(lmax, Codomain::Full, 1, 5).unwrap();
        let mut errs = vec![];
        for e in [16usize, 32] {
            let g = CubeCross::new(e).unwrap();
            let field = CubeMapFrameField;
            let img: Vec<[f64; 4]> = (0..g.len())
                .map(|i| {
                    if g.solid_angle(i) == 0.0 {
                        return [0.0; 4];
                    }
                    let w = g.direction(i);
                    let s = v.evaluate(0, w).unwrap();
                    s.components_in(&field.frame(w).unwrap())
                        .unwrap()
                        .to_array()
                })
                .collect();
            let p = project_image(&g, &field, &[&img], Codomain::Full, lmax).unwrap();
            let err = p
                .data()
                .iter()
                .zip(v.data())
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            errs.push(err);
        }
        assert!(errs[0] < 2e-2 && errs[1] < errs[0] / 3.0, "{errs:?}");
    }
}
