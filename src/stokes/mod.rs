//! Stokes vectors and Mueller transforms, numeric and geometric (PSH Sec. 4.2, 4.2.1,
//! 4.2.2, Table 1-2).
//!
//! The paper's discipline, kept by the types:
//!
//! | PSH | numeric | geometric |
//! |---|---|---|
//! | Stokes | [`StokesComponents`] `s` | [`StokesVector`] `[s]_F` (PSH (15)) |
//! | spin-2 Stokes | `Vector2` / `Complex64` `s1 + i s2` | [`Spin2StokesVector`] `[s1 + i s2]_F` |
//! | Mueller | [`MuellerMatrix`] `M` | [`MuellerTransform`] `[M]_{F_i -> F_o}` (PSH (22)) |
//!
//! - Building a geometric quantity names its frame: [`StokesVector::new`]`(s, frame)` is
//!   `[s]_F`, [`MuellerTransform::new`]`(m, f_in, f_out)` is `[M]_{F_i -> F_o}`.
//! - Reading it names the frame too: [`StokesVector::components_in`]`(&frame)` is
//!   `[s]^F` (PSH (16)), [`MuellerTransform::matrix_in`]`(&f_in, &f_out)` is
//!   `[M]^{F_i -> F_o}` (PSH (22)); both convert by the rotator [`rotator`] `C(vartheta)`
//!   of PSH (14) and fail with [`crate::Error::DifferentRays`] for a frame of another ray.
//! - Sum and inner product (PSH (17), (18)) are fallible methods
//!   ([`StokesVector::try_add`], [`StokesVector::inner`]) that convert to a common frame;
//!   there is no `Add` between geometric vectors and no `Deref` to the numeric types.
//! - Rotation: [`StokesVector::rotate`] is `R_S` (PSH (19)), [`MuellerTransform::rotate`]
//!   is `R_M` (PSH (59)).
//!
//! Conventions (derivations in `proofs/stokes-frames.md`):
//! - In a frame `[x, y, z]`, `z` the ray direction: `s1 > 0` for polarization along `x`,
//!   `s2 > 0` along `(x + y)/sqrt 2`. For `F' = R_z(vartheta) F` (the frame turned by
//!   `vartheta` counterclockwise about `z`), `s1' + i s2' = e^{-2 i vartheta}(s1 + i s2)`:
//!   PSH (14) exactly as printed, and the same as Mitsuba 3's `rotate_stokes_basis`.
//! - `s3` is frame-independent under rotations about the ray; its handedness convention
//!   is not fixed here (it matters only for retarders and reflections, `optics`).
//! - Same-ray tolerance: [`crate::geometry::frame::RAY_TOLERANCE`].

mod complex_pair;
mod components;
mod field;
mod frame_change;
mod mueller;
mod mueller_field;
mod valid_range;
mod vector;

pub use complex_pair::{complex_pair, from_complex_pair};
pub use components::StokesComponents;
pub use field::convert_between_fields;
pub use frame_change::FrameChange;
pub use mueller::{rotator, MuellerMatrix, MuellerTransform};
pub use mueller_field::MuellerField;
pub use vector::{Spin2StokesVector, StokesVector};
