//! Projection PSH (32) of Stokes images on pixel grids: the texel-wise quadrature
//! `f_lmp ~ sum_i Omega_i <Y_lmp(w_i), s_i>` with exact solid angles `Omega_i`
//! ([`crate::geometry::image_grid`]). Each texel's components are given in a frame field
//! (e.g. the cube-map frame field of the shared environment maps) and converted to the
//! theta-phi frame field of PSH (28) before they meet the basis (PSH (14)). Not exact (an
//! image is not band-limited): the error is that of the midpoint rule per texel.

use super::{Codomain, PshVector};
use crate::error::{check_len, Error, Result};
use crate::geometry::frame::{FrameField, ThetaPhiFrameField};
use crate::geometry::image_grid::PixelGrid;
use crate::sh::harmonics::direction_angles;
use crate::sh::lm_index;
use crate::sh::pixel::project_real_channels;
use crate::stokes::{StokesComponents, StokesVector};
use crate::swsh::transform::SpinEvaluator;
use num_complex::Complex64;

/// PSH coefficients of `l <= lmax` of Stokes images (one slice of texels per
/// channel, row-major over `grid`, components `[s0, s1, s2, s3]` in `frames`), for the
/// components of `codomain`. Texels of zero solid angle (off the cube cross) are ignored;
/// a NaN or infinite component elsewhere is an error naming the texel.
pub fn project_image(
    grid: &impl PixelGrid,
    frames: &impl FrameField,
    channels: &[&[[f64; 4]]],
    codomain: Codomain,
    lmax: usize,
) -> Result<PshVector> {
    let mut out = PshVector::zeros(lmax, codomain, channels.len())?;
    for ch in channels {
        check_len("Stokes image", grid.len(), ch.len())?;
    }
    // Spin 0: s0 and s3 are frame independent.
    for (k, &p) in codomain.components().iter().enumerate() {
        if p == 0 || p == 3 {
            let images: Vec<Vec<f64>> = channels
                .iter()
                .map(|ch| ch.iter().map(|s| s[p]).collect())
                .collect();
            let refs: Vec<&[f64]> = images.iter().map(|v| v.as_slice()).collect();
            for (c, coeffs) in project_real_channels(grid, &refs, lmax)?.iter().enumerate() {
                out.set_component(c, k, coeffs);
            }
        }
    }
    // Spin 2: a_lm = sum_i Omega_i conj(2Y_lm(w_i)) z_i, z = s1 + i s2 in the theta-phi frame
    // (nothing below l = 2, PSH (31)).
    if lmax < 2 {
        return Ok(out);
    }
    let eval = SpinEvaluator::new(2, lmax)?;
    let theta_phi = ThetaPhiFrameField::new();
    let n = crate::sh::num_coeffs(lmax);
    let mut acc = vec![vec![Complex64::default(); n]; channels.len()];
    let mut z = vec![Complex64::default(); channels.len()];
    for i in 0..grid.len() {
        let omega = grid.solid_angle(i);
        if omega <= 0.0 {
            continue;
        }
        let w = grid.direction(i);
        let (from, to) = (frames.frame(w)?, theta_phi.frame(w)?);
        for (c, ch) in channels.iter().enumerate() {
            let comps = StokesComponents::new(ch[i]).map_err(|_| Error::InvalidArgument {
                name: "Stokes texel",
                value: format!("channel {c}, texel {i}: {:?}", ch[i]),
                reason: "components must be finite".into(),
            })?;
            let s = StokesVector::new(comps, from).components_in(&to)?;
            z[c] = Complex64::new(s.s1(), s.s2()) * omega;
        }
        let (theta, phi) = direction_angles(w)?;
        eval.for_each_order(theta, |m, l0, lambda| {
            let (cm, sm) = crate::sh::harmonics::cis_m(m.unsigned_abs() as usize, phi);
            // conj(e^{i m phi}) = e^{-i m phi}.
            let e = Complex64::new(cm, -(m.signum() as f64) * sm);
            for (c, zc) in z.iter().enumerate() {
                let g = zc * e;
                for (k, &v) in lambda.iter().enumerate() {
                    acc[c][lm_index(l0 + k, m)] += g * v;
                }
            }
        });
    }
    for (c, a) in acc.iter().enumerate() {
        out.set_spin2(c, a);
    }
    Ok(out)
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
        let v = crate::verify::random_psh(lmax, Codomain::Full, 1, 5).unwrap();
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
