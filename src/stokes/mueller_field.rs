//! Mueller transform fields `P: S^2 x S^2 -> M_{w_i -> w_o}` (PSH (38)): (cosine-weighted)
//! pBRDFs, radiance transfer and every other linear operator on Stokes vector fields,
//! acting by `P_F[f](w_o) = int P(w_i, w_o) f(w_i) dw_i` (PSH (39)).
//!
//! Direction conventions (those of PSH Sec. 6.3 and of [`crate::map`]): the input field is
//! indexed by `w_i`, the direction towards the light's source, with Stokes frames whose
//! `z` is `w_i`; the output field by `w_o`, the direction the output light travels, with
//! frames whose `z` is `w_o`. For a pBRDF both point away from the surface.

use super::{MuellerMatrix, MuellerTransform};
use crate::error::Result;
use crate::geometry::frame::Frame;

/// A Mueller transform field (PSH (38)).
pub trait MuellerField {
    /// `P(w_i, w_o)` as a geometric Mueller transform `[M]_{F_i -> F_o}` in frames of the
    /// field's choosing (`F_i` on the ray `w_i`, `F_o` on `w_o`). Errors: directions that
    /// are not unit vectors. Values are finite for every pair of unit directions.
    fn transform(&self, wi: [f64; 3], wo: [f64; 3]) -> Result<MuellerTransform>;

    /// The numeric Mueller matrix `[P(w_i, w_o)]^{F_i -> F_o}` (PSH (22), converted by
    /// PSH (49)), with `w_i`, `w_o` the `z` axes of `fi`, `fo`.
    fn matrix_in(&self, fi: &Frame, fo: &Frame) -> Result<MuellerMatrix> {
        self.transform(fi.direction(), fo.direction())?
            .matrix_in(fi, fo)
    }
}
