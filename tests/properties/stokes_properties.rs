//! Property tests (proptest) of the geometric Stokes layer: frames, frame fields, Stokes
//! vectors and Mueller transforms (PSH (14)-(22), (49), (59)).
//!
//! The expected values do not come from the code under test: Stokes components are
//! computed here from a physical (Jones) field `E` by projecting it on the frame's axes,
//! and the complex-pair form of PSH (49) is evaluated with PSH (44) written out here.

use nalgebra::{Matrix4, Rotation3, Vector2, Vector3};
use num_complex::Complex64;
use proptest::prelude::*;
use psh::geometry::{
    CubeMapFrameField, Frame, FrameField, PerspectiveFrameField, ThetaPhiFrameField,
};
use psh::stokes::{
    convert_between_fields, rotator, MuellerMatrix, MuellerTransform, Spin2StokesVector,
    StokesComponents, StokesVector,
};
use psh::Error;
use std::f64::consts::{FRAC_1_SQRT_2, PI};

const TOL: f64 = 1e-12;

fn unit(theta: f64, phi: f64) -> Vector3<f64> {
    Vector3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

fn arr(v: &Vector3<f64>) -> [f64; 3] {
    [v[0], v[1], v[2]]
}

/// A unit direction, uniform in angles (poles included with some probability).
fn direction() -> impl Strategy<Value = Vector3<f64>> {
    prop_oneof![
        8 => (0.0..PI, -PI..PI).prop_map(|(t, p)| unit(t, p)),
        1 => prop::sample::select(vec![
            Vector3::new(0.0, 0.0, 1.0),
            Vector3::new(0.0, 0.0, -1.0),
            Vector3::new(1.0, 0.0, 0.0),
        ]),
    ]
}

fn angle() -> impl Strategy<Value = f64> {
    -7.0f64..7.0
}

fn rotation() -> impl Strategy<Value = Rotation3<f64>> {
    prop::array::uniform3(-4.0f64..4.0).prop_map(|v| Rotation3::new(Vector3::from(v)))
}

/// A frame on the ray `w`, from a hint that is not parallel to it.
fn frame_on(w: Vector3<f64>, a: f64) -> Frame {
    // The world axis least aligned with w, turned by a about w.
    let e = if w[0].abs() < 0.5 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let x0 = (e - w * w.dot(&e)).normalize();
    let y0 = w.cross(&x0);
    let x = x0 * a.cos() + y0 * a.sin();
    Frame::from_z_and_x(arr(&w), arr(&x)).unwrap()
}

fn components() -> impl Strategy<Value = StokesComponents> {
    (0.0..10.0f64, -10.0..10.0f64, -10.0..10.0f64, -10.0..10.0f64)
        .prop_map(|(a, b, c, d)| StokesComponents::new([a, b, c, d]).unwrap())
}

fn mueller() -> impl Strategy<Value = MuellerMatrix> {
    prop::array::uniform16(-2.0f64..2.0)
        .prop_map(|v| MuellerMatrix::new(Matrix4::from_column_slice(&v)).unwrap())
}

/// A transverse Jones field on the ray `w`: complex amplitudes along two orthogonal axes.
fn jones(w: &Vector3<f64>, amps: [f64; 4]) -> [Complex64; 3] {
    let f = Frame::from_z(arr(w)).unwrap();
    let (a, b) = (
        Complex64::new(amps[0], amps[1]),
        Complex64::new(amps[2], amps[3]),
    );
    let (x, y) = (f.x(), f.y());
    [0, 1, 2].map(|k| a * x[k] + b * y[k])
}

fn proj(e: &[Complex64; 3], v: &Vector3<f64>) -> Complex64 {
    e[0] * v[0] + e[1] * v[1] + e[2] * v[2]
}

/// Stokes components of the field `e` measured in `f`, from the definitions:
/// `s0 = |E_x|^2 + |E_y|^2`, `s1 = |E_x|^2 - |E_y|^2`, `s2 = |E_+|^2 - |E_-|^2` with
/// `E_+- = E . (x +- y)/sqrt 2`, `s3 = 2 Im(conj(E_x) E_y)`.
fn measured(e: &[Complex64; 3], f: &Frame) -> StokesComponents {
    let (x, y) = (f.x(), f.y());
    let (ex, ey) = (proj(e, &x), proj(e, &y));
    let ep = proj(e, &((x + y) * FRAC_1_SQRT_2));
    let em = proj(e, &((x - y) * FRAC_1_SQRT_2));
    StokesComponents::new([
        ex.norm_sqr() + ey.norm_sqr(),
        ex.norm_sqr() - ey.norm_sqr(),
        ep.norm_sqr() - em.norm_sqr(),
        2.0 * (ex.conj() * ey).im,
    ])
    .unwrap()
}

fn close(a: &StokesComponents, b: &StokesComponents, tol: f64) -> bool {
    a.approx_eq(b, tol)
}

/// PSH (44): the isomorphic and conjugation parts of the spin 2-to-2 block.
fn complex_pair(m: &MuellerMatrix) -> (Complex64, Complex64) {
    let g = |i, j| m.get(i, j).unwrap();
    let (m11, m12, m21, m22) = (g(1, 1), g(1, 2), g(2, 1), g(2, 2));
    (
        Complex64::new((m11 + m22) / 2.0, (m21 - m12) / 2.0),
        Complex64::new((m11 - m22) / 2.0, (m21 + m12) / 2.0),
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// PSH (14) against physics: the components measured from a Jones field in `F`,
    /// converted to `G`, equal the components measured in `G`. This fixes the sign of
    /// PSH (14) independently of the code.
    #[test]
    fn frame_change_matches_measurement(
        w in direction(), a in angle(), b in angle(), amps in prop::array::uniform4(-3.0f64..3.0)
    ) {
        let (f, g) = (frame_on(w, a), frame_on(w, b));
        let e = jones(&w, amps);
        let s = StokesVector::new(measured(&e, &f), f);
        let got = s.components_in(&g).unwrap();
        prop_assert!(close(&got, &measured(&e, &g), TOL), "{got:?}");
    }

    /// Round trip `[[[s]_F]^G]_G]^F = s`, and the rotator form `C(vartheta) s`.
    #[test]
    fn frame_change_round_trip(w in direction(), a in angle(), b in angle(), s in components()) {
        let (f, g) = (frame_on(w, a), frame_on(w, b));
        let t = StokesVector::new(s, f).components_in(&g).unwrap();
        let back = StokesVector::new(t, g).components_in(&f).unwrap();
        prop_assert!(close(&back, &s, TOL));
        // G = R_z(b - a) F: the components are C(b - a) s.
        prop_assert!(close(&t, &rotator(b - a).unwrap().apply(&s), TOL));
        prop_assert!(((f.angle_to(&g).unwrap() - (b - a)).rem_euclid(2.0 * PI)).min(
            (-(f.angle_to(&g).unwrap() - (b - a))).rem_euclid(2.0 * PI)) < 1e-12);
    }

    /// PSH (14) composes: F -> G -> H equals F -> H.
    #[test]
    fn frame_changes_compose(
        w in direction(), a in angle(), b in angle(), c in angle(), s in components()
    ) {
        let (f, g, h) = (frame_on(w, a), frame_on(w, b), frame_on(w, c));
        let via = StokesVector::new(s, f).in_frame(&g).unwrap().components_in(&h).unwrap();
        let direct = StokesVector::new(s, f).components_in(&h).unwrap();
        prop_assert!(close(&via, &direct, TOL));
        // And the rotators: C(c - b) C(b - a) = C(c - a).
        let two = rotator(c - b).unwrap() * rotator(b - a).unwrap();
        prop_assert!(two.approx_eq(&rotator(c - a).unwrap(), TOL));
    }

    /// `s0`, `s3`, the degree of linear polarization, and the polarization line (its
    /// angle to a fixed geometric direction) do not depend on the frame.
    #[test]
    fn invariants_do_not_depend_on_the_frame(
        w in direction(), a in angle(), b in angle(), s in components(), refdir in direction()
    ) {
        let (f, g) = (frame_on(w, a), frame_on(w, b));
        let v = StokesVector::new(s, f);
        let t = v.components_in(&g).unwrap();
        prop_assert!((t.s0() - s.s0()).abs() <= TOL && (t.s3() - s.s3()).abs() <= TOL);
        if let (Some(p), Some(q)) = (s.degree_of_linear_polarization(),
                                     t.degree_of_linear_polarization()) {
            prop_assert!((p - q).abs() <= TOL * (1.0 + p));
        }
        if s.s1().hypot(s.s2()) > 1e-3 {
            let d1 = v.linear_polarization_direction().unwrap();
            let d2 = v.in_frame(&g).unwrap().linear_polarization_direction().unwrap();
            prop_assert!(d1.cross(&d2).norm() < 1e-9, "{d1} {d2}");
            prop_assert!(d1.dot(&w).abs() < 1e-12);
            // The angle between the polarization line and a fixed direction (projected
            // on the plane of the ray), modulo pi.
            let r = refdir - w * w.dot(&refdir);
            if r.norm() > 1e-3 {
                let ang = |d: &Vector3<f64>| {
                    let c = d.dot(&r) / r.norm();
                    c * c
                };
                prop_assert!((ang(&d1) - ang(&d2)).abs() < 1e-9);
            }
        }
    }

    /// PSH (17), (18): sum and inner product computed with the operands in any frames
    /// agree (as geometric quantities), and agree with the numeric ones in one frame.
    #[test]
    fn sum_and_inner_product_do_not_depend_on_frames(
        w in direction(), a in angle(), b in angle(), c in angle(),
        s in components(), t in components()
    ) {
        let (f, g, h) = (frame_on(w, a), frame_on(w, b), frame_on(w, c));
        let sv = StokesVector::new(s, f);
        let tv = StokesVector::new(t, g);
        let (sh, th) = (sv.components_in(&h).unwrap(), tv.components_in(&h).unwrap());
        let inner = sv.inner(&tv).unwrap();
        prop_assert!((inner - sh.dot(&th)).abs() < 1e-10);
        prop_assert!((inner - tv.inner(&sv).unwrap()).abs() < 1e-10);
        let sum = sv.try_add(&tv).unwrap();
        prop_assert!(close(&sum.components_in(&h).unwrap(), &(sh + th), 1e-11));
        prop_assert!(sum.approx_eq(&tv.try_add(&sv).unwrap(), 1e-11).unwrap());
        // Spin-2 parts likewise.
        let (ls, lt) = (sv.spin2(), tv.spin2());
        prop_assert!((ls.inner(&lt).unwrap()
            - (sh.s1() * th.s1() + sh.s2() * th.s2())).abs() < 1e-10);
        let lsum = ls.try_add(&lt).unwrap().components_in(&h).unwrap();
        prop_assert!((lsum - Vector2::new(sh.s1() + th.s1(), sh.s2() + th.s2())).amax() < 1e-11);
    }

    /// PSH (20): the complex multiple is frame-independent.
    #[test]
    fn complex_multiple_is_frame_independent(
        w in direction(), a in angle(), b in angle(), s in components(),
        zr in -3.0f64..3.0, zi in -3.0f64..3.0
    ) {
        let (f, g) = (frame_on(w, a), frame_on(w, b));
        let z = Complex64::new(zr, zi);
        let lin = StokesVector::new(s, f).spin2();
        let lin_g = Spin2StokesVector::from_complex(lin.complex_in(&g).unwrap(), g).unwrap();
        prop_assert!(lin.mul_complex(z).unwrap()
            .approx_eq(&lin_g.mul_complex(z).unwrap(), 1e-11).unwrap());
    }

    /// PSH (19): `[R_S s]^{R F} = [s]^F`; and `R_S` acts on the physical field: the
    /// rotated field measured in any frame of the rotated ray gives the components of the
    /// rotated Stokes vector.
    #[test]
    fn rotation_of_stokes_vectors(
        w in direction(), a in angle(), b in angle(), r in rotation(),
        amps in prop::array::uniform4(-3.0f64..3.0)
    ) {
        let f = frame_on(w, a);
        let e = jones(&w, amps);
        let s = measured(&e, &f);
        let rs = StokesVector::new(s, f).rotate(&r).unwrap();
        prop_assert!(close(&rs.components_in(&f.rotated(&r).unwrap()).unwrap(), &s, TOL));
        let rw = r * w;
        prop_assert!((Vector3::from(rs.direction()) - rw).norm() < 1e-12);
        let re = [0, 1, 2].map(|i| {
            (0..3).map(|k| e[k] * r.matrix()[(i, k)]).sum::<Complex64>()
        });
        let g = frame_on(rw.normalize(), b);
        prop_assert!(close(&rs.components_in(&g).unwrap(), &measured(&re, &g), 1e-11));
    }

    /// PSH (49): `[M]^{G_i -> G_o}` maps `[s]^{G_i}` to `[M s]^{G_o}`; the spin 2-to-2
    /// block's complex pair (PSH (44)) turns as printed in PSH (49) with `alpha` the
    /// output frame's angle and `beta` the input's.
    #[test]
    fn mueller_frame_change(
        wi in direction(), wo in direction(), m in mueller(), s in components(),
        a in angle(), b in angle(), c in angle(), d in angle()
    ) {
        let (fi, fo) = (frame_on(wi, a), frame_on(wo, b));
        let (gi, go) = (frame_on(wi, c), frame_on(wo, d));
        let t = MuellerTransform::new(m, fi, fo);
        let mg = t.matrix_in(&gi, &go).unwrap();
        let sv = StokesVector::new(s, gi);
        let want = t.apply(&sv).unwrap().components_in(&go).unwrap();
        prop_assert!(close(&mg.apply(&s), &want, 1e-10));
        // Complex-pair form of PSH (49): beta = input angle, alpha = output angle.
        let (beta, alpha) = (c - a, d - b);
        let (iso, conj) = complex_pair(&m);
        let (iso2, conj2) = complex_pair(&mg);
        let iso_want = iso * Complex64::from_polar(1.0, 2.0 * (beta - alpha));
        let conj_want = conj * Complex64::from_polar(1.0, -2.0 * (alpha + beta));
        prop_assert!((iso2 - iso_want).norm() < 1e-12 && (conj2 - conj_want).norm() < 1e-12);
        // The 0-0 block (rows and columns 0, 3) does not change.
        for (i, j) in [(0, 0), (0, 3), (3, 0), (3, 3)] {
            prop_assert!((mg.get(i, j).unwrap() - m.get(i, j).unwrap()).abs() < 1e-13);
        }
        // Same as the numeric reframing and as the stored-in-other-frames transform.
        prop_assert!(mg.approx_eq(&m.reframed(c - a, d - b).unwrap(), 1e-12));
        prop_assert!(t.in_frames(&gi, &go).unwrap().approx_eq(&t, 1e-12).unwrap());
    }

    /// Composition: consistent with applying one after the other, and associative, when
    /// the meeting frames differ by rotations about the ray.
    #[test]
    fn mueller_composition(
        w0 in direction(), w1 in direction(), w2 in direction(), w3 in direction(),
        ms in prop::array::uniform3(mueller()), angs in prop::array::uniform6(angle()),
        s in components()
    ) {
        let a = MuellerTransform::new(ms[0], frame_on(w0, angs[0]), frame_on(w1, angs[1]));
        let b = MuellerTransform::new(ms[1], frame_on(w1, angs[2]), frame_on(w2, angs[3]));
        let c = MuellerTransform::new(ms[2], frame_on(w2, angs[4]), frame_on(w3, angs[5]));
        let sv = StokesVector::new(s, frame_on(w0, 0.3));
        let ba = b.compose(&a).unwrap();
        let step = b.apply(&a.apply(&sv).unwrap()).unwrap();
        prop_assert!(ba.apply(&sv).unwrap().approx_eq(&step, 1e-10).unwrap());
        let left = c.compose(&b).unwrap().compose(&a).unwrap();
        let right = c.compose(&ba).unwrap();
        prop_assert!(left.approx_eq(&right, 1e-10).unwrap());
        prop_assert!(a.then(&b).unwrap().then(&c).unwrap().approx_eq(&left, 1e-10).unwrap());
    }

    /// PSH (59): `R_M[K] = R_S K R_S^{-1}`, literally as a composition of transforms, and
    /// `R_M[K] (R_S s) = R_S (K s)`.
    #[test]
    fn mueller_rotation(
        wi in direction(), wo in direction(), m in mueller(), s in components(),
        r in rotation(), a in angle(), b in angle(), c in angle()
    ) {
        let (fi, fo) = (frame_on(wi, a), frame_on(wo, b));
        let k = MuellerTransform::new(m, fi, fo);
        let rk = k.rotate(&r).unwrap();
        let sv = StokesVector::new(s, frame_on(wi, c));
        let lhs = rk.apply(&sv.rotate(&r).unwrap()).unwrap();
        let rhs = k.apply(&sv).unwrap().rotate(&r).unwrap();
        prop_assert!(lhs.approx_eq(&rhs, 1e-10).unwrap());
        // R_S as Mueller transforms, on frames other than K's.
        let gi = frame_on(wi, c);
        let go = frame_on(wo, a + b);
        let rs_in = MuellerTransform::rotation(&r, gi).unwrap();
        let rs_in_inv = MuellerTransform::rotation(&r.inverse(), gi.rotated(&r).unwrap()).unwrap();
        let rs_out = MuellerTransform::rotation(&r, go).unwrap();
        let literal = rs_out.compose(&k).unwrap().compose(&rs_in_inv).unwrap();
        prop_assert!(literal.approx_eq(&rk, 1e-10).unwrap());
        prop_assert!(rs_in.apply(&sv).unwrap().approx_eq(&sv.rotate(&r).unwrap(), 1e-10).unwrap());
    }

    /// Operations across different rays are errors, never panics.
    #[test]
    fn different_rays_are_errors(
        w1 in direction(), w2 in direction(), s in components(), m in mueller(), a in angle()
    ) {
        prop_assume!((w1 - w2).norm() > 1e-6);
        let (f1, f2) = (frame_on(w1, a), frame_on(w2, a));
        let (s1, s2) = (StokesVector::new(s, f1), StokesVector::new(s, f2));
        let is_rays = |e: Error| matches!(e, Error::DifferentRays { .. });
        prop_assert!(is_rays(s1.try_add(&s2).unwrap_err()));
        prop_assert!(is_rays(s1.inner(&s2).unwrap_err()));
        prop_assert!(is_rays(s1.components_in(&f2).unwrap_err()));
        prop_assert!(is_rays(s1.spin2().try_add(&s2.spin2()).unwrap_err()));
        let t = MuellerTransform::new(m, f1, f1);
        prop_assert!(is_rays(t.apply(&s2).unwrap_err()));
        let u = MuellerTransform::new(m, f2, f2);
        prop_assert!(is_rays(t.compose(&u).unwrap_err()));
        prop_assert!(is_rays(t.matrix_in(&f2, &f1).unwrap_err()));
        prop_assert!(is_rays(f1.angle_to(&f2).unwrap_err()));
    }

    /// NaN and infinities anywhere are errors, never panics.
    #[test]
    fn non_finite_input_is_an_error(k in 0usize..4, bad in prop::sample::select(vec![
        f64::NAN, f64::INFINITY, f64::NEG_INFINITY]), w in direction()
    ) {
        let mut s = [1.0, 0.2, 0.3, 0.1];
        s[k] = bad;
        prop_assert!(StokesComponents::new(s).is_err());
        let mut rows = [[0.0; 4]; 4];
        rows[k][3 - k] = bad;
        prop_assert!(MuellerMatrix::from_rows(rows).is_err());
        let mut wv = arr(&w);
        wv[k % 3] = bad;
        prop_assert!(ThetaPhiFrameField::new().frame(wv).is_err());
        prop_assert!(CubeMapFrameField.frame(wv).is_err());
        prop_assert!(Frame::from_z(wv).is_err());
        prop_assert!(rotator(bad).is_err());
        let f = frame_on(w, 0.0);
        prop_assert!(f.rotated_about_z(bad).is_err());
        let v = StokesVector::new(StokesComponents::unpolarized(1.0).unwrap(), f);
        prop_assert!(v.scaled(bad).is_err());
        let r = Rotation3::from_matrix_unchecked(nalgebra::Matrix3::from_element(bad));
        prop_assert!(v.rotate(&r).is_err());
    }

    /// Every frame field gives orthonormal right-handed frames with `z = w`; converting
    /// between fields round-trips.
    #[test]
    fn frame_fields(w in direction(), s in components(), cam in rotation()) {
        let persp = PerspectiveFrameField::new(Frame::from_rotation(&cam).unwrap());
        let fields: [&dyn FrameField; 3] = [&ThetaPhiFrameField::new(), &CubeMapFrameField, &persp];
        for field in fields {
            let f = field.frame(arr(&w)).unwrap();
            let m = f.matrix();
            prop_assert!((m.transpose() * m - nalgebra::Matrix3::identity()).amax() < 1e-14);
            prop_assert!((m.determinant() - 1.0).abs() < 1e-14);
            prop_assert!((f.z() - w).norm() < 1e-15);
        }
        let t = convert_between_fields(s, arr(&w), &ThetaPhiFrameField::new(), &persp).unwrap();
        let back = convert_between_fields(t, arr(&w), &persp, &ThetaPhiFrameField::new()).unwrap();
        prop_assert!(close(&back, &s, TOL));
        // Perspective rule (Mitsuba): x parallel to w x up, up = -y_camera.
        let up = -Frame::from_rotation(&cam).unwrap().y();
        let h = w.cross(&up);
        if h.norm() > 1e-6 {
            prop_assert!((persp.frame(arr(&w)).unwrap().x() - h.normalize()).norm() < 1e-9);
        }
        // Theta-phi: x along increasing theta, i.e. x . e_z = -sin(theta) <= 0.
        let tp = ThetaPhiFrameField::new().frame(arr(&w)).unwrap();
        prop_assert!((tp.x()[2] + w[0].hypot(w[1])).abs() < 1e-15);
        prop_assert!(tp.y()[2].abs() < 1e-15);
    }
}
