//! Two complete pBRDFs: a polarized plastic (dielectric microfacet specular plus a
//! depolarizing diffuse base) and a rough conductor.

use super::ggx::Masking;
use super::ior::ComplexIor;
use super::lambertian::Lambertian;
use super::material::{Channel, Material};
use super::microfacet::{sp_frames_unit, unit_pair, MicrofacetSpecular};
use crate::error::Result;
use crate::stokes::{MuellerField, MuellerMatrix, MuellerTransform};

/// A polarized plastic: `P = P_spec + P_diffuse`, the [`MicrofacetSpecular`] reflection
/// of a dielectric of index `n` (real) plus the depolarizing [`Lambertian`] term with
/// `albedo` (the model of Mitsuba 3's polarized `pplastic` in its simplest form, and of the
/// PF paper's assumptions A1-A2: only the specular part polarizes). The two terms are
/// added without coupling (no Fresnel transmission factors on the diffuse part), so the
/// sum can exceed energy conservation for `albedo` near 1; both terms are realizable
/// Mueller matrices and so is their sum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolarizedPlastic {
    specular: MicrofacetSpecular,
    diffuse: Lambertian,
}

impl PolarizedPlastic {
    /// Roughness `alpha` ([`super::Ggx::new`]), dielectric index `n`
    /// ([`ComplexIor::dielectric`]), diffuse `albedo` ([`Lambertian::new`]). Errors name
    /// the invalid value.
    pub fn new(alpha: f64, n: f64, albedo: f64) -> Result<Self> {
        Ok(Self {
            specular: MicrofacetSpecular::new(alpha, ComplexIor::dielectric(n)?)?,
            diffuse: Lambertian::new(albedo)?,
        })
    }

    /// This plastic with the specular term's masking-shadowing form `masking`.
    pub fn with_masking(self, masking: Masking) -> Self {
        Self {
            specular: self.specular.with_masking(masking),
            ..self
        }
    }

    /// The specular term.
    pub fn specular(&self) -> &MicrofacetSpecular {
        &self.specular
    }

    /// The diffuse term.
    pub fn diffuse(&self) -> &Lambertian {
        &self.diffuse
    }
}

impl MuellerField for PolarizedPlastic {
    /// `[P_spec + P_diffuse]_{F_i -> F_o}` in the frames of [`super::sp_frames`]. Errors:
    /// a non-unit or non-finite direction.
    fn transform(&self, wi: [f64; 3], wo: [f64; 3]) -> Result<MuellerTransform> {
        let (wi, wo) = unit_pair(wi, wo)?;
        let m = self.specular.matrix_unit(&wi, &wo)? + self.diffuse.matrix_unit(&wi, &wo);
        let (fi, fo) = sp_frames_unit(&wi, &wo)?;
        Ok(MuellerTransform::new(MuellerMatrix::new(m)?, fi, fo))
    }
}

/// A rough conductor: the [`MicrofacetSpecular`] reflection of a complex index
/// `n + i k` (Mitsuba 3's polarized `roughconductor` with GGX; Smith's masking
/// height-correlated by default, separable as Mitsuba's with [`Self::with_masking`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor {
    specular: MicrofacetSpecular,
}

impl Conductor {
    /// Roughness `alpha` ([`super::Ggx::new`]) and index `n + i k`
    /// ([`ComplexIor::new`]). Errors name the invalid value.
    pub fn new(alpha: f64, n: f64, k: f64) -> Result<Self> {
        Ok(Self {
            specular: MicrofacetSpecular::new(alpha, ComplexIor::new(n, k)?)?,
        })
    }

    /// Roughness `alpha` and a complex index already checked.
    pub fn with_ior(alpha: f64, ior: ComplexIor) -> Result<Self> {
        Ok(Self {
            specular: MicrofacetSpecular::new(alpha, ior)?,
        })
    }

    /// A conductor (or any material) of the PF table in one colour channel.
    pub fn from_material(alpha: f64, material: Material, channel: Channel) -> Result<Self> {
        Ok(Self {
            specular: MicrofacetSpecular::new(alpha, material.ior(channel))?,
        })
    }

    /// This conductor with the masking-shadowing form `masking`.
    pub fn with_masking(self, masking: Masking) -> Self {
        Self {
            specular: self.specular.with_masking(masking),
        }
    }

    /// The specular term.
    pub fn specular(&self) -> &MicrofacetSpecular {
        &self.specular
    }
}

impl MuellerField for Conductor {
    /// `[P(w_i, w_o)]_{F_i -> F_o}` in the frames of [`super::sp_frames`]. Errors: a
    /// non-unit or non-finite direction.
    fn transform(&self, wi: [f64; 3], wo: [f64; 3]) -> Result<MuellerTransform> {
        self.specular.transform(wi, wo)
    }
}
