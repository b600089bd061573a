//! Scalar spherical harmonics: Legendre functions, complex and real SH, Wigner D
//! rotations, exact quadrature and transforms, Wigner 3j symbols, Gaunt coefficients and
//! their tables, zonal harmonics, solid harmonics with Cartesian SH gradients and Hessians
//! (SHH).
//!
//! Conventions (see `docs/conventions.md`): `Y_lm = A_lm P_l^m(cos theta) e^{i m phi}`
//! with the Condon-Shortley phase in `P_l^m` (PSH (1)); real SH by PSH (12); coefficients
//! stored in flat order `l*l + l + m`.

mod cartesian;
pub(crate) mod column_recursion;
mod double_double;
pub(crate) mod gaunt;
pub(crate) mod gaunt_table;
pub(crate) mod grid;
pub(crate) mod harmonics;
pub(crate) mod legendre;
pub(crate) mod order_sums;
pub(crate) mod order_transform;
pub(crate) mod pixel;
pub(crate) mod solid;
pub(crate) mod transform;
pub(crate) mod wigner;
pub(crate) mod wigner3j;
pub(crate) mod window;
pub(crate) mod zonal;

pub use gaunt::{gaunt, gaunt_product, real_gaunt};
pub use gaunt_table::{GauntBasis, GauntEntry, GauntTable, MAX_TABLE_DEGREE};
pub use grid::{GaussLegendre, SphereGrid};
pub use harmonics::{real_from_complex, sh_complex, sh_real, ShEvaluator};
pub use legendre::{
    for_each_column_accurate, legendre_all, legendre_polynomials, tri_index, zonal_legendre,
    Legendre, Polar,
};
pub use pixel::{project_real, project_real_channels};
pub use solid::{
    hessian_index, sh_derivatives, Derivatives, SolidHarmonics, HESSIAN_ENTRIES, SOLID_MAX_DEGREE,
};
pub use transform::ShTransform;
pub use wigner::{
    for_each_block, for_each_small_d, real_block, rotate_z_complex, rotate_z_real, small_d_block,
    small_d_column, RealWignerD, SmallDHalf, SmallDRecursion, WignerD,
};
pub use wigner3j::{wigner_3j, wigner_3j_row, wigner_3j_row_into, Wigner3jRow, MAX_GAUNT_DEGREE};
pub use window::Window;
pub use zonal::{
    funk_hecke, rotated_zonal_complex, rotated_zonal_real, zonal_coefficients, ZonalCoefficients,
};

use crate::error::{Error, Result};

/// Largest degree any routine of this module accepts. Tables of recursion
/// coefficients take `O(MAX_DEGREE^2)` memory (about 270 MB at this limit).
pub const MAX_DEGREE: usize = 8192;

/// Flat index of `(l, m)`: `l*l + l + m`.
#[inline]
pub const fn lm_index(l: usize, m: i64) -> usize {
    (l * l + l).wrapping_add_signed(m as isize)
}

/// Number of coefficients of degrees `l <= lmax`: `(lmax + 1)^2`.
#[inline]
pub const fn num_coeffs(lmax: usize) -> usize {
    (lmax + 1) * (lmax + 1)
}

/// `(l, m)` of a flat index (inverse of [`lm_index`]).
#[inline]
pub fn lm_of_index(i: usize) -> (usize, i64) {
    let mut l = (i as f64).sqrt() as usize;
    while l * l > i {
        l -= 1;
    }
    while (l + 1) * (l + 1) <= i {
        l += 1;
    }
    (l, i as i64 - (l * l + l) as i64)
}

/// Checks `lmax <= MAX_DEGREE`.
pub fn check_lmax(lmax: usize) -> Result<()> {
    check_degree_limit("lmax", lmax, MAX_DEGREE, "the largest supported degree")
}

/// Checks `lmax <= limit`; the error names `name`, `lmax` and says `what` the limit is.
pub fn check_degree_limit(name: &'static str, lmax: usize, limit: usize, what: &str) -> Result<()> {
    if lmax > limit {
        return Err(Error::DegreeOutOfRange {
            name,
            value: lmax as i128,
            reason: format!("{what} is {limit}"),
        });
    }
    Ok(())
}

/// Checks `0 <= l` and `|m| <= l`.
pub fn check_lm(l: i64, m: i64) -> Result<()> {
    if l < 0 {
        return Err(Error::DegreeOutOfRange {
            name: "l",
            value: l.into(),
            reason: "degrees are non-negative".into(),
        });
    }
    if m.abs() > l {
        return Err(Error::OrderOutOfRange { name: "m", l, m });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_index_round_trips() {
        let mut i = 0;
        for l in 0..40usize {
            for m in -(l as i64)..=l as i64 {
                assert_eq!(lm_index(l, m), i);
                assert_eq!(lm_of_index(i), (l, m));
                i += 1;
            }
        }
        assert_eq!(i, num_coeffs(39));
    }
}
