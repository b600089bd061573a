//! The ideal linear polarizer (PF (8)) and Malus's law (PF Sec. 2.3).
//!
//! A polarizer acts on one ray: its Mueller matrix is read in one frame `[x, y, z]` of
//! that ray for both input and output, and the transmission axis is given by its angle
//! `varphi` from `x` towards `y` (counterclockwise about `z` seen from the tip of `z`;
//! for `z` along the light's travel that is "looking towards the source", PF's wording).
//! With psh's Stokes convention (`s1 > 0` along `x`, `s2 > 0` along `(x + y)/sqrt 2`,
//! `proofs/stokes-frames.md`) the matrix is PF (8) as printed; it does not depend on
//! which way `z` points.

use crate::error::{finite, Result};
use crate::geometry::frame::Frame;
use crate::stokes::{MuellerMatrix, MuellerTransform};
use nalgebra::Matrix4;

/// An ideal linear polarizer whose transmission axis makes the angle `varphi` (radians)
/// with the `x` axis of the frame it is read in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearPolarizer {
    angle: f64,
}

impl LinearPolarizer {
    /// The polarizer at `varphi` radians from `x` towards `y`. Error: non-finite angle.
    pub fn new(varphi: f64) -> Result<Self> {
        Ok(Self {
            angle: finite("polarizer angle varphi", varphi)?,
        })
    }

    /// The angle `varphi` in radians.
    pub fn angle(&self) -> f64 {
        self.angle
    }

    /// PF (8): with `c = cos 2 varphi`, `s = sin 2 varphi`,
    ///
    /// ```text
    /// M = 1/2 [ 1  c   s   0 ]
    ///         [ c  c^2 cs  0 ]
    ///         [ s  cs  s^2 0 ]
    ///         [ 0  0   0   0 ]
    /// ```
    ///
    /// (after Wilkie & Weidlich 2012), i.e. the projector on the Stokes vector
    /// `(1, c, s, 0)` of light polarized along the axis, scaled by 1/2.
    pub fn mueller(&self) -> MuellerMatrix {
        // The axis is defined modulo pi: reducing first (exactly, by `rem_euclid`) keeps
        // `2 varphi` finite for any finite angle (1e308 doubled overflowed to NaN entries).
        let (s, c) = (2.0 * self.angle.rem_euclid(std::f64::consts::PI)).sin_cos();
        let m = 0.5
            * Matrix4::new(
                1.0,
                c,
                s,
                0.0, //
                c,
                c * c,
                c * s,
                0.0, //
                s,
                c * s,
                s * s,
                0.0, //
                0.0,
                0.0,
                0.0,
                0.0,
            );
        MuellerMatrix::new(m).expect("entries of a polarizer are bounded by 1")
    }

    /// The polarizer as a geometric transform on the ray of `frame`, axis at `varphi`
    /// from `frame.x()` towards `frame.y()`: `[M]_{F -> F}`.
    pub fn transform(&self, frame: Frame) -> MuellerTransform {
        MuellerTransform::new(self.mueller(), frame, frame)
    }
}

/// Malus's law (PF Sec. 2.3): the intensity `I_0 cos^2 varphi` that an ideal linear
/// polarizer passes of linearly polarized light of intensity `I_0` whose plane of
/// polarization makes the angle `varphi` with the transmission axis. Errors: `I_0`
/// negative or non-finite, `varphi` non-finite.
pub fn malus_law(intensity: f64, varphi: f64) -> Result<f64> {
    if finite("intensity I_0", intensity)? < 0.0 {
        return Err(crate::Error::invalid(
            "intensity I_0",
            format!("{intensity}"),
            "must be non-negative",
        ));
    }
    let c = finite("Malus angle varphi", varphi)?.cos();
    Ok(intensity * c * c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stokes::StokesComponents;

    #[test]
    fn malus_law_from_the_mueller_matrix() {
        // Light fully polarized at chi, polarizer at varphi: s0' = I cos^2(varphi - chi).
        for (chi, varphi) in [(0.0, 0.0), (0.3, 1.1), (-0.7, 2.0), (1.2, -0.4)] {
            let (s, c) = (2.0f64 * chi).sin_cos();
            let light = StokesComponents::new([2.0, 2.0 * c, 2.0 * s, 0.0]).unwrap();
            let out = LinearPolarizer::new(varphi)
                .unwrap()
                .mueller()
                .apply(&light);
            let want = malus_law(2.0, varphi - chi).unwrap();
            assert!((out.s0() - want).abs() < 1e-15, "{chi} {varphi}");
        }
        // Unpolarized light: half passes.
        let out = LinearPolarizer::new(0.4)
            .unwrap()
            .mueller()
            .apply(&StokesComponents::unpolarized(1.0).unwrap());
        assert!((out.s0() - 0.5).abs() < 1e-16);
    }

    #[test]
    fn ideal_polarizer_is_idempotent() {
        let m = LinearPolarizer::new(0.77).unwrap().mueller().matrix();
        assert!((m * m - m).amax() < 1e-16);
    }

    /// Any finite angle gives a projector: `2 varphi` of 1e308 overflowed to NaN entries
    /// (and panicked in `mueller`) before the reduction modulo pi.
    #[test]
    fn huge_angles_are_projectors() {
        for a in [1e308, -1e308, f64::MAX, 1e20, -3.0 * std::f64::consts::PI] {
            let m = LinearPolarizer::new(a).unwrap().mueller().matrix();
            assert!(m.iter().all(|x| x.is_finite()), "{a}");
            assert!((m * m - m).amax() < 1e-15, "{a}");
        }
    }

    #[test]
    fn bad_input_is_named() {
        let e = LinearPolarizer::new(f64::NAN).unwrap_err().to_string();
        assert!(e.contains("varphi"), "{e}");
        let e = malus_law(-1.0, 0.0).unwrap_err().to_string();
        assert!(e.contains("I_0") && e.contains("-1"), "{e}");
        assert!(malus_law(1.0, f64::INFINITY).is_err());
    }
}
