//! Lights with analytic SH coefficients, spatial gradients and Hessians (SHH).
//!
//! - [`spherical`]: spherical lights of uniform radiance, SHH (2)-(8), (15), (20).

pub mod spherical;
