//! The polarized microfacet specular pBRDF: GGX, Smith masking-shadowing (height-correlated
//! or separable), and the Fresnel Mueller matrix at the half vector in the `s`/`p` frames
//! of the microfacet.

use super::fresnel::FresnelCoefficients;
use super::ggx::{Ggx, Masking};
use super::ior::ComplexIor;
use crate::error::Result;
use crate::geometry::check_direction;
use crate::geometry::frame::Frame;
use crate::stokes::{MuellerField, MuellerMatrix, MuellerTransform};
use nalgebra::{Matrix4, Vector3};

/// Validated unit directions `w_i`, `w_o` (normalized after the check).
pub(crate) fn unit_pair(wi: [f64; 3], wo: [f64; 3]) -> Result<(Vector3<f64>, Vector3<f64>)> {
    let wi = Vector3::from(check_direction(wi)?).normalize();
    let wo = Vector3::from(check_direction(wo)?).normalize();
    Ok((wi, wo))
}

/// The `s`/`p` frames of a reflection from `w_i` (towards the source) into `w_o`
/// (towards the viewer): `s = normalize(w_i x w_o)`, the normal of the plane of incidence
/// of the microfacet `h = normalize(w_i + w_o)` (since `h x w_o` is parallel to
/// `w_i x w_o`; Mitsuba 3's `s_axis_out = H x wi_hat` is the same axis), and
///
/// ```text
/// F_i = [s, w_i x s, w_i],   F_o = [s, w_o x s, w_o].
/// ```
///
/// `F_o` is the travel frame of the reflected ray and `F_i` is `[x, -y, -z]` of the travel
/// frame `[s, d_i x s, d_i]` of the incident ray, `d_i = -w_i` (`proofs/optics.md` §3).
/// When `w_i x w_o = 0` exactly (`w_i = +-w_o`) the plane is undefined and `s` is
/// the `x` axis of [`Frame::from_z`]`(w_o)`; there the Fresnel matrix in these frames is
/// a multiple of the identity (normal incidence on the facet) or the value is zero, so
/// the choice does not matter. Errors: a non-unit or non-finite direction.
pub fn sp_frames(wi: [f64; 3], wo: [f64; 3]) -> Result<(Frame, Frame)> {
    let (wi, wo) = unit_pair(wi, wo)?;
    sp_frames_unit(&wi, &wo)
}

pub(crate) fn sp_frames_unit(wi: &Vector3<f64>, wo: &Vector3<f64>) -> Result<(Frame, Frame)> {
    // Scaled by its largest component first, so that a cross product of size 1e-300
    // (grazing directions) normalizes without underflow.
    let c = wi.cross(wo);
    let big = c.amax();
    let s = if big > 0.0 {
        (c / big).normalize()
    } else {
        Frame::from_z([wo[0], wo[1], wo[2]])?.x()
    };
    let arr = |v: &Vector3<f64>| [v[0], v[1], v[2]];
    let fi = Frame::from_z_and_x(arr(wi), arr(&s))?;
    let fo = Frame::from_z_and_x(arr(wo), arr(&s))?;
    Ok((fi, fo))
}

/// The polarized microfacet specular reflection (a cosine-weighted pBRDF, PSH (38)):
///
/// ```text
/// P(w_i, w_o) = f(w_i, w_o) cos theta_i,
/// f = F(h . w_i) D(h) G2(w_i, w_o) / (4 cos theta_i cos theta_o),   h = normalize(w_i + w_o)
/// ```
///
/// (Walter et al. 2007 (20) with the Mueller matrix `F` of the Fresnel reflection at the
/// microfacet, as Mitsuba 3's polarized `roughconductor`), with `D` GGX (Walter (33)),
/// `G2` Smith's function in the form of [`Ggx::masking`] (height-correlated by default,
/// Heitz 2014; separable as Mitsuba 3), and `F` = [`FresnelCoefficients::mueller`] in the
/// frames of [`sp_frames`]. Written as `P = F D G2/(4 c_o)` with [`Ggx::g2_over_4co`],
/// finite at grazing angles: `P = 0` at `cos theta_i = 0`, and finite at
/// `cos theta_o = 0` (`F D / (2 alpha)` height-correlated). Zero matrix when `w_i` or `w_o`
/// is below the horizon (`z < 0`), or `w_i` on it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MicrofacetSpecular {
    ggx: Ggx,
    ior: ComplexIor,
}

impl MicrofacetSpecular {
    /// The model with roughness `alpha` ([`Ggx::new`]) and relative index `ior`.
    pub fn new(alpha: f64, ior: ComplexIor) -> Result<Self> {
        Ok(Self {
            ggx: Ggx::new(alpha)?,
            ior,
        })
    }

    /// This model with the masking-shadowing form `masking`.
    pub fn with_masking(self, masking: Masking) -> Self {
        Self {
            ggx: self.ggx.with_masking(masking),
            ..self
        }
    }

    /// The microfacet distribution.
    pub fn ggx(&self) -> &Ggx {
        &self.ggx
    }

    /// The relative index of refraction.
    pub fn ior(&self) -> &ComplexIor {
        &self.ior
    }

    /// The numeric matrix in the frames of [`sp_frames`] for validated unit directions.
    pub(crate) fn matrix_unit(&self, wi: &Vector3<f64>, wo: &Vector3<f64>) -> Result<Matrix4<f64>> {
        let (ci, co) = (wi[2], wo[2]);
        if ci <= 0.0 || co < 0.0 {
            return Ok(Matrix4::zeros());
        }
        // w_i + w_o has z >= ci > 0, so h is defined and faces up; but when both are
        // grazing and w_o is within rounding of -w_i, |w_i + w_o| is rounding noise and so
        // is h: that configuration (a set of measure zero, where the value has no limit)
        // is given 0, so that the model stays a function of phi_o - phi_i to rounding.
        let v = wi + wo;
        if v.norm() < HALF_VECTOR_EPS {
            return Ok(Matrix4::zeros());
        }
        let h = (v / v.amax()).normalize();
        let cos_d = h.dot(wi).clamp(0.0, 1.0);
        let fresnel = FresnelCoefficients::new(cos_d, &self.ior)?
            .mueller()
            .matrix();
        Ok(fresnel * (self.ggx.d(&h) * self.ggx.g2_over_4co(wi, wo)))
    }
}

/// Below this `|w_i + w_o|` the half vector is not resolved in `f64`.
const HALF_VECTOR_EPS: f64 = 1e-8;

impl MuellerField for MicrofacetSpecular {
    /// `[P(w_i, w_o)]_{F_i -> F_o}` in the frames of [`sp_frames`]. Errors: a non-unit or
    /// non-finite direction.
    fn transform(&self, wi: [f64; 3], wo: [f64; 3]) -> Result<MuellerTransform> {
        let (wi, wo) = unit_pair(wi, wo)?;
        let m = self.matrix_unit(&wi, &wo)?;
        let (fi, fo) = sp_frames_unit(&wi, &wo)?;
        Ok(MuellerTransform::new(MuellerMatrix::new(m)?, fi, fo))
    }
}
