//! Spherical harmonics at points: complex and real, the small-degree batch, solid harmonics with derivatives, zonal harmonics.

mod cartesian;
pub(crate) mod harmonics;
pub(crate) mod solid;
pub(crate) mod zonal;
