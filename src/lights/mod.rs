//! Lights with analytic SH coefficients, spatial gradients and Hessians (SHH).
//!
//! - [`spherical`]: spherical lights of uniform radiance, SHH (2)-(8), (15), (20);
//! - [`grid`]: the error metric SHH (21)-(22), Hermite interpolation, the occupancy octree
//!   and adaptive grids (SHH Sec. 5, Fig. 2);
//! - [`scene`]: a procedural many-light scene for the demo and the checks.

pub mod grid;
pub mod polygon;
pub mod scene;
pub mod spherical;
