//! A directional light: a near-delta source at infinity (the sky's sun with
//! [`super::Sun::Directional`]), reflected exactly by `src/pprt/direct.rs`.

use crate::error::{Error, Result};

/// An unpolarized directional light: the unit direction towards it and its irradiance
/// per channel (normal to the direction).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionalLight {
    direction: [f64; 3],
    irradiance: [f64; 3],
}

impl DirectionalLight {
    /// Errors: `direction` not a unit vector, an irradiance negative or not finite.
    pub fn new(direction: [f64; 3], irradiance: [f64; 3]) -> Result<Self> {
        crate::geometry::check_direction(direction)?;
        if let Some(e) = irradiance.iter().find(|e| !(e.is_finite() && **e >= 0.0)) {
            return Err(Error::invalid(
                "light irradiance",
                e.to_string(),
                "finite and non-negative",
            ));
        }
        Ok(Self {
            direction,
            irradiance,
        })
    }

    /// The unit direction towards the light.
    pub fn direction(&self) -> [f64; 3] {
        self.direction
    }

    /// The irradiance per channel, normal to the direction.
    pub fn irradiance(&self) -> [f64; 3] {
        self.irradiance
    }
}
