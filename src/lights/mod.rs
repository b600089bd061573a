//! Lights with analytic SH coefficients, spatial gradients and Hessians (SHH).
//!
//! - [`SphericalLights`]: spherical lights of uniform radiance, SHH (2)-(8), (15), (20);
//! - [`PolygonalLights`]: uniform polygonal lights, SHG (4)-(18);
//! - [`LightGrid`]: the error metric SHH (21)-(22) ([`Metric`]), Hermite interpolation,
//!   the occupancy octree and adaptive grids (SHH Sec. 5, Fig. 2);
//! - [`LightField`], [`LightSource`]: the light field at a shading point and the lights a
//!   grid can hold.

pub(crate) mod demo_scene;
pub(crate) mod grid;
pub(crate) mod polygon;
pub(crate) mod source;
pub(crate) mod spherical;

// The polygon-lights demo's per-point errors (`apps`).
#[cfg(feature = "apps")]
pub(crate) use demo_scene::grid_errors_with;
pub use demo_scene::{exact_coefficients, grid_errors, light_scene, LightScene};
pub use grid::{
    Interpolation, Lattice, LightGrid, Metric, OccupancyOctree, PointError, Refinement, MAX_LEVEL,
};
pub use polygon::{
    polygon_scene, BandLobes, PolygonScene, PolygonalLight, PolygonalLights, ZonalFactorization,
    GEOMETRY_TOLERANCE,
};
pub use source::{LightField, LightSource, Order};
pub use spherical::{cap_of, cap_zonal, half_angle, SphericalLight, SphericalLights};
