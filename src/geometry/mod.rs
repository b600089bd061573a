//! Geometry: directions, frames and pixel grids on the sphere.

pub mod image_grid;
