//! A pixel grid or a frame field seen through a rotation `q`: texel `i` at `q w_i`, and
//! at `u` the frame `q F(q^-1 u)` (PSH Table 2).
//!
//! Evaluating a field `f` on `Rotated(grid, q)` with frames `Rotated(frames, q)` gives,
//! texel by texel, the components of the rotated field `R_F[f](w) = R_S[f(R^-1 w)]`
//! (PSH (25)) at `w_i` in `F(w_i)`, for `R = q^-1`: the rotation in the angular domain that
//! PSH Fig. 11 compares with the rotation of coefficients.

use super::frame::{Frame, FrameField};
use super::image_grid::PixelGrid;
use crate::error::Result;
use nalgebra::{Rotation3, Vector3};

/// `inner` seen through the rotation `q`.
#[derive(Clone, Debug)]
pub struct Rotated<T> {
    /// The grid or frame field.
    pub inner: T,
    /// The rotation.
    pub q: Rotation3<f64>,
}

impl<T> Rotated<T> {
    /// `inner` seen through `q`.
    pub fn new(inner: T, q: Rotation3<f64>) -> Self {
        Self { inner, q }
    }
}

fn apply(q: &Rotation3<f64>, w: [f64; 3]) -> [f64; 3] {
    let v = q * Vector3::from(w);
    [v.x, v.y, v.z]
}

impl<G: PixelGrid> PixelGrid for Rotated<G> {
    fn len(&self) -> usize {
        self.inner.len()
    }

    fn direction(&self, i: usize) -> [f64; 3] {
        apply(&self.q, self.inner.direction(i))
    }

    fn solid_angle(&self, i: usize) -> f64 {
        self.inner.solid_angle(i)
    }
}

impl<F: FrameField> FrameField for Rotated<F> {
    fn frame(&self, u: [f64; 3]) -> Result<Frame> {
        crate::geometry::check_direction(u)?;
        self.inner
            .frame(apply(&self.q.inverse(), u))?
            .rotated(&self.q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::frame::ThetaPhiFrameField;
    use crate::geometry::image_grid::Equirect;

    #[test]
    fn rotated_grid_and_frames_agree() {
        let q = Rotation3::from_scaled_axis(Vector3::new(0.4, -1.2, 0.3));
        let g = Rotated::new(Equirect::new(4, 8).unwrap(), q);
        let f = Rotated::new(ThetaPhiFrameField::new(), q);
        for i in 0..g.len() {
            let u = g.direction(i);
            let frame = f.frame(u).unwrap();
            // The frame belongs to the rotated texel's ray and is q F(w_i).
            let w = g.inner.direction(i);
            let want = ThetaPhiFrameField::new()
                .frame(w)
                .unwrap()
                .rotated(&q)
                .unwrap();
            assert!(frame.approx_eq(&want, 1e-14));
            assert!((Vector3::from(u) - frame.z()).norm() < 1e-15);
        }
        assert!(f.frame([1.0, 1.0, 0.0]).is_err());
    }
}
