//! Scalar spherical harmonics: Legendre functions, complex and real SH, Wigner D
//! rotations, exact quadrature and transforms, Wigner 3j symbols, Gaunt coefficients and
//! their tables, zonal harmonics, solid harmonics with Cartesian SH gradients and Hessians
//! (SHH).
//!
//! Conventions (see `docs/conventions.md`): `Y_lm = A_lm P_l^m(cos theta) e^{i m phi}`
//! with the Condon-Shortley phase in `P_l^m` (PSH (1)); real SH by PSH (12); coefficients
//! stored in flat order `l*l + l + m`.
//!
//! | folder | what |
//! |---|---|
//! | `index` | the flat index `l*l + l + m`, [`MAX_DEGREE`] and the degree checks |
//! | `recursion/` | `legendre` (Pbar_lm, the Bonnet recurrence, the accurate double-double path), `lambda` (the recursion of `Lambda_lm = (-1)^s sqrt((2l+1)/(4 pi)) d^l_{m,-s}` shared by every spin), `double_double` |
//! | `evaluation/` | SH at points: `harmonics` (complex and real SH, [`ShEvaluator`]), `cartesian` (the small-degree SIMD batch), `solid` (gradients and Hessians, SHH), `zonal` (zonal harmonics, Funk-Hecke) |
//! | `transform/` | `grid` (Gauss-Legendre), `sht` ([`ShTransform`]), `sweeps` (the order-major synthesis and analysis of any spin), `texel_sums` (order-major sums over image texels), `pixel` (image projection) |
//! | `rotation/` | `small_d` (Risbo's recursion of `d^l(beta)`), `wigner_d` (`D^l` blocks, real blocks, rotation of coefficients) |
//! | `coupling/` | `wigner3j`, `gaunt` (Gaunt coefficients, PSH (58)), `gaunt_table` |
//! | `window` | windowed band limits |

pub(crate) mod coupling;
pub(crate) mod evaluation;
pub(crate) mod index;
pub mod kernels;
pub(crate) mod recursion;
pub(crate) mod rotation;
pub(crate) mod transform;
pub(crate) mod window;

pub use coupling::gaunt::{gaunt, gaunt_product, real_gaunt};
pub use coupling::gaunt_table::{GauntBasis, GauntEntry, GauntTable, MAX_TABLE_DEGREE};
pub use coupling::wigner3j::{wigner_3j, wigner_3j_row, Wigner3jRow, MAX_GAUNT_DEGREE};
pub use evaluation::harmonics::{real_from_complex, sh_complex, sh_real, ShEvaluator};
pub use evaluation::solid::{
    hessian_index, sh_derivatives, Derivatives, SolidHarmonics, HESSIAN_ENTRIES, SOLID_MAX_DEGREE,
};
pub use evaluation::zonal::{
    funk_hecke, rotated_zonal_complex, rotated_zonal_real, zonal_coefficients, ZonalCoefficients,
};
pub use index::{
    check_degree_limit, check_lm, check_lmax, lm_index, lm_of_index, num_coeffs, MAX_DEGREE,
};
pub use recursion::legendre::{legendre_all, legendre_polynomials, zonal_legendre};
pub use rotation::small_d::small_d_block;
pub use rotation::wigner_d::{
    for_each_block, real_block, rotate_z_complex, rotate_z_real, RealWignerD, WignerD,
};
pub use transform::grid::{GaussLegendre, SphereGrid};
pub use transform::pixel::{project_real, project_real_channels};
pub use transform::sht::ShTransform;
pub use window::Window;
