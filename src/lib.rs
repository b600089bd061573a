//! psh: spherical harmonics for polarized light transport (Yi et al. 2024, "PSH"), with
//! the scalar core it stands on, verified against exact identities, quadrature
//! equivalences and high-precision oracles. See `README.md` and `docs/`.

// Numerical kernels index several arrays with one loop variable (bands, lanes, rings);
// iterator chains would obscure the equations they implement.
#![allow(clippy::needless_range_loop)]

/// The Rust examples of `README.md`, run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

pub mod error;
pub use error::{Error, Result};
#[cfg(feature = "exact")]
pub mod exact;
pub mod geometry;
pub mod io;
pub mod isd;
pub mod lights;
pub mod map;
pub mod optics;
pub mod polarized;
pub mod pprt;
pub mod random;
pub mod sh;
pub mod stokes;
pub mod swsh;
pub mod testing;
pub mod verify;
