//! Polarized spherical harmonics (PSH Sec. 6.2): the basis PSH (29) with index set
//! PSH (31), real coefficient vectors PSH (34), projection PSH (32) and reconstruction
//! PSH (30) on the exact grid, and rotation PSH (35)-(37).
//!
//! With the linear part of a Stokes field written as the complex spin-2 field
//! `z = s1 + i s2` (components in the theta-phi frame field, PSH (28)):
//!
//! - `Y_lm0 = [Y^R_lm, 0, 0, 0]`, `Y_lm3 = [0, 0, 0, Y^R_lm]` (real SH, PSH (12));
//! - `Y_lm1` has `z = 2Y_lm` and `Y_lm2` has `z = i 2Y_lm` (PSH (29)), so that
//!   `f_lm1 + i f_lm2 = <2Y_lm, z>` (PSH (32)-(34)) and `z = sum (f_lm1 + i f_lm2) 2Y_lm`.
//!
//! The index set PSH (31): `l >= 0` for `p = 0, 3`, `l >= 2` for `p = 1, 2`; coefficients
//! outside it are stored as zeros. Storage follows the polarsh `.npz` layout
//! `coeff[channel][l*l + l + m][p]`, `p` running over the codomain's components.

// The angular-domain reference PSH (39) that `psh verify` checks the products against.
#[cfg(feature = "verify")]
mod angular;
mod argument;
mod codomain;
mod convolution;
mod cube;
mod evaluator;
mod image;
mod isotropic;
mod kernel;
mod linear_basis;
mod matrix;
mod rotation;
mod sparse;
mod synthesis;
mod transform;
mod triple;
mod vector;

#[cfg(feature = "verify")]
pub(crate) use angular::apply_angular;
pub use argument::FieldArgument;
pub use codomain::{in_index_set, Codomain};
pub use convolution::{
    convolve_angular, kernel_coefficients, project_to_convolution, rotation_average,
    KernelCoefficients,
};
pub use cube::project_cube_map;
pub use evaluator::PshEvaluator;
pub use image::project_image;
pub use isotropic::{
    horizon_free_grid, isotropic_lmax, isotropic_pair_count, isotropic_pairs, isotropy_defect,
    project_isotropic_with, table_grid, IsotropicMatrix, IsotropicProjection, TABLE_GRID_MIN,
};
pub use kernel::{ConvolutionKernel, KernelValue};
pub use linear_basis::{off_block_fraction, rotation_coefficient_matrix, LinearBasis};
pub(crate) use matrix::{band_limit_residual, project_operator_normed};
pub use matrix::{project_operator, project_operator_with, MatrixKernel, PshMatrix, SpinBlock22};
pub use rotation::PshRotation;
pub use sparse::{SparsePshMatrix, Sparsity};
pub use synthesis::reconstruct_image;
pub use transform::PshTransform;
pub use triple::{spin2_gaunt, visibility_transfer, visibility_transfer_quadrature, TripleTable};
pub use vector::PshVector;
