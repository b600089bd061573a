//! The naive basis of PSH Sec. 4.4 (Figs. 7, 11): the Stokes components in the theta-phi
//! frame field each projected on scalar SH as if they were scalar fields.

use crate::error::Result;
use crate::geometry::Equirect;
use crate::geometry::PixelGrid;
use crate::polarized::{PshTransform, PshVector};
use crate::sh::{num_coeffs, RealWignerD, ShEvaluator, ShTransform};
use nalgebra::Rotation3;

/// Per channel, the theta-phi components on `grid` of `v`'s field projected per
/// component on scalar SH of degrees `l <= band` (quadrature on the exact grid of `v`'s
/// band limit; `band <= v.lmax()`), each rotated by `rotation` as if scalar (PSH Fig. 11's
/// naive rotation; none: Fig. 7's naive band limit).
pub fn naive_field(
    v: &PshVector,
    band: usize,
    rotation: Option<&Rotation3<f64>>,
    grid: &Equirect,
) -> Result<Vec<Vec<[f64; 4]>>> {
    let lmax = v.lmax();
    let kept = num_coeffs(band.min(lmax));
    let exact = PshTransform::new(lmax)?;
    let scalar = ShTransform::new(lmax)?;
    let d = rotation.map(|r| RealWignerD::new(r, lmax)).transpose()?;
    let eval = ShEvaluator::new(lmax)?;
    let dirs: Vec<[f64; 3]> = (0..grid.len()).map(|i| grid.direction(i)).collect();
    let n = num_coeffs(lmax);
    let mut basis = vec![0.0; dirs.len() * n];
    eval.real_batch(&dirs, &mut basis)?;
    let mut out = Vec::new();
    for c in 0..v.channels() {
        let field = exact.reconstruct(v, c)?;
        let mut img = vec![[0.0; 4]; grid.len()];
        for p in 0..4 {
            let values: Vec<f64> = field.iter().map(|s| s[p]).collect();
            let mut coeffs = vec![0.0; n];
            scalar.analysis_real(&values, &mut coeffs)?;
            coeffs[kept..].fill(0.0);
            let coeffs = match &d {
                Some(d) => d.rotate(&coeffs)?,
                None => coeffs,
            };
            for (i, px) in img.iter_mut().enumerate() {
                px[p] = basis[i * n..(i + 1) * n]
                    .iter()
                    .zip(&coeffs)
                    .map(|(y, f)| y * f)
                    .sum();
            }
        }
        out.push(img);
    }
    Ok(out)
}
