//! Rotations of the sphere: from a rotation vector, and their ZYZ Euler angles (the
//! parametrization of Wigner D, PSH (9)).

use crate::error::{Error, Result};
use nalgebra::{Rotation3, Vector3};

/// Rotation from a rotation vector (axis times angle in radians), as an active rotation.
/// A zero vector has no axis and is rejected; use [`Rotation3::identity`] explicitly.
pub fn rotation_from_rotvec(v: [f64; 3]) -> Result<Rotation3<f64>> {
    if v.iter().any(|c| !c.is_finite()) {
        return Err(Error::InvalidRotation {
            value: format!("{v:?}"),
            reason: "rotation vector components must be finite".into(),
        });
    }
    if v == [0.0; 3] {
        return Err(Error::InvalidRotation {
            value: format!("{v:?}"),
            reason: "a zero rotation vector has no axis (pass the identity explicitly)".into(),
        });
    }
    let r = Rotation3::new(Vector3::from(v));
    if !r.matrix().iter().all(|x| x.is_finite()) {
        return Err(Error::InvalidRotation {
            value: format!("{v:?}"),
            reason: "the rotation angle (the vector's norm) is too large to represent".into(),
        });
    }
    Ok(r)
}

/// ZYZ Euler angles `(alpha, beta, gamma)` with `R = Rz(alpha) Ry(beta) Rz(gamma)`,
/// `beta` in `[0, pi]`. At `beta = 0` or `pi` only `alpha +- gamma` is defined; `gamma = 0`.
pub fn euler_zyz(r: &Rotation3<f64>) -> (f64, f64, f64) {
    let m = r.matrix();
    let s = m[(0, 2)].hypot(m[(1, 2)]);
    let beta = s.atan2(m[(2, 2)]);
    if s == 0.0 {
        let alpha = if m[(2, 2)] > 0.0 {
            m[(1, 0)].atan2(m[(0, 0)])
        } else {
            (-m[(1, 0)]).atan2(-m[(0, 0)])
        };
        return (alpha, beta, 0.0);
    }
    let alpha = m[(1, 2)].atan2(m[(0, 2)]);
    let gamma = m[(2, 1)].atan2(-m[(2, 0)]);
    (alpha, beta, gamma)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn euler_angles_reconstruct_the_rotation() {
        for v in [
            [0.3, -1.1, 0.7],
            [0.0, 0.0, 2.0],
            [0.0, 3.0, 0.0],
            [1e-9, 0.0, 0.0],
        ] {
            let r = rotation_from_rotvec(v).unwrap();
            let (a, b, g) = euler_zyz(&r);
            let back = Rotation3::from_axis_angle(&Vector3::z_axis(), a)
                * Rotation3::from_axis_angle(&Vector3::y_axis(), b)
                * Rotation3::from_axis_angle(&Vector3::z_axis(), g);
            assert!((back.matrix() - r.matrix()).abs().max() < 1e-14, "{v:?}");
        }
        let flip = Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI);
        let (a, b, g) = euler_zyz(&flip);
        let back = Rotation3::from_axis_angle(&Vector3::z_axis(), a)
            * Rotation3::from_axis_angle(&Vector3::y_axis(), b)
            * Rotation3::from_axis_angle(&Vector3::z_axis(), g);
        assert!((back.matrix() - flip.matrix()).abs().max() < 1e-14);
    }

    #[test]
    fn bad_rotations_are_errors() {
        assert!(rotation_from_rotvec([0.0; 3]).is_err());
        assert!(rotation_from_rotvec([f64::NAN, 0.0, 1.0]).is_err());
    }
}
