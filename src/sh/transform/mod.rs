//! Exact quadrature and the transforms on it; projections of images.

pub(crate) mod grid;
pub(crate) mod pixel;
pub(crate) mod sht;
pub(crate) mod sweeps;
pub(crate) mod texel_sums;
