//! The coefficient matrix of a rotation acting on the linear polarization of Stokes
//! fields, under two bases (PSH Fig. 10 (b) and (c)):
//!
//! - scalar SH applied to the components `z = s1 + i s2` in the theta-phi frame field (the
//!   naive approach): entries `<Y_lm, R_F[Y_l'm' as spin-2 components]>`;
//! - spin-2 SH (PSH (26), (28)): entries `<2Y_lm, R_F[2Y_l'm']>`, which PSH (36) says are
//!   `delta_ll' D^l_mm'`.
//!
//! `R_F` acts on Stokes fields by PSH (25), carried out with the typed layer (Stokes
//! vectors rotated with their frames). The naive matrix is computed by quadrature on a
//! finer grid (its basis fields are not smooth spin-2 fields, so no grid is exact); the
//! spin-2 one on the exact grid. The library shows the paper's point by measuring the
//! off-block mass of each (checks `polarized.naive_not_block_diagonal`,
//! `polarized.spin2_block_diagonal`).

use crate::error::Result;
use crate::geometry::direction_angles;
use crate::geometry::frame::{FrameField, ThetaPhiFrameField};
use crate::sh::evaluation::harmonics::sh_complex;
use crate::sh::num_coeffs;
use crate::sh::transform::sht::ShTransform;
use crate::stokes::{StokesComponents, StokesVector};
use crate::swsh::swsh;
use crate::swsh::SpinTransform;
use nalgebra::{Rotation3, Vector3};
use num_complex::Complex64;

/// The basis in which the rotation's coefficient matrix is taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LinearBasis {
    /// Scalar complex SH on the theta-phi components (PSH Fig. 10(b)).
    ScalarThetaPhi,
    /// Spin-2 SH (PSH Fig. 10(c)).
    Spin2,
}

/// The `(lmax+1)^2` square coefficient matrix (row-major; rows `(l, m)` out, columns
/// `(l', m')` in, flat order) of the rotation `r` on linear polarization, under `basis`,
/// projected on the Gauss-Legendre grid of band limit `grid_lmax` (`>= lmax`).
pub fn rotation_coefficient_matrix(
    basis: LinearBasis,
    r: &Rotation3<f64>,
    lmax: usize,
    grid_lmax: usize,
) -> Result<Vec<Complex64>> {
    let n = num_coeffs(lmax);
    let field = ThetaPhiFrameField::new();
    let eval = |t: f64, p: f64| match basis {
        LinearBasis::ScalarThetaPhi => sh_complex(lmax, t, p),
        LinearBasis::Spin2 => swsh(2, lmax, t, p),
    };
    let scalar = ShTransform::new(grid_lmax)?;
    let grid = scalar.grid().clone();
    let spin = SpinTransform::with_grid(2, grid_lmax, grid.clone())?;
    // Per grid point w: the basis at R^-1 w and the frames needed by PSH (25).
    let mut src_vals = Vec::with_capacity(grid.len());
    let mut frames = Vec::with_capacity(grid.len());
    for i in 0..grid.len() {
        let w = grid.direction(i)?;
        let v = r.inverse() * Vector3::from(w);
        let src = [v.x, v.y, v.z];
        let (t, p) = direction_angles(src)?;
        src_vals.push(eval(t, p)?);
        frames.push((field.frame(src)?, field.frame(w)?));
    }
    let big = num_coeffs(grid_lmax);
    let mut out = vec![Complex64::default(); n * n];
    let mut rotated = vec![Complex64::default(); grid.len()];
    let mut coeffs = vec![Complex64::default(); big];
    for j in 0..n {
        for (i, (f_src, f_dst)) in frames.iter().enumerate() {
            let z = src_vals[i][j];
            let s = StokesVector::new(StokesComponents::new([0.0, z.re, z.im, 0.0])?, *f_src);
            let c = s.rotate(r)?.components_in(f_dst)?;
            rotated[i] = Complex64::new(c.s1(), c.s2());
        }
        match basis {
            LinearBasis::ScalarThetaPhi => scalar.analysis_complex(&rotated, &mut coeffs)?,
            LinearBasis::Spin2 => spin.analysis(&rotated, &mut coeffs)?,
        }
        for i in 0..n {
            out[i * n + j] = coeffs[i];
        }
    }
    Ok(out)
}

/// The fraction of the squared Frobenius norm of a flat-order coefficient matrix that lies
/// outside its diagonal blocks `l = l'`.
pub fn off_block_fraction(matrix: &[Complex64], lmax: usize) -> f64 {
    let n = num_coeffs(lmax);
    let (mut off, mut total) = (0.0, 0.0);
    for i in 0..n {
        for j in 0..n {
            let v = matrix[i * n + j].norm_sqr();
            total += v;
            if crate::sh::lm_of_index(i).0 != crate::sh::lm_of_index(j).0 {
                off += v;
            }
        }
    }
    if total > 0.0 {
        off / total
    } else {
        0.0
    }
}
