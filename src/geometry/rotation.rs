//! Rotations of the sphere: from a rotation vector, and their ZYZ Euler angles (the
//! parametrization of Wigner D, PSH (9)), computed through the unit quaternion so that
//! small and near-half-turn rotations lose nothing (`proofs/euler-angles.md`).

use crate::error::{Error, Result};
use nalgebra::{Quaternion, Rotation3, UnitQuaternion};
use std::f64::consts::{PI, TAU};

/// Rotation from a rotation vector (axis times angle in radians), as an active rotation.
/// A zero vector has no axis and is rejected; use [`Rotation3::identity`] explicitly.
///
/// The matrix is built from the unit quaternion `(cos(t/2), sin(t/2) v/t)`, `t = |v|`:
/// its entries are products of the quaternion's components, each to full relative
/// accuracy, where the axis-angle form rounds `1 - cos t` and loses the second-order
/// entries of a small rotation (`proofs/euler-angles.md`).
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
    // |v| by hypot: no underflow of the squares for |v| < 1e-154.
    let t = v[0].hypot(v[1]).hypot(v[2]);
    let (s, c) = (0.5 * t).sin_cos();
    let [x, y, z] = v.map(|vi| s * (vi / t));
    let r = UnitQuaternion::new_unchecked(Quaternion::new(c, x, y, z)).to_rotation_matrix();
    if !r.matrix().iter().all(|x| x.is_finite()) {
        return Err(Error::InvalidRotation {
            value: format!("{v:?}"),
            reason: "the rotation angle (the vector's norm) is too large to represent".into(),
        });
    }
    Ok(r)
}

/// ZYZ Euler angles `(alpha, beta, gamma)` with `R = Rz(alpha) Ry(beta) Rz(gamma)`,
/// `beta` in `[0, pi]`, `alpha`, `gamma` in `(-pi, pi]`. At `beta = 0` or `pi` only
/// `alpha +- gamma` is defined; `gamma = 0`.
///
/// From the unit quaternion `(w, x, y, z)` of `R`: `R_a = w + i z = cos(beta/2)
/// e^{i (alpha + gamma)/2}` and `R_b = y - i x = sin(beta/2) e^{i (alpha - gamma)/2}`
/// (`proofs/euler-angles.md`), so `beta = 2 atan2(|R_b|, |R_a|)` and the half sum and half
/// difference are the arguments of `R_a` and `R_b`, each to about an ulp. The sum
/// `alpha + gamma` never comes from two ill-determined angles: for a small tilt both are
/// near `+-pi/2` but their sum is `2 arg R_a`, exact to rounding, as is the difference
/// near a half turn about a horizontal axis.
pub fn euler_zyz(r: &Rotation3<f64>) -> (f64, f64, f64) {
    let q = UnitQuaternion::from_rotation_matrix(r);
    let (w, x, y, z) = (q.w, q.i, q.j, q.k);
    let (ra, rb) = (w.hypot(z), y.hypot(x));
    let beta = 2.0 * rb.atan2(ra);
    let half_sum = z.atan2(w);
    let half_difference = (-x).atan2(y);
    if rb == 0.0 {
        return (wrap(2.0 * half_sum), beta, 0.0);
    }
    if ra == 0.0 {
        return (wrap(2.0 * half_difference), beta, 0.0);
    }
    (
        wrap(half_sum + half_difference),
        beta,
        wrap(half_sum - half_difference),
    )
}

/// An angle of `(-2 pi, 2 pi]` brought into `(-pi, pi]` (exact by Sterbenz's lemma: only
/// the constant `TAU - 2 pi` of 2.4e-16 is added).
fn wrap(a: f64) -> f64 {
    if a > PI {
        a - TAU
    } else if a <= -PI {
        a + TAU
    } else {
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

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

    /// A small turn about a tilted axis: the second-order entries `2 sin^2(t/2) k_i k_j`
    /// (closed form of Rodrigues' matrix) to relative accuracy. nalgebra's axis-angle
    /// matrix gave 0 for them (`1 - cos t` rounds to 0 below `t ~ 1e-8`).
    #[test]
    fn small_rotations_keep_their_second_order_entries() {
        for (v, tol) in [([1e-10, 0.0, 1e-8], 4.0), ([3e-7, 0.0, -2e-6], 4.0)] {
            let r = rotation_from_rotvec(v).unwrap();
            let t = v[0].hypot(v[2]);
            let (kx, kz) = (v[0] / t, v[2] / t);
            let h = (0.5 * t).sin();
            let want = 2.0 * h * h * kx * kz;
            for got in [r[(0, 2)], r[(2, 0)]] {
                assert!(
                    ((got - want) / want).abs() < tol * f64::EPSILON,
                    "{v:?}: {got:e} vs {want:e}"
                );
            }
        }
    }

    /// The Euler angles of rotations about z are `(t, 0, 0)`, of the half turn about x
    /// `(pi, pi, 0)`, each to a few ulps.
    #[test]
    fn degenerate_euler_angles_follow_the_convention() {
        for t in [1e-300, 1e-12, 0.5, -3.0] {
            let (a, b, g) = euler_zyz(&rotation_from_rotvec([0.0, 0.0, t]).unwrap());
            assert!(
                (a - t).abs() <= 4.0 * f64::EPSILON * t.abs() && b == 0.0 && g == 0.0,
                "{t}: {a} {b} {g}"
            );
        }
        // The half turn about x, exactly: Rz(pi) Ry(pi).
        let flip = nalgebra::Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, -1.0, -1.0));
        let (a, b, g) = euler_zyz(&Rotation3::from_matrix_unchecked(flip));
        assert!((a - PI).abs() < 4.0 * f64::EPSILON, "{a}");
        assert!((b - PI).abs() < 4.0 * f64::EPSILON && g == 0.0, "{b} {g}");
    }

    #[test]
    fn bad_rotations_are_errors() {
        assert!(rotation_from_rotvec([0.0; 3]).is_err());
        assert!(rotation_from_rotvec([f64::NAN, 0.0, 1.0]).is_err());
    }
}
