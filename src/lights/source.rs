//! What an adaptive light grid holds (SHH Sec. 5): the light field at a shading point
//! (SH coefficients, their gradients and Hessians) and the lights that produce it.

use crate::error::Result;

/// The light field at one shading point: `coefficients[l*l + l + m] = L_lm(x)`, and when
/// requested its gradients and packed Hessians (order [`crate::sh::evaluation::solid::HESSIAN_ENTRIES`]) in `x`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightField {
    /// `L_lm(x)` in flat order `l*l + l + m` (SHH (2)).
    pub coefficients: Vec<f64>,
    /// `grad_x L_lm(x)` per coefficient (SHH (6)); empty for [`Order::Values`].
    pub gradients: Vec<[f64; 3]>,
    /// Hessians of `L_lm(x)` in `x` per coefficient (SHH (15)), packed as
    /// [`crate::sh::HESSIAN_ENTRIES`]; empty unless [`Order::Hessians`] and derived.
    pub hessians: Vec<[f64; 6]>,
}

/// What to compute at a shading point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Order {
    /// Coefficients only (SHH (2)).
    Values,
    /// Coefficients and gradients (SHH (6)).
    Gradients,
    /// Coefficients, gradients and Hessians (SHH (15)).
    Hessians,
}

/// Lights whose summed field (SH coefficients with gradients, and Hessians where
/// derived) a grid can hold: spherical lights (SHH) and polygonal lights (SHG).
pub trait LightSource {
    /// The band limit.
    fn lmax(&self) -> usize;
    /// The summed light field at `x`.
    fn field(&self, x: [f64; 3], order: Order) -> Result<LightField>;
}
