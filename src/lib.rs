//! psh: spherical harmonics for polarized light transport (Yi et al. 2024, "PSH"), with
//! the scalar core it stands on, verified against exact identities, quadrature
//! equivalences and high-precision oracles. See `README.md` and `docs/`.

// Numerical kernels index several arrays with one loop variable (bands, lanes, rings);
// iterator chains would obscure the equations they implement.
#![allow(clippy::needless_range_loop)]

/// The Rust examples of `README.md`, run as doctests.
#[cfg(all(doctest, feature = "io"))]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

#[cfg(feature = "apps")]
pub mod apps;
pub mod error;
pub use error::{Error, Result};
#[cfg(feature = "exact")]
pub mod exact;
pub mod geometry;
#[cfg(feature = "io")]
pub mod io;
pub mod isd;
pub mod lights;
pub mod map;
pub mod optics;
pub mod polarized;
#[cfg(feature = "render")]
pub mod pprt;
pub mod progress;
pub mod random;
pub mod sh;
pub mod stokes;
pub mod swsh;
#[cfg(any(test, feature = "verify"))]
pub mod testing;
#[cfg(feature = "verify")]
pub mod verify;
