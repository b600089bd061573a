//! The renderer's pBRDFs with their output below the shading plane mirrored
//! (`proofs/mirrored-output.md`): a camera never sees a surface from below, so the value
//! of `P(w_i, w_o)` for `w_o` under the plane is free; zero (the model's) puts a step in
//! the outgoing field at the horizon, whose truncation rings over every visible view
//! direction (PSH (39) band-limited), while the mirror image of the output above leaves
//! `s0` and `s1` continuous there.

use crate::error::Result;
use crate::geometry::frame::Frame;
use crate::stokes::{MuellerField, MuellerMatrix, MuellerTransform};
use nalgebra::{Matrix4, Vector4};

/// `P(w_i, w_o)` for `w_o` on or above the shading plane (`z >= 0`); below it, the mirror
/// image `M P(w_i, m w_o)` of the output at `m w_o`, `m = diag(1, 1, -1)`: components
/// `diag(1, 1, -1, -1)` (a mirror keeps `s0`, `s1` and turns the handedness, `s2`, `s3`)
/// in the frame `[m a, -m b, w_o]` for the output frame `[a, b, m w_o]` above
/// (`proofs/mirrored-output.md`). Commutes with rotations about the normal, so an
/// isotropic pBRDF stays isotropic.
pub struct MirroredBelow<'a>(pub &'a dyn MuellerField);

impl MuellerField for MirroredBelow<'_> {
    /// As the wrapped field above the plane, mirrored below. Errors: the wrapped field's.
    fn transform(&self, wi: [f64; 3], wo: [f64; 3]) -> Result<MuellerTransform> {
        if wo[2].is_nan() || wo[2] >= 0.0 {
            return self.0.transform(wi, wo);
        }
        let above = self.0.transform(wi, [wo[0], wo[1], -wo[2]])?;
        let (a, b) = (above.frame_out().x(), above.frame_out().y());
        let frame = Frame::new([a.x, a.y, -a.z], [-b.x, -b.y, b.z], wo)?;
        let mirror = Matrix4::from_diagonal(&Vector4::new(1.0, 1.0, -1.0, -1.0));
        let m = MuellerMatrix::new(mirror * above.matrix().matrix())?;
        Ok(MuellerTransform::new(m, *above.frame_in(), frame))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::Lambertian;
    use crate::polarized::{project_operator, Codomain, PshVector, SpinBlock22};

    /// A Lambertian under a constant environment: the band-limited outgoing radiance at
    /// grazing view directions, with the model's zero output below the plane and mirrored.
    fn grazing_error(mirrored: bool) -> f64 {
        let lmax = 8;
        let lambert = Lambertian::new(0.5).unwrap();
        let field: &dyn MuellerField = &lambert;
        let m = if mirrored {
            project_operator(
                &MirroredBelow(field),
                lmax,
                2 * lmax + 2,
                SpinBlock22::ComplexPair,
            )
        } else {
            project_operator(field, lmax, 2 * lmax + 2, SpinBlock22::ComplexPair)
        }
        .unwrap();
        let mut data = vec![0.0; crate::sh::num_coeffs(lmax) * 4];
        data[0] = (4.0 * std::f64::consts::PI).sqrt();
        let env = PshVector::from_data(lmax, Codomain::Full, 1, data)
            .unwrap()
            .labelled(m.input());
        let out = m.apply(&env).unwrap();
        let s0 = |t: f64| {
            let w = crate::geometry::direction(t.to_radians(), 0.3);
            out.evaluate(0, w).unwrap().s0()
        };
        [70.0f64, 85.0, 89.0]
            .iter()
            .map(|&t| (s0(t) - s0(0.0)).abs() / s0(0.0))
            .fold(0.0, f64::max)
    }

    /// A Lambertian's outgoing radiance does not depend on the view direction: with the
    /// mirror its band-limited value does not either (to rounding), without it the
    /// horizon's ringing changes it by 5% and more at grazing.
    #[test]
    fn the_mirror_removes_the_horizon_ringing() {
        let (plain, mirrored) = (grazing_error(false), grazing_error(true));
        assert!(mirrored < 1e-13, "{mirrored}");
        assert!(plain > 0.05, "{plain}");
    }

    /// Above the plane the field is the model; below, a Mueller transform on the ray
    /// `w_o` whose `s0` row is the model's at the mirrored direction.
    #[test]
    fn above_unchanged_below_mirrored() {
        let lambert = Lambertian::new(0.5).unwrap();
        let wi = [0.0, 0.6, 0.8];
        let above = [0.6, 0.0, 0.8];
        let m = MirroredBelow(&lambert);
        let (x, y) = (
            m.transform(wi, above).unwrap(),
            lambert.transform(wi, above).unwrap(),
        );
        assert_eq!(x.matrix().matrix(), y.matrix().matrix());
        assert_eq!(x.frame_out().matrix(), y.frame_out().matrix());
        let below = m.transform(wi, [0.6, 0.0, -0.8]).unwrap();
        assert_eq!(below.frame_out().direction(), [0.6, 0.0, -0.8]);
        assert_eq!(below.matrix().matrix().row(0), y.matrix().matrix().row(0));
    }
}
