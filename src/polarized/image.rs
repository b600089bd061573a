//! Projection PSH (32) of Stokes images on pixel grids: the texel-wise quadrature
//! `f_lmp ~ sum_i Omega_i <Y_lmp(w_i), s_i>` with exact solid angles `Omega_i`
//! ([`crate::geometry::image_grid`]). Each texel's components are given in a frame field
//! (e.g. the cube-map frame field of the shared environment maps) and converted to the
//! theta-phi frame field of PSH (28) before they meet the basis (PSH (14)). Not exact (an
//! image is not band-limited): the error is that of the midpoint rule per texel. The sums
//! run order by order ([`crate::sh::transform::texel_sums`]): the work space is about the size of
//! the output.

use super::{Codomain, PshVector};
use crate::error::{check_len, Error, Result};
use crate::geometry::frame::FrameField;
use crate::geometry::image_grid::PixelGrid;
use crate::sh::recursion::lambda::Columns;
use crate::sh::transform::pixel::{real_sums, Texels};
use crate::sh::transform::texel_sums::order_sums;
use crate::sh::{lm_index, num_coeffs};
use num_complex::Complex64;
use rayon::prelude::*;
use std::sync::Mutex;

/// Texels per parallel task of the weighting (the values times the solid angles).
const TEXEL_CHUNK: usize = 1024;

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
    let texels = Texels::of(grid);
    let nch = channels.len();
    // The output, the weighted values (at most two complex numbers per channel and texel)
    // and the sums of the ranges of orders in flight (less than the output again).
    crate::budget::check(
        "the work space of a PSH projection",
        &[num_coeffs(lmax) + 4 * texels.index.len(), nch, 8],
        8,
    )?;
    let comps = codomain.components();
    // Spin 0: s0 and s3 are frame independent; real images (component k of channel c in
    // row k * nch + c) sharing one recursion.
    let spin0: Vec<(usize, usize)> = comps
        .iter()
        .copied()
        .enumerate()
        .filter(|&(_, p)| p == 0 || p == 3)
        .collect();
    // Spin 2: z = s1 + i s2 in the theta-phi frame (nothing below l = 2, PSH (31)).
    let spin2 = lmax >= 2 && codomain.has_spin2();
    let n = texels.index.len();
    let mut v = vec![Complex64::default(); n * nch * spin0.len()];
    let mut z = vec![Complex64::default(); if spin2 { n * nch } else { 0 }];
    // Texels in chunks, in parallel; the first error in texel order is returned.
    let (v_rows, z_rows) = (nch * spin0.len(), if spin2 { nch } else { 0 });
    let mut chunks = Vec::with_capacity(n.div_ceil(TEXEL_CHUNK));
    let (mut v_rest, mut z_rest) = (v.as_mut_slice(), z.as_mut_slice());
    for start in (0..n).step_by(TEXEL_CHUNK) {
        let k = TEXEL_CHUNK.min(n - start);
        let (vc, vr) = std::mem::take(&mut v_rest).split_at_mut(k * v_rows);
        let (zc, zr) = std::mem::take(&mut z_rest).split_at_mut(k * z_rows);
        (v_rest, z_rest) = (vr, zr);
        chunks.push((start..start + k, vc, zc));
    }
    let weigh = |(range, vc, zc): (std::ops::Range<usize>, &mut [Complex64], &mut [Complex64])| {
        for (t, k) in range.enumerate() {
            let (i, omega) = (texels.index[k], texels.omega[k]);
            for (c, ch) in channels.iter().enumerate() {
                check_texel(c, i, ch[i])?;
            }
            let vt = &mut vc[t * v_rows..(t + 1) * v_rows];
            for (row, (c, &(_, p))) in vt.iter_mut().zip(
                spin0
                    .iter()
                    .flat_map(|p| channels.iter().map(move |ch| (ch, p))),
            ) {
                *row = Complex64::new(c[i][p] * omega, 0.0);
            }
            if spin2 {
                // e_theta = (cos theta cos phi, cos theta sin phi, -sin theta).
                let w = grid.direction(i);
                let (cis, rho) = (texels.sites[k].cis(), w[0].hypot(w[1]));
                let rot = to_theta_phi(&frames.frame(w)?, [w[2] * cis.re, w[2] * cis.im, -rho]);
                for (row, ch) in zc[t * nch..(t + 1) * nch].iter_mut().zip(channels) {
                    *row = rot * Complex64::new(ch[i][1], ch[i][2]) * omega;
                }
            }
        }
        Ok(())
    };
    let results: Vec<Result<()>> = chunks.into_par_iter().map(weigh).collect();
    results.into_iter().collect::<Result<()>>()?;
    if !spin0.is_empty() {
        real_sums(
            lmax,
            &texels.sites,
            &v,
            &Mutex::new(|r: usize, lm: usize, x: f64| {
                out.set_coefficient(r % nch, lm, spin0[r / nch].0, x)
            }),
        );
    }
    if spin2 {
        let k1 = comps
            .iter()
            .position(|&p| p == 1)
            .expect("checked: the codomain has s1");
        let put = Mutex::new(&mut out);
        // a_lm = sum_i Omega_i conj(2Y_lm(w_i)) z_i.
        order_sums(
            &Columns::new(2, lmax),
            &texels.sites,
            &z,
            |_| true,
            |m, l0, a| {
                let mut out = put.lock().unwrap_or_else(|e| e.into_inner());
                for (k, ak) in a.chunks_exact(nch).enumerate() {
                    let lm = lm_index(l0 + k, m);
                    for (c, x) in ak.iter().enumerate() {
                        out.set_coefficient(c, lm, k1, x.re);
                        out.set_coefficient(c, lm, k1 + 1, x.im);
                    }
                }
            },
        );
    }
    Ok(out)
}

/// Error: a non-finite component of texel `i` (index on the grid) of channel `c`.
pub(crate) fn check_texel(c: usize, i: usize, s: [f64; 4]) -> Result<()> {
    if s.iter().all(|x| x.is_finite()) {
        return Ok(());
    }
    Err(Error::invalid(
        "Stokes texel",
        format!("channel {c}, texel {i}: {s:?}"),
        "components must be finite",
    ))
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
    use crate::stokes::StokesComponents;

    /// The order-major sums against the texel-major quadrature PSH (32) written out with
    /// the spin-weighted SH of [`crate::swsh::swsh`] (from the Wigner d, not the column
    /// recursion): `f_lm0 + i 0 = sum Omega s0 conj(Y_lm)` and
    /// `f_lm1 + i f_lm2 = sum Omega conj(2Y_lm) (s1 + i s2)` in the theta-phi frame, on a
    /// cube cross (poles and seams among the texels), two channels.
    #[test]
    fn sums_equal_the_texel_quadrature() {
        let lmax = 12;
        let g = CubeCross::new(6).unwrap();
        let field = CubeMapFrameField;
        let r = crate::random::pseudo_random(g.len() * 8, 4);
        let imgs: Vec<Vec<[f64; 4]>> = (0..2)
            .map(|c| {
                (0..g.len())
                    .map(|i| std::array::from_fn(|p| r[(c * g.len() + i) * 4 + p]))
                    .collect()
            })
            .collect();
        let refs: Vec<&[[f64; 4]]> = imgs.iter().map(|v| v.as_slice()).collect();
        let got = project_image(&g, &field, &refs, Codomain::Full, lmax).unwrap();
        let n = num_coeffs(lmax);
        let mut want = vec![[Complex64::default(); 3]; 2 * n];
        for i in (0..g.len()).filter(|&i| g.solid_angle(i) > 0.0) {
            let w = g.direction(i);
            let (theta, phi) = (w[2].acos(), w[1].atan2(w[0]));
            let (y0, y2) = (
                crate::swsh::swsh(0, lmax, theta, phi).unwrap(),
                crate::swsh::swsh(2, lmax, theta, phi).unwrap(),
            );
            let tp = crate::geometry::frame::ThetaPhiFrameField::default()
                .frame(w)
                .unwrap();
            for (c, img) in imgs.iter().enumerate() {
                let s = crate::stokes::StokesVector::new(
                    StokesComponents::new(img[i]).unwrap(),
                    field.frame(w).unwrap(),
                )
                .components_in(&tp)
                .unwrap()
                .to_array();
                let om = g.solid_angle(i);
                for lm in 0..n {
                    let acc = &mut want[c * n + lm];
                    acc[0] += om * s[0] * y0[lm].conj();
                    acc[1] += om * Complex64::new(s[1], s[2]) * y2[lm].conj();
                    acc[2] += om * s[3] * y0[lm].conj();
                }
            }
        }
        // Real SH coefficients of s0, s3 from the complex ones (PSH (12)).
        let real = |a: &[[Complex64; 3]], c: usize, l: usize, m: i64, k: usize| {
            let pos = a[c * n + lm_index(l, m.abs())][k];
            match m.signum() {
                0 => pos.re,
                1 => std::f64::consts::SQRT_2 * pos.re,
                _ => -std::f64::consts::SQRT_2 * pos.im,
            }
        };
        for c in 0..2 {
            for l in 0..=lmax {
                for m in -(l as i64)..=l as i64 {
                    let z = want[c * n + lm_index(l, m)][1];
                    let expect = [
                        real(&want, c, l, m, 0),
                        if l >= 2 { z.re } else { 0.0 },
                        if l >= 2 { z.im } else { 0.0 },
                        real(&want, c, l, m, 2),
                    ];
                    for (p, e) in expect.iter().enumerate() {
                        let x = got.get(c, l, m, p).unwrap();
                        assert!((x - e).abs() < 1e-13, "c {c} l {l} m {m} p {p}: {x} vs {e}");
                    }
                }
            }
        }
    }

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

    /// Of several non-finite texels in different parallel chunks, the error names the
    /// first in texel order, whatever chunk finishes first.
    #[test]
    fn the_first_bad_texel_is_named() {
        let g = CubeCross::new(24).unwrap();
        let valid: Vec<usize> = (0..g.len()).filter(|&i| g.solid_angle(i) > 0.0).collect();
        assert!(valid.len() > 3 * TEXEL_CHUNK);
        let (early, late) = (valid[100], valid[3 * TEXEL_CHUNK]);
        let mut imgs = vec![vec![[1.0, 0.1, 0.1, 0.0]; g.len()]; 2];
        imgs[0][late][2] = f64::NAN;
        imgs[1][early][0] = f64::INFINITY;
        let refs: Vec<&[[f64; 4]]> = imgs.iter().map(|v| v.as_slice()).collect();
        for _ in 0..4 {
            let e = project_image(&g, &CubeMapFrameField, &refs, Codomain::Full, 3).unwrap_err();
            assert!(
                e.to_string()
                    .contains(&format!("channel 1, texel {early}:")),
                "{e}"
            );
        }
    }
}
