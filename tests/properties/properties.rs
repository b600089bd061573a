//! Property tests (proptest) of the scalar core: rotations compose, are unitary and
//! commute with evaluation; transforms invert; bad input is an error, never a panic.

use nalgebra::{Rotation3, Vector3};
use num_complex::Complex64;
use proptest::prelude::*;
use psh::geometry::rotation_from_rotvec;
use psh::geometry::{direction, direction_angles};
use psh::sh::num_coeffs;
use psh::sh::ShTransform;
use psh::sh::{sh_real, ShEvaluator};
use psh::sh::{RealWignerD, WignerD};

fn rotvec() -> impl Strategy<Value = [f64; 3]> {
    prop::array::uniform3(-3.0f64..3.0)
        .prop_filter("non-zero", |v| v.iter().any(|c| c.abs() > 1e-6))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// D(R1 R2) = D(R1) D(R2) acting on coefficient vectors (PSH (8)-(9)).
    #[test]
    fn rotations_compose(a in rotvec(), b in rotvec(), seed in 0u64..1000) {
        let lmax = 12;
        let (r1, r2) = (rotation_from_rotvec(a).unwrap(), rotation_from_rotvec(b).unwrap());
        let c = psh::random::pseudo_random(num_coeffs(lmax), seed);
        let one = RealWignerD::new(&(r1 * r2), lmax).unwrap().rotate(&c).unwrap();
        let two = RealWignerD::new(&r1, lmax).unwrap()
            .rotate(&RealWignerD::new(&r2, lmax).unwrap().rotate(&c).unwrap()).unwrap();
        for (x, y) in one.iter().zip(&two) {
            prop_assert!((x - y).abs() < 1e-13);
        }
    }

    /// Rotations preserve the norm of complex coefficient vectors (unitarity) and the
    /// inverse rotation undoes them.
    #[test]
    fn rotations_are_unitary(a in rotvec(), seed in 0u64..1000) {
        let lmax = 16;
        let r = rotation_from_rotvec(a).unwrap();
        let re = psh::random::pseudo_random(num_coeffs(lmax), seed);
        let c: Vec<Complex64> = re.iter().map(|&x| Complex64::new(x, 0.5 - x * x)).collect();
        let d = WignerD::new(&r, lmax).unwrap();
        let rc = d.rotate(&c).unwrap();
        let n0: f64 = c.iter().map(|z| z.norm_sqr()).sum();
        let n1: f64 = rc.iter().map(|z| z.norm_sqr()).sum();
        prop_assert!((n0 - n1).abs() < 1e-12 * n0);
        let back = WignerD::new(&r.inverse(), lmax).unwrap().rotate(&rc).unwrap();
        for (x, y) in c.iter().zip(&back) {
            prop_assert!((x - y).norm() < 1e-13);
        }
    }

    /// Evaluating rotated coefficients at w equals evaluating the original at R^-1 w.
    #[test]
    fn rotation_commutes_with_evaluation(a in rotvec(), t in 0.0f64..std::f64::consts::PI, p in -3.2f64..3.2) {
        let lmax = 10;
        let r = rotation_from_rotvec(a).unwrap();
        let c = psh::random::pseudo_random(num_coeffs(lmax), 5);
        let rc = RealWignerD::new(&r, lmax).unwrap().rotate(&c).unwrap();
        let w = Vector3::from(direction(t, p));
        let v = r.inverse() * w;
        let (tv, pv) = direction_angles([v.x, v.y, v.z]).unwrap();
        let at = |coeffs: &[f64], t: f64, p: f64| -> f64 {
            sh_real(lmax, t, p).unwrap().iter().zip(coeffs).map(|(y, c)| y * c).sum()
        };
        prop_assert!((at(&rc, t, p) - at(&c, tv, pv)).abs() < 1e-12);
    }

    /// The batch evaluator agrees with the single-direction one anywhere, poles included.
    #[test]
    fn batch_agrees_with_single(t in 0.0f64..std::f64::consts::PI, p in -3.2f64..3.2) {
        let lmax = 30;
        let ev = ShEvaluator::new(lmax).unwrap();
        let dirs = [direction(t, p), [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]];
        let mut batch = vec![0.0; 3 * ev.len()];
        ev.real_batch(&dirs, &mut batch).unwrap();
        let one = sh_real(lmax, t, p).unwrap();
        for (x, y) in batch[..ev.len()].iter().zip(&one) {
            prop_assert!((x - y).abs() < 1e-13);
        }
    }

    /// Analysis inverts synthesis on the exact grid for any band-limited input.
    #[test]
    fn transforms_invert(lmax in 0usize..40, seed in 0u64..1000) {
        let t = ShTransform::new(lmax).unwrap();
        let c = psh::random::pseudo_random(num_coeffs(lmax), seed);
        let mut f = vec![0.0; t.grid().len()];
        t.synthesis_real(&c, &mut f).unwrap();
        let mut back = vec![0.0; c.len()];
        t.analysis_real(&f, &mut back).unwrap();
        for (x, y) in c.iter().zip(&back) {
            prop_assert!((x - y).abs() < 1e-13);
        }
    }

    /// Any finite or non-finite input gives a value or a psh::Error, never a panic.
    #[test]
    fn bad_angles_never_panic(t in prop::num::f64::ANY, p in prop::num::f64::ANY) {
        let r = sh_real(4, t, p);
        if let Ok(v) = r {
            prop_assert!(v.iter().all(|x| x.is_finite()));
        }
    }

    #[test]
    fn bad_rotations_never_panic(v in prop::array::uniform3(prop::num::f64::ANY)) {
        if let Ok(r) = rotation_from_rotvec(v) {
            let d = RealWignerD::new(&r, 3).unwrap();
            prop_assert!(d.block(3).unwrap().iter().all(|x| x.is_finite()));
            prop_assert!(d.block(4).is_err());
        }
    }
}

#[test]
fn identity_rotation_is_identity() {
    let d = WignerD::new(&Rotation3::identity(), 5).unwrap();
    for l in 0..=5 {
        let n = 2 * l + 1;
        for i in 0..n {
            for k in 0..n {
                let e = if i == k { 1.0 } else { 0.0 };
                assert!((d.block(l).unwrap()[i * n + k] - e).norm() < 1e-15);
            }
        }
    }
}
