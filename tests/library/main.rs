//! The library's public surface, as a user calls it: the renderer, the planner, the
//! reference, the ISD, polygonal lights, the Mitsuba export, the checks of `psh verify`,
//! the viewer (`psh view`'s frames) and the shared data (skipped without it). One test
//! binary (`cargo test --release --test library`); each file a module.

mod isd;
mod measured;
mod mitsuba_export;
mod plan;
mod polygon;
mod pprt;
mod real_data;
mod reference;
mod verify;
mod view;
