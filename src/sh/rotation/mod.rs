//! Wigner small d and D matrices: the coefficient matrices of rotations.

pub(crate) mod small_d;
pub(crate) mod wigner_d;
