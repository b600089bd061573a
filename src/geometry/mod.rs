//! Geometry: directions, frames and pixel grids on the sphere.

pub mod frame;
pub mod image_grid;
pub mod rotated;
