//! Lights with analytic SH coefficients, spatial gradients and Hessians (SHH).
//!
//! - [`spherical`]: spherical lights of uniform radiance, SHH (2)-(8), (15), (20);
//! - [`grid`]: the error metric SHH (21)-(22), Hermite interpolation, the occupancy octree
//!   and adaptive grids (SHH Sec. 5, Fig. 2);
//! - [`source`]: the light field at a shading point and the lights a grid can hold.

pub mod grid;
pub mod polygon;
pub mod source;
pub mod spherical;

pub use grid::{Interpolation, LightGrid, Metric, Refinement};
pub use polygon::{PolygonalLight, PolygonalLights};
pub use source::{LightField, LightSource, Order};
pub use spherical::{SphericalLight, SphericalLights};
