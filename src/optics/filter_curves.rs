//! The polarizing factor of every material of PF Table 1 sampled against the angle of
//! incidence (PF Fig. 3), with its specular-colour approximation and the approximation's
//! error (PF Fig. 5): the curves behind `psh filter-report` (`apps::filter_report`
//! tabulates them) and the checks `filter.conductor_error_*`.

use super::filter::{psi, psi_approx, Incidence};
use super::material::{Channel, Material};
use crate::error::Result;

/// The angle step of the curves, in degrees.
pub const STEP_DEGREES: f64 = 0.1;

/// The number of samples: `0, 0.1, ..., 89.9` degrees.
pub const SAMPLES: usize = 900;

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
    /// The material (a row of PF Table 1).
    pub material: Material,
    /// The colour channel, whose `n`, `k` and `R_0` are used.
    pub channel: Channel,
    /// The `R_0` given to `psi~`.
    pub r0: f64,
    /// `psi` (PF (10)) from the table's `n`, `k`, one per sample.
    pub psi: Vec<f64>,
    /// `psi~` (PF Sec. 3.6; `psi~_C` for conductors, `psi_D` for dielectrics) from
    /// [`r0`](Self::r0), one per sample.
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
