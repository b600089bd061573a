//! Numeric Stokes component vectors `s = [s0, s1, s2, s3]` (PSH Sec. 4.2, Table 1).
//!
//! A [`StokesComponents`] is a plain numeric 4-vector: it means nothing without a frame
//! (PSH Sec. 4.2.1). Numeric arithmetic on it (sum, scaling, dot product) is the
//! arithmetic of components measured in one and the same frame; to combine Stokes vectors
//! of possibly different frames use the geometric [`super::StokesVector`].

use crate::error::{finite, Result};
use nalgebra::{Vector2, Vector4};
use std::ops::{Add, Mul, Neg, Sub};

/// Stokes components `[s0, s1, s2, s3]` in some (unnamed) frame `[x, y, z]`: total
/// intensity; linear polarization along `x` minus along `y`; along `(x + y)/sqrt 2` minus
/// along `(x - y)/sqrt 2`; circular (PSH Sec. 4.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StokesComponents {
    s: Vector4<f64>,
}

impl StokesComponents {
    /// Components `[s0, s1, s2, s3]`. Error: a non-finite component.
    pub fn new(s: [f64; 4]) -> Result<Self> {
        Self::from_vector(Vector4::from(s))
    }

    /// Components from an nalgebra vector. Error: a non-finite component.
    pub fn from_vector(s: Vector4<f64>) -> Result<Self> {
        for &c in s.iter() {
            finite("Stokes component", c)?;
        }
        Ok(Self { s })
    }

    /// Internal constructor for values already known to be finite (or produced by
    /// arithmetic on finite values).
    pub(crate) fn from_vector_unchecked(s: Vector4<f64>) -> Self {
        Self { s }
    }

    /// Unpolarized light of intensity `s0`: `[s0, 0, 0, 0]`.
    pub fn unpolarized(s0: f64) -> Result<Self> {
        Self::new([s0, 0.0, 0.0, 0.0])
    }

    /// All zero.
    pub fn zero() -> Self {
        Self {
            s: Vector4::zeros(),
        }
    }

    /// The components as an array.
    pub fn to_array(&self) -> [f64; 4] {
        [self.s[0], self.s[1], self.s[2], self.s[3]]
    }

    /// The components as an nalgebra vector.
    pub fn vector(&self) -> Vector4<f64> {
        self.s
    }

    /// `s0`, the total intensity.
    pub fn s0(&self) -> f64 {
        self.s[0]
    }

    /// `s1`.
    pub fn s1(&self) -> f64 {
        self.s[1]
    }

    /// `s2`.
    pub fn s2(&self) -> f64 {
        self.s[2]
    }

    /// `s3`.
    pub fn s3(&self) -> f64 {
        self.s[3]
    }

    /// The spin-2 (linear) part `[s1, s2]`.
    pub fn linear(&self) -> Vector2<f64> {
        Vector2::new(self.s[1], self.s[2])
    }

    /// The numeric dot product `s . t` (PSH (18) once both are in the same frame).
    pub fn dot(&self, other: &StokesComponents) -> f64 {
        self.s.dot(&other.s)
    }

    /// Degree of polarization `sqrt(s1^2 + s2^2 + s3^2) / s0`; `None` unless `s0 > 0`.
    pub fn degree_of_polarization(&self) -> Option<f64> {
        (self.s[0] > 0.0).then(|| {
            let p = self.s[1].hypot(self.s[2]).hypot(self.s[3]);
            p / self.s[0]
        })
    }

    /// Degree of linear polarization `sqrt(s1^2 + s2^2) / s0`; `None` unless `s0 > 0`.
    /// Frame-independent (PSH (14) rotates `(s1, s2)` by `-2 vartheta`).
    pub fn degree_of_linear_polarization(&self) -> Option<f64> {
        (self.s[0] > 0.0).then(|| self.s[1].hypot(self.s[2]) / self.s[0])
    }

    /// Angle of linear polarization `chi = atan2(s2, s1) / 2` in `(-pi/2, pi/2]`, measured
    /// from the frame's `x` towards its `y`: the polarization direction is
    /// `cos(chi) x + sin(chi) y` (up to sign). `None` when `s1 = s2 = 0`. Depends on the
    /// frame: use [`super::StokesVector::linear_polarization_direction`] for the
    /// geometric direction.
    pub fn angle_of_linear_polarization(&self) -> Option<f64> {
        (self.s[1] != 0.0 || self.s[2] != 0.0).then(|| 0.5 * self.s[2].atan2(self.s[1]))
    }

    /// Whether every component agrees within `tol`.
    pub fn approx_eq(&self, other: &StokesComponents, tol: f64) -> bool {
        (self.s - other.s).amax() <= tol
    }
}

impl Add for StokesComponents {
    type Output = StokesComponents;
    /// Componentwise sum: meaningful only for components of one frame.
    fn add(self, rhs: StokesComponents) -> StokesComponents {
        StokesComponents { s: self.s + rhs.s }
    }
}

impl Sub for StokesComponents {
    type Output = StokesComponents;
    fn sub(self, rhs: StokesComponents) -> StokesComponents {
        StokesComponents { s: self.s - rhs.s }
    }
}

impl Neg for StokesComponents {
    type Output = StokesComponents;
    fn neg(self) -> StokesComponents {
        StokesComponents { s: -self.s }
    }
}

impl Mul<f64> for StokesComponents {
    type Output = StokesComponents;
    fn mul(self, a: f64) -> StokesComponents {
        StokesComponents { s: self.s * a }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn construction_and_nan() {
        assert!(StokesComponents::new([1., 0.5, 0., 0.]).is_ok());
        assert!(StokesComponents::new([1., f64::NAN, 0., 0.]).is_err());
        assert!(StokesComponents::new([f64::INFINITY, 0., 0., 0.]).is_err());
        assert!(StokesComponents::unpolarized(f64::NAN).is_err());
    }

    #[test]
    fn degrees_and_angle() {
        let s = StokesComponents::new([2., 0., 1., 0.]).unwrap();
        assert_eq!(s.degree_of_linear_polarization(), Some(0.5));
        assert_eq!(s.degree_of_polarization(), Some(0.5));
        // s2 > 0, s1 = 0: polarized along (x + y)/sqrt 2, 45 degrees.
        assert!((s.angle_of_linear_polarization().unwrap() - PI / 4.0).abs() < 1e-15);
        let v = StokesComponents::new([1., -1., 0., 0.]).unwrap();
        assert!((v.angle_of_linear_polarization().unwrap() - PI / 2.0).abs() < 1e-15);
        let c = StokesComponents::new([1., 0., 0., 1.]).unwrap();
        assert_eq!(c.angle_of_linear_polarization(), None);
        assert_eq!(c.degree_of_polarization(), Some(1.0));
        assert_eq!(StokesComponents::zero().degree_of_polarization(), None);
    }

    #[test]
    fn arithmetic() {
        let a = StokesComponents::new([1., 2., 3., 4.]).unwrap();
        let b = StokesComponents::new([0.5, -1., 0., 2.]).unwrap();
        assert_eq!((a + b).to_array(), [1.5, 1., 3., 6.]);
        assert_eq!((a - b).to_array(), [0.5, 3., 3., 2.]);
        assert_eq!((-a * 2.0).to_array(), [-2., -4., -6., -8.]);
        assert_eq!(a.dot(&b), 0.5 - 2. + 8.);
        assert_eq!(a.linear(), Vector2::new(2., 3.));
    }
}
