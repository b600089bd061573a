//! The library's public surface, as a user calls it: properties of the mathematics
//! (proptest), the renderer, the planner, the reference, the ISD, polygonal lights, the
//! Mitsuba export, the checks of `psh verify`, and the shared data (skipped without it).
//! One test binary (`cargo test --release --test library`); each file a module.

mod convolution_properties;
mod filter_properties;
mod gaunt_oracle;
mod isd;
mod mitsuba_export;
mod optics_properties;
mod plan;
mod polarized_properties;
mod polygon;
mod pprt;
mod properties;
mod real_data;
mod reference;
mod stokes_properties;
mod verify;
