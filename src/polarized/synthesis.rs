//! Reconstruction PSH (30) on pixel grids: the Stokes field of a coefficient vector at
//! every texel of an image, with components in a given frame field.
//!
//! Texels are grouped by polar angle: for each distinct `theta` the sums over `l` are done
//! once, `g_m(theta) = sum_l f_lm Pbar_lm(theta)` (real SH, PSH (12)) and
//! `h_m(theta) = sum_l a_lm Lambda_lm(theta)` with `2Y_lm = Lambda_lm e^{i m phi}`
//! (PSH (29)-(30)), and each texel adds up `O(lmax)` Fourier terms. An equirectangular
//! image costs `O(H lmax^2 + H W lmax)`, a cube map `O(texels lmax^2)`. The values come
//! out in the theta-phi frames (PSH (28)) and are converted to `frames` by PSH (14).

use super::PshVector;
use crate::error::Result;
use crate::geometry::frame::{FrameField, ThetaPhiFrameField};
use crate::geometry::image_grid::PixelGrid;
use crate::sh::evaluation::harmonics::CisWalk;
use crate::sh::lm_index;
use crate::sh::recursion::legendre::{Legendre, Polar};
use crate::stokes::{StokesComponents, StokesVector};
use crate::swsh::SpinEvaluator;
use num_complex::Complex64;
use std::f64::consts::SQRT_2;

/// The Stokes components `[s0, s1, s2, s3]` of every channel of `v` at the texels of
/// `grid` (row-major), in the frames of `frames`; texels of zero solid angle (off a cube
/// cross) are left zero. Components outside `v`'s codomain are zero. Error: the image over
/// the memory budget ([`crate::budget`]).
pub fn reconstruct_image(
    v: &PshVector,
    grid: &impl PixelGrid,
    frames: &impl FrameField,
) -> Result<Vec<Vec<[f64; 4]>>> {
    let lmax = v.lmax();
    let nch = v.channels();
    // The image (4 components per channel) and the texel list, before either exists.
    crate::budget::check("the reconstructed image", &[grid.len(), 4 * nch + 3], 8)?;
    let mut texels = Vec::with_capacity(grid.len());
    for i in 0..grid.len() {
        if grid.solid_angle(i) > 0.0 {
            let (theta, phi) = grid.angles(i)?;
            texels.push((theta, phi, i));
        }
    }
    texels.sort_by(|a, b| a.0.total_cmp(&b.0));

    let comps = v.codomain().components();
    // (slot k in the vector, Stokes index p) of the spin-0 components s0, s3.
    let scalar: Vec<(usize, usize)> = comps
        .iter()
        .enumerate()
        .filter(|(_, &p)| p == 0 || p == 3)
        .map(|(k, &p)| (k, p))
        .collect();
    let scalar_coeffs: Vec<Vec<Vec<f64>>> = (0..nch)
        .map(|c| scalar.iter().map(|&(k, _)| v.component(c, k)).collect())
        .collect();
    let spin_coeffs: Vec<Vec<Complex64>> = (0..nch).map(|c| v.spin2(c)).collect();
    let legendre = Legendre::new(lmax)?;
    let spin = if lmax >= 2 {
        Some(SpinEvaluator::new(2, lmax)?)
    } else {
        None
    };
    let theta_phi = ThetaPhiFrameField::new();
    let nm = 2 * lmax + 1;
    // g[c][j][m + lmax]: cosine (m >= 0) and sine (m < 0) sums of component j.
    let mut g = vec![vec![vec![0.0; nm]; scalar.len()]; nch];
    // h[c][m + lmax]: spin-2 Fourier coefficients.
    let mut h = vec![vec![Complex64::default(); nm]; nch];
    let mut cis = vec![Complex64::default(); lmax + 1];
    let mut out = vec![vec![[0.0; 4]; grid.len()]; nch];

    let mut start = 0;
    while start < texels.len() {
        let theta = texels[start].0;
        let end = start + texels[start..].partition_point(|t| t.0 == theta);
        legendre.for_each_column(Polar::from_theta(theta), |m, col| {
            for (gc, fc) in g.iter_mut().zip(&scalar_coeffs) {
                for (gj, f) in gc.iter_mut().zip(fc) {
                    let (mut cos_sum, mut sin_sum) = (0.0, 0.0);
                    for (k, &p) in col.iter().enumerate() {
                        cos_sum += f[lm_index(m + k, m as i64)] * p;
                        sin_sum += f[lm_index(m + k, -(m as i64))] * p;
                    }
                    gj[lmax + m] = cos_sum;
                    if m > 0 {
                        gj[lmax - m] = sin_sum;
                    }
                }
            }
        });
        if let Some(spin) = &spin {
            spin.for_each_order(theta, |m, l0, lambda| {
                for (hc, a) in h.iter_mut().zip(&spin_coeffs) {
                    hc[(m + lmax as i64) as usize] = lambda
                        .iter()
                        .enumerate()
                        .map(|(k, &x)| a[lm_index(l0 + k, m)] * x)
                        .sum();
                }
            });
        }
        for &(_, phi, i) in &texels[start..end] {
            fill_cis(phi, &mut cis);
            let to = theta_phi.frame_at_angles(theta, phi)?;
            let target = frames.frame(grid.direction(i))?;
            for c in 0..nch {
                let mut s = [0.0; 4];
                for (gj, &(_, p)) in g[c].iter().zip(&scalar) {
                    let mut x = gj[lmax];
                    for m in 1..=lmax {
                        x += SQRT_2 * (gj[lmax + m] * cis[m].re + gj[lmax - m] * cis[m].im);
                    }
                    s[p] = x;
                }
                if spin.is_some() {
                    let hc = &h[c];
                    let mut z = hc[lmax];
                    for m in 1..=lmax {
                        z += hc[lmax + m] * cis[m] + hc[lmax - m] * cis[m].conj();
                    }
                    (s[1], s[2]) = (z.re, z.im);
                }
                out[c][i] = StokesVector::new(StokesComponents::new(s)?, to)
                    .components_in(&target)?
                    .to_array();
            }
        }
        start = end;
    }
    Ok(out)
}

/// `cis[m] = e^{i m phi}` for `m = 0..cis.len()` ([`CisWalk`]).
fn fill_cis(phi: f64, cis: &mut [Complex64]) {
    let mut walk = CisWalk::new(phi);
    for (m, e) in cis.iter_mut().enumerate() {
        let (c, s) = walk.at(m);
        *e = Complex64::new(c, s);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::frame::CubeMapFrameField;
    use crate::geometry::image_grid::{CubeCross, Equirect};
    use crate::polarized::Codomain;

    /// Against the single-direction evaluation PSH (30) (`PshVector::evaluate`) on an
    /// equirectangular image (rows share theta) and on a cube map (each texel its own),
    /// converted to the image's frame field.
    #[test]
    fn matches_pointwise_evaluation() {
        let lmax = 9;
        for cod in [Codomain::Full, Codomain::NoCircular, Codomain::Linear] {
            let v = crate::testing::random_psh(lmax, cod, 2, 17).unwrap();
            let eq = Equirect::new(7, 14).unwrap();
            let tp = ThetaPhiFrameField::new();
            let cube = CubeCross::new(3).unwrap();
            let mut worst = 0.0f64;
            let mut check = |grid: &dyn Fn(usize) -> Option<[f64; 3]>,
                             frames: &dyn Fn([f64; 3]) -> crate::geometry::frame::Frame,
                             img: &[Vec<[f64; 4]>]| {
                for (c, ch) in img.iter().enumerate() {
                    for (i, got) in ch.iter().enumerate() {
                        let Some(w) = grid(i) else {
                            assert_eq!(got, &[0.0; 4]);
                            continue;
                        };
                        let want = v
                            .evaluate(c, w)
                            .unwrap()
                            .components_in(&frames(w))
                            .unwrap()
                            .to_array();
                        for p in 0..4 {
                            worst = worst.max((got[p] - want[p]).abs());
                        }
                    }
                }
            };
            let img = reconstruct_image(&v, &eq, &tp).unwrap();
            check(&|i| Some(eq.direction(i)), &|w| tp.frame(w).unwrap(), &img);
            let img = reconstruct_image(&v, &cube, &CubeMapFrameField).unwrap();
            check(
                &|i| (cube.solid_angle(i) > 0.0).then(|| cube.direction(i)),
                &|w| CubeMapFrameField.frame(w).unwrap(),
                &img,
            );
            assert!(worst < 1e-13, "{cod:?}: {worst}");
        }
    }
}
