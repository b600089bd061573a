//! [`FrameChange`]: the conversion PSH (14) of Stokes components between two frames of one
//! ray, computed once and applied to many (the channels of a pixel, a renderer's loop).

use crate::error::Result;
use crate::geometry::frame::Frame;
use num_complex::Complex64;

/// `[s]^F -> [s]^G` for frames `F`, `G` of one ray, `G = R_z(vartheta) F`: `s0`, `s3`
/// unchanged, `s1' + i s2' = e^{-2 i vartheta} (s1 + i s2)` (PSH (14)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameChange {
    /// `e^{-2 i vartheta}`.
    factor: Complex64,
}

impl FrameChange {
    /// From `from` to `to`. Error: the frames belong to different rays
    /// ([`crate::geometry::frame::RAY_TOLERANCE`]).
    pub fn between(from: &Frame, to: &Frame) -> Result<Self> {
        let (c, s) = from.cos_sin_to(to)?;
        Ok(Self {
            factor: Complex64::new(c * c - s * s, -2.0 * c * s),
        })
    }

    /// `s1 + i s2` in the new frame.
    pub fn spin2(&self, z: Complex64) -> Complex64 {
        self.factor * z
    }

    /// `[s0, s1, s2, s3]` in the new frame.
    pub fn components(&self, s: [f64; 4]) -> [f64; 4] {
        let z = self.spin2(Complex64::new(s[1], s[2]));
        [s[0], z.re, z.im, s[3]]
    }
}
