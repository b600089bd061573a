//! The polarizing factor of every material of PF Table 1 against the angle of incidence
//! (PF Fig. 3), its specular-colour approximation and the approximation's error
//! (PF Fig. 5), and the largest error per material and channel: the numbers behind
//! `psh filter-report` and the checks `filter.conductor_error_*`.

use super::filter::{psi, psi_approx, Incidence};
use super::material::{Channel, Material};
use crate::error::Result;

/// The angle step of the curves, in degrees.
pub const STEP_DEGREES: f64 = 0.1;

/// The number of samples: `0, 0.1, ..., 89.9` degrees.
pub const SAMPLES: usize = 900;

/// The angles (degrees) at which the largest errors are reported.
pub const ERROR_LIMITS_DEGREES: [f64; 2] = [60.0, 89.0];

/// Which specular colour feeds the approximation `psi~`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpecularSource {
    /// `R_0` from the table's `n`, `k` by PF (3): for dielectrics `psi~ = psi` exactly, so
    /// the error is that of the conductor approximation alone.
    FromIor,
    /// `R_0` as printed in Table 1 (two decimals), what a renderer would store.
    Printed,
}

impl SpecularSource {
    /// The `R_0` of `material` in `channel`.
    pub fn r0(self, material: Material, channel: Channel) -> f64 {
        match self {
            SpecularSource::FromIor => material.ior(channel).normal_reflectance(),
            SpecularSource::Printed => material.specular_color()[channel.index()],
        }
    }
}

/// The metalness of a table material for the switch of [`psi_approx`]: 1 for the
/// conductors (`k > 0`), 0 for the dielectrics.
pub fn metalness(material: Material) -> f64 {
    if material.is_conductor() {
        1.0
    } else {
        0.0
    }
}

/// The angle of sample `i` in degrees (`i * 0.1`).
pub fn sample_degrees(i: usize) -> f64 {
    i as f64 * STEP_DEGREES
}

/// One material and channel: `psi` (PF (10)) and `psi~` (PF Sec. 3.6) at the angles
/// [`sample_degrees`]`(0..SAMPLES)`.
#[derive(Clone, Debug, PartialEq)]
pub struct PsiCurve {
    pub material: Material,
    pub channel: Channel,
    /// The `R_0` given to `psi~`.
    pub r0: f64,
    pub psi: Vec<f64>,
    pub psi_approx: Vec<f64>,
}

impl PsiCurve {
    /// The curve of `material` in `channel`, `psi~` fed by `source`.
    pub fn new(material: Material, channel: Channel, source: SpecularSource) -> Result<Self> {
        let ior = material.ior(channel);
        let r0 = source.r0(material, channel);
        let mut psi_exact = Vec::with_capacity(SAMPLES);
        let mut approx = Vec::with_capacity(SAMPLES);
        for i in 0..SAMPLES {
            let t = Incidence::from_degrees(sample_degrees(i))?;
            psi_exact.push(psi(&ior, t));
            approx.push(psi_approx(r0, t, metalness(material))?);
        }
        Ok(Self {
            material,
            channel,
            r0,
            psi: psi_exact,
            psi_approx: approx,
        })
    }

    /// The signed error `psi~ - psi` (PF Fig. 5) at sample `i`.
    pub fn error(&self, i: usize) -> f64 {
        self.psi_approx[i] - self.psi[i]
    }

    /// The largest `|psi~ - psi|` over the samples at angles `<= limit_degrees`, with the
    /// signed error and the angle where it occurs.
    pub fn max_error(&self, limit_degrees: f64) -> MaxError {
        let mut worst = MaxError {
            abs: 0.0,
            signed: 0.0,
            at_degrees: 0.0,
        };
        for i in (0..SAMPLES).take_while(|&i| sample_degrees(i) <= limit_degrees + 1e-9) {
            let e = self.error(i);
            if e.abs() > worst.abs {
                worst = MaxError {
                    abs: e.abs(),
                    signed: e,
                    at_degrees: sample_degrees(i),
                };
            }
        }
        worst
    }
}

/// The largest approximation error over a range of angles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaxError {
    /// `max |psi~ - psi|`.
    pub abs: f64,
    /// `psi~ - psi` where it is largest.
    pub signed: f64,
    /// The angle (degrees) where it is largest.
    pub at_degrees: f64,
}

/// The curves of every material and channel of PF Table 1, in the table's order.
pub fn psi_curves(source: SpecularSource) -> Result<Vec<PsiCurve>> {
    Material::ALL
        .iter()
        .flat_map(|&m| Channel::ALL.map(|c| (m, c)))
        .map(|(m, c)| PsiCurve::new(m, c, source))
        .collect()
}

/// The largest errors of one material and channel, up to each of
/// [`ERROR_LIMITS_DEGREES`], with `psi~` fed by both [`SpecularSource`]s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorSummary {
    pub material: Material,
    pub channel: Channel,
    /// `R_0` by PF (3) from the table's `n`, `k`.
    pub r0_ior: f64,
    /// `R_0` as printed.
    pub r0_printed: f64,
    /// With `R_0` from PF (3), up to 60 and 89 degrees.
    pub from_ior: [MaxError; 2],
    /// With the printed `R_0`, up to 60 and 89 degrees.
    pub printed: [MaxError; 2],
}

/// The [`ErrorSummary`] of every material and channel, in the table's order.
pub fn error_summary() -> Result<Vec<ErrorSummary>> {
    let ior = psi_curves(SpecularSource::FromIor)?;
    let printed = psi_curves(SpecularSource::Printed)?;
    Ok(ior
        .iter()
        .zip(&printed)
        .map(|(a, b)| ErrorSummary {
            material: a.material,
            channel: a.channel,
            r0_ior: a.r0,
            r0_printed: b.r0,
            from_ior: ERROR_LIMITS_DEGREES.map(|l| a.max_error(l)),
            printed: ERROR_LIMITS_DEGREES.map(|l| b.max_error(l)),
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dielectrics_are_exact_and_conductors_are_not() {
        for curve in psi_curves(SpecularSource::FromIor).unwrap() {
            let e = curve.max_error(89.0).abs;
            if curve.material.is_conductor() {
                assert!(e > 1e-3, "{:?}", curve.material);
            } else {
                assert!(e < 1e-13, "{:?} {e}", curve.material);
            }
            assert!(curve.max_error(60.0).abs <= e);
        }
        assert!((sample_degrees(SAMPLES - 1) - 89.9).abs() < 1e-12);
    }
}
