//! The recursions as kernels, for callers that stream what the rest of the layer returns
//! whole: the Legendre columns of one polar angle order by order ([`Legendre`], in `f64`;
//! [`for_each_column_accurate`], in double-double), the small d of one `beta` degree by
//! degree ([`SmallDRecursion`], [`for_each_small_d`] with [`SmallDHalf`]) or one `(m, m')`
//! at a time ([`small_d_column`]), and a row of 3j symbols into a caller's buffer
//! ([`wigner_3j_row_into`]). The user types of the layer (`ShEvaluator`, `ShTransform`,
//! `WignerD`, ...) are built on them; derivations in `proofs/legendre-recursion.md`,
//! `proofs/wigner-recursion.md`, `proofs/wigner3j-recursion.md`.

pub use super::coupling::wigner3j::wigner_3j_row_into;
pub use super::recursion::legendre::{for_each_column_accurate, tri_index, Legendre, Polar};
pub use super::rotation::small_d::{for_each_small_d, small_d_column, SmallDHalf, SmallDRecursion};
