//! The depolarizing Lambertian diffuse pBRDF.

use super::microfacet::{sp_frames_unit, unit_pair};
use crate::error::{Error, Result};
use crate::stokes::{MuellerField, MuellerMatrix, MuellerTransform};
use nalgebra::{Matrix4, Vector3};

/// An ideal depolarizing diffuse reflector (a cosine-weighted pBRDF, PSH (38)):
/// `f = (albedo / pi) diag(1, 0, 0, 0)` (Lambert's law with the depolarizer of
/// Mitsuba 3's `mueller::depolarizer`; PF assumption A2), so
/// `P(w_i, w_o) = (albedo / pi) cos theta_i diag(1, 0, 0, 0)` for `w_i`, `w_o` in the upper
/// hemisphere, zero otherwise. The matrix is the same in every pair of frames (the
/// rotators of PSH (49) leave the `(0, 0)` entry alone and the others are zero).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lambertian {
    albedo: f64,
}

impl Lambertian {
    /// A Lambertian reflector with `albedo` in `[0, 1]`. Error
    /// ([`Error::InvalidArgument`] naming the value): NaN or outside `[0, 1]`.
    pub fn new(albedo: f64) -> Result<Self> {
        if !(0.0..=1.0).contains(&albedo) {
            return Err(Error::invalid(
                "diffuse albedo",
                format!("{albedo}"),
                "must be in [0, 1]".to_string(),
            ));
        }
        Ok(Self { albedo })
    }

    /// The albedo.
    pub fn albedo(&self) -> f64 {
        self.albedo
    }

    /// The numeric matrix for validated unit directions (any frames).
    pub(crate) fn matrix_unit(&self, wi: &Vector3<f64>, wo: &Vector3<f64>) -> Matrix4<f64> {
        let mut m = Matrix4::zeros();
        if wi[2] > 0.0 && wo[2] >= 0.0 {
            m[(0, 0)] = self.albedo * std::f64::consts::FRAC_1_PI * wi[2];
        }
        m
    }
}

impl MuellerField for Lambertian {
    /// `[P(w_i, w_o)]_{F_i -> F_o}`, in the frames of [`super::sp_frames`] (any would do).
    /// Errors: a non-unit or non-finite direction.
    fn transform(&self, wi: [f64; 3], wo: [f64; 3]) -> Result<MuellerTransform> {
        let (wi, wo) = unit_pair(wi, wo)?;
        let (fi, fo) = sp_frames_unit(&wi, &wo)?;
        let m = MuellerMatrix::new(self.matrix_unit(&wi, &wo))?;
        Ok(MuellerTransform::new(m, fi, fo))
    }
}
