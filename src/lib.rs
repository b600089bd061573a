//! psh: spherical harmonics for polarized light transport, the system of *Spin-Weighted
//! Spherical Harmonics for Polarized Light Transport* (Yi et al. 2024, tag `PSH`) with the
//! scalar core it stands on, verified against exact identities, quadrature equivalences,
//! high-precision oracles and independent packages (`psh verify`, `docs/validation.md`).
//!
//! # Layers
//!
//! Bottom to top; a module uses only the ones below it (`docs/architecture.md`,
//! checked by `tests/layers.rs`):
//!
//! | module | what | feature |
//! |---|---|---|
//! | [`error`], [`random`], [`progress`] | `psh::Error`; the deterministic generator; progress reports | |
//! | [`budget`], [`names`] | the memory budget; named choices (`Window`, `Sun`, ...: [`named_enum!`]) | |
//! | [`geometry`] | directions, rotations, frames and frame fields, pixel grids | |
//! | [`sh`] | Legendre, real and complex SH, Wigner D, transforms, 3j and Gaunt, zonal and solid SH | |
//! | [`swsh`] | spin-weighted SH and spin-s transforms | |
//! | [`stokes`] | Stokes vectors and Mueller transforms with their frames | |
//! | [`optics`] | Fresnel, polarizers, the polarizing filter, pBRDF models | |
//! | [`polarized`] | PSH vectors and matrices, rotation, triple products, convolution | |
//! | [`map`] | polarized environment maps on pixel grids | |
//! | [`lights`], [`isd`] | spherical and polygonal lights (SHH, SHG); the ISD | |
//! | `pprt` | the PPRT renderer | `render` |
//! | `io` | EXR, PNG, polarsh `.npz`, CSV, OBJ, scene files | `io` |
//! | `exact` | arbitrary-precision oracles | `exact` |
//! | `apps` | reports, demos, the render job | `apps` |
//! | `testing`, `verify` | random test inputs; the checks of `psh verify` | `verify` |
//!
//! # Quickstart
//!
//! Read a polarized environment map, project it to PSH, rotate it, convolve it, apply a
//! measured pBRDF and read a Stokes vector in a frame. The files are written first so
//! that the example runs anywhere; with the shared data, read
//! `polarsh/*_s%d.exr` and a `SHMat_*_ISOBI2.npz` instead.
//!
//! ```
//! # #[cfg(all(feature = "io", feature = "render"))]
//! # fn main() -> psh::Result<()> {
//! use psh::geometry::{rotation_from_rotvec, Frame};
//! use psh::io;
//! use psh::map::{MapLayout, StokesMap};
//! use psh::optics::{Channel, Conductor, Material};
//! use psh::polarized::{kernel_coefficients, project_operator, Codomain, ConvolutionKernel};
//! use psh::polarized::{FieldArgument, IsotropicMatrix, PshRotation, SpinBlock22};
//! # let dir = std::env::temp_dir().join(format!("psh-quickstart-{}", std::process::id()));
//! # std::fs::create_dir_all(&dir).unwrap();
//! # let pattern = dir.join("sky_s%d.exr");
//! # let sky = psh::pprt::RayleighSky::new(0.5, 1.0)?.project(8)?;
//! # io::write_stokes_map(&StokesMap::reconstruct(&sky, MapLayout::from_image_size(64, 128)?)?, &pattern)?;
//! # let gold = Conductor::from_material(0.3, Material::Gold, Channel::Red)?;
//! # let measured = dir.join("gold_ISOBI2.npz");
//! # io::write_isotropic_npz(&measured, &IsotropicMatrix::from_dense(
//! #     &project_operator(&gold, 6, 6, SpinBlock22::ComplexPair)?, 1e-12)?)?;
//! // An environment map: one EXR per Stokes component, Mitsuba 3's frames (PSH (14)).
//! let map = io::read_stokes_map(&pattern)?;
//! let env = map.project(Codomain::Full, 6)?; // PSH (32), indexed towards the source
//! let r = rotation_from_rotvec([0.0, 0.0, 0.4])?;
//! let turned = PshRotation::new(&r, 6)?.rotate(&env)?; // PSH (35)-(37)
//! let k = kernel_coefficients(&ConvolutionKernel::linear_zenith(), 6)?;
//! let blurred = k.convolve(&turned)?; // PSH (69)
//! // A measured pBRDF in polarsh's ISOBI2 layout, indexed by directions of travel.
//! let pbrdf = io::read_isotropic_npz(&measured)?;
//! let incident = blurred.channel(0)?.converted(pbrdf.input());
//! let reflected = pbrdf.apply(&incident)?; // PSH (41)
//! assert_eq!(reflected.argument(), FieldArgument::Travel);
//! let w = [0.0, 0.6, 0.8];
//! let s = reflected.evaluate(0, w)?; // a StokesVector in the theta-phi frame at w
//! let c = s.components_in(&Frame::from_z(w)?)?; // its components in another frame
//! assert!((c.s0() - s.s0()).abs() < 1e-12 && s.s0().is_finite());
//! # std::fs::remove_dir_all(&dir).unwrap();
//! # Ok(())
//! # }
//! # #[cfg(not(all(feature = "io", feature = "render")))]
//! # fn main() {}
//! ```

// Numerical kernels index several arrays with one loop variable (bands, lanes, rings);
// iterator chains would obscure the equations they implement.
#![allow(clippy::needless_range_loop)]

/// The Rust examples of `README.md`, run as doctests.
#[cfg(all(doctest, feature = "io"))]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

#[cfg(feature = "apps")]
pub mod apps;
pub mod budget;
pub mod error;
pub use error::{Error, Result};
#[cfg(feature = "exact")]
pub mod exact;
#[cfg(all(feature = "apps", feature = "verify"))]
pub mod figures;
pub mod geometry;
#[cfg(feature = "io")]
pub mod io;
pub mod isd;
pub(crate) mod lanes;
pub mod lights;
pub mod map;
pub mod names;
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
