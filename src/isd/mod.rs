//! Isotropic spherical decomposition (Soler, Bagher, Nowrouzezahrai 2015, "ISD").
//!
//! A kernel `k` of band limit `L` is written as a weighted sum of rotated copies of
//! isotropic mother functions `phi_l`, one per band: `k(w) = sum_lm lambda_l^m
//! phi_l((R_l^m)^-1 w)` (ISD (5), (12)), where `R_l^m z = z_l^m` (only the axis matters:
//! `phi_l` is symmetric about `z`). The weights solve `c = M Lambda` (ISD (10), (17))
//! with `c` the kernel's real SH coefficients. Filtering a signal `f` with the kernel
//! turned by any rotation `R`, `fhat(R) = int k(R^-1 w) f(w) dw` (ISD (1)), is then a
//! weighted sum of values of the pre-convolved signals `fhat_l = f (x) phi_l` at the
//! directions `R z_l^m` (ISD (6)): no SH rotation.
//!
//! - [`DirectionSet`]: the axes `z_l^m` (Fibonacci, Halton; per band or shared, "lobe
//!   sharing");
//! - [`Profile`]: the mother functions (RZH `y_l^0`, and ISD Sec. 7.2's Legendre,
//!   Gaussian, Phong and Gauss-Legendre profiles) and their ZH coefficients `beta_ll'`
//!   (ISD (16));
//! - [`Isd`], [`transfer_matrix`], [`condition_number`]: the transfer matrix `M`
//!   (ISD (17)), its conditioning, and the weights `Lambda = M^-1 c` (ISD (11));
//! - [`PreConvolved`], [`spherical_light`]: pre-convolved signals (ISD (13), (14)),
//!   filtering (ISD (6)) and spherical lights (ISD (33), (34)).
//!
//! Conventions: real SH of PSH (12) (`docs/conventions.md`), flat index `l*l + l + m`;
//! `pi_l = sqrt(4 pi / (2l + 1))` (ISD Fig. 2). Derivations not printed in the paper:
//! `proofs/isd.md`.

use crate::error::Result;

pub(crate) mod decomposition;
pub(crate) mod directions;
pub(crate) mod filter;
pub(crate) mod profiles;

pub use decomposition::{condition_number, transfer_matrix, Isd, MAX_CONDITION};
pub use directions::{DirectionSet, Pattern, Sharing};
pub use filter::{sh_rotate_dot, spherical_light, PreConvolved};
pub use profiles::Profile;

/// Largest band limit: `M` is dense, `(L + 1)^2` square (ISD uses `L <= 31`, Table I).
pub const MAX_LMAX: usize = 48;

/// Checks `lmax <= MAX_LMAX`.
pub fn check_isd_lmax(lmax: usize) -> Result<()> {
    crate::sh::check_degree_limit(
        "ISD lmax",
        lmax,
        MAX_LMAX,
        "the ISD transfer matrix is dense; the largest supported L",
    )
}

/// `pi_l = sqrt(4 pi / (2l + 1))`, the convolution factor of ISD (9), (13).
#[inline]
pub fn pi_l(l: usize) -> f64 {
    (4.0 * std::f64::consts::PI / (2 * l + 1) as f64).sqrt()
}
