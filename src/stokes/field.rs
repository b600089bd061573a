//! Stokes components between frame fields (PSH Sec. 5.1 with PSH (14)).

use super::components::StokesComponents;
use super::vector::StokesVector;
use crate::error::Result;
use crate::geometry::frame::FrameField;

/// Components measured at the direction `w` in the frame field `from` re-expressed in the
/// frame field `to`: `[[s]_{from(w)}]^{to(w)} = C(vartheta) s` with
/// `to(w) = R_z(vartheta) from(w)` (PSH (14), (15), (16)). Errors: a bad direction.
pub fn convert_between_fields<A, B>(
    s: StokesComponents,
    w: [f64; 3],
    from: &A,
    to: &B,
) -> Result<StokesComponents>
where
    A: FrameField + ?Sized,
    B: FrameField + ?Sized,
{
    StokesVector::from_field(s, w, from)?.components_in_field(to)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::frame::{CubeMapFrameField, ThetaPhiFrameField};

    /// Looking along +y (Front face centre), the theta-phi frame is `x = -z`, `y = -x`
    /// and the Front camera's is `x = +x`, `y = -z`. Light polarized along world `z`
    /// (vertical) is `s1 = +1` in theta-phi (along its x) and `s1 = -1` in the cube frame
    /// (along its y).
    #[test]
    fn vertical_polarization_in_two_fields() {
        let w = [0.0, 1.0, 0.0];
        let s = StokesComponents::new([1.0, 1.0, 0.0, 0.0]).unwrap();
        let t =
            convert_between_fields(s, w, &ThetaPhiFrameField::new(), &CubeMapFrameField).unwrap();
        assert!(t.approx_eq(
            &StokesComponents::new([1.0, -1.0, 0.0, 0.0]).unwrap(),
            1e-15
        ));
        // Diagonal: theta-phi (x + y)/sqrt 2 = (-z - x)/sqrt 2 = -(x_c - y_c)/sqrt 2 in
        // the cube frame: the -45 degree line, s2 = -1.
        let d = StokesComponents::new([1.0, 0.0, 1.0, 0.0]).unwrap();
        let e =
            convert_between_fields(d, w, &ThetaPhiFrameField::new(), &CubeMapFrameField).unwrap();
        assert!(e.approx_eq(
            &StokesComponents::new([1.0, 0.0, -1.0, 0.0]).unwrap(),
            1e-15
        ));
        assert!(
            convert_between_fields(s, [0.0, 0.0, 0.0], &CubeMapFrameField, &CubeMapFrameField)
                .is_err()
        );
    }
}
