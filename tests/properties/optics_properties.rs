//! Property and reference tests of `psh::optics`: Fresnel coefficients, the Mueller matrix
//! of a specular reflection and its frames, the microfacet pBRDF models.
//!
//! Expected values come from outside the code under test wherever possible: Maxwell's
//! boundary conditions on explicit plane waves (for `r_s`, `r_p` and their sign
//! convention), the Stokes parameters of explicit 3D electric fields measured in
//! arbitrary frames (for the Mueller matrix and its frames), the a/b form of the
//! Fresnel reflectances printed in PF (1)-(2), Born & Wolf's formula for the phase of
//! total internal reflection, and Walter et al. 2007 (20), (33), (34) written out here.

use nalgebra::{Matrix4, Vector3, Vector4};
use num_complex::Complex64;
use proptest::prelude::*;
use psh::geometry::Frame;
use psh::optics::{
    fresnel, sp_frames, Channel, ComplexIor, Conductor, FresnelCoefficients, Lambertian, Material,
    MicrofacetSpecular, PolarizedPlastic,
};
use psh::stokes::{MuellerField, MuellerTransform, StokesComponents};
use psh::Error;
use std::f64::consts::PI;

type C3 = Vector3<Complex64>;

fn c(re: f64) -> Complex64 {
    Complex64::new(re, 0.0)
}

fn cvec(v: &Vector3<f64>) -> C3 {
    v.map(c)
}

/// Plain (bilinear, not Hermitian) dot and cross products of complex 3-vectors.
fn dot(a: &C3, b: &C3) -> Complex64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: &C3, b: &C3) -> C3 {
    Vector3::new(
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    )
}

fn arr(v: &Vector3<f64>) -> [f64; 3] {
    [v[0], v[1], v[2]]
}

fn unit(theta: f64, phi: f64) -> Vector3<f64> {
    Vector3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

/// Stokes components of the complex field `e` (amplitudes in the `e^{-i omega t}`
/// convention) measured in `frame` by psh's definition: `a = E.x`, `b = E.y`,
/// `s0 = |a|^2 + |b|^2`, `s1 = |a|^2 - |b|^2`, `s2 + i s3 = 2 a conj(b)`.
fn measure(e: &C3, frame: &Frame) -> Vector4<f64> {
    let a = dot(e, &cvec(&frame.x()));
    let b = dot(e, &cvec(&frame.y()));
    let z = a * b.conj() * 2.0;
    Vector4::new(
        a.norm_sqr() + b.norm_sqr(),
        a.norm_sqr() - b.norm_sqr(),
        z.re,
        z.im,
    )
}

/// A relative index: dielectric from outside, dielectric from inside, or conductor.
fn any_ior() -> impl Strategy<Value = ComplexIor> {
    prop_oneof![
        (1.0f64..3.0).prop_map(|n| ComplexIor::dielectric(n).unwrap()),
        (1.0f64..3.0).prop_map(|n| ComplexIor::dielectric(1.0 / n).unwrap()),
        (0.05f64..3.0, 0.0f64..8.0).prop_map(|(n, k)| ComplexIor::new(n, k).unwrap()),
    ]
}

fn upper() -> impl Strategy<Value = Vector3<f64>> {
    (0.0..PI / 2.0, -PI..PI).prop_map(|(t, p)| unit(t, p))
}

fn frame_on(w: &Vector3<f64>, a: f64) -> Frame {
    Frame::from_z(arr(w)).unwrap().rotated_about_z(a).unwrap()
}

fn polarized_input() -> impl Strategy<Value = Vector4<f64>> {
    (0.0..PI, -PI..PI).prop_map(|(t, p)| {
        let v = unit(t, p);
        Vector4::new(1.0, v[0], v[1], v[2])
    })
}

fn realizable(out: &Vector4<f64>, scale: f64) -> bool {
    let pol = (out[1] * out[1] + out[2] * out[2] + out[3] * out[3]).sqrt();
    out[0] >= pol - 1e-12 * scale && out[0] >= -1e-15 * scale
}

// ---------------------------------------------------------------- Fresnel coefficients

/// Checks Maxwell's boundary conditions for the coefficients at `theta`: incident,
/// reflected and transmitted plane waves with wave vectors (units of `k0 n_1`)
/// `K_i = (sin, 0, -cos)`, `K_r = (sin, 0, cos)`, `K_t = (sin, 0, -u)` (`u^2 = eta^2 - sin^2`),
/// `s = e_y`, `p = K x s / |K|`; the transmitted amplitudes are solved from one condition
/// each and the other two conditions must then hold. Returns the largest residual.
fn boundary_residual(f: &FresnelCoefficients, ior: &ComplexIor, theta: f64) -> f64 {
    let (st, ct) = theta.sin_cos();
    let eta = ior.eta();
    let u = (eta * eta - c(st * st)).sqrt();
    let u = if u.im < 0.0 { -u } else { u };
    let ki = Vector3::new(c(st), c(0.0), c(-ct));
    let kr = Vector3::new(c(st), c(0.0), c(ct));
    let kt = Vector3::new(c(st), c(0.0), -u);
    let s = Vector3::new(c(0.0), c(1.0), c(0.0));
    let (pi, pr) = (cross(&ki, &s), cross(&kr, &s));
    let pt = cross(&kt, &s) / eta;
    let mut worst: f64 = 0.0;
    // s polarization: E_y gives t_s; H_x (H proportional to K x E) must match.
    {
        let (ei, er) = (s, s * f.r_s());
        let ts = (ei[1] + er[1]) / s[1];
        let et = s * ts;
        let h1 = cross(&ki, &ei) + cross(&kr, &er);
        let h2 = cross(&kt, &et);
        worst = worst
            .max((h1[0] - h2[0]).norm())
            .max((h1[1] - h2[1]).norm());
    }
    // p polarization: H_y gives t_p; E_x must match.
    {
        let (ei, er) = (pi, pr * f.r_p());
        let h1 = cross(&ki, &ei) + cross(&kr, &er);
        let hp = cross(&kt, &pt);
        let tp = h1[1] / hp[1];
        let et = pt * tp;
        let e1 = ei + er;
        worst = worst
            .max((e1[0] - et[0]).norm())
            .max((e1[1] - et[1]).norm());
    }
    worst
}

#[test]
fn reflectance_of_gold_against_pf_formula() {
    // Gold at 650 nm, PF Table 1: n = 0.183, k = 3.424, printed R_0 = 0.94.
    let gold = Material::Gold.ior(Channel::Red);
    let (n, k) = (0.183f64, 3.424f64);
    // PF (1)-(2) (Wilkie & Weidlich 2012), evaluated here independently.
    let pf = |theta: f64| {
        let (s, co) = theta.sin_cos();
        let t = n * n - k * k - s * s;
        let root = (t * t + 4.0 * n * n * k * k).sqrt();
        let a = ((root + t) / 2.0).sqrt();
        let b2 = (root - t) / 2.0;
        let fs = (a * a + b2 - 2.0 * a * co + co * co) / (a * a + b2 + 2.0 * a * co + co * co);
        let st = s * theta.tan();
        let fp = fs * (a * a + b2 - 2.0 * a * st + st * st) / (a * a + b2 + 2.0 * a * st + st * st);
        (fs, fp)
    };
    for deg in [0.0f64, 45.0, 80.0] {
        let th = deg.to_radians();
        let f = fresnel(th.cos(), &gold).unwrap();
        let (fs, fp) = pf(th);
        assert!(
            (f.reflectance_s() - fs).abs() < 1e-13,
            "{deg}: {} {fs}",
            f.reflectance_s()
        );
        assert!(
            (f.reflectance_p() - fp).abs() < 1e-13,
            "{deg}: {} {fp}",
            f.reflectance_p()
        );
    }
    let r0 = fresnel(1.0, &gold).unwrap().reflectance();
    assert!(
        (r0 - 0.9442).abs() < 1e-4 && (r0 - 0.94).abs() < 0.005,
        "{r0}"
    );
    // At 45 degrees, R_p = R_s^2 exactly for any index (Abeles' relation).
    let f = fresnel((PI / 4.0).cos(), &gold).unwrap();
    assert!((f.reflectance_p() - f.reflectance_s().powi(2)).abs() < 1e-14);
}

#[test]
fn glass_textbook_values() {
    let glass = ComplexIor::dielectric(1.5).unwrap();
    let f = fresnel(1.0, &glass).unwrap();
    assert!((f.reflectance() - 0.04).abs() < 1e-15);
    assert!((f.r_s() - c(-0.2)).norm() < 1e-15 && (f.r_p() - c(0.2)).norm() < 1e-15);
    let brewster = 1.5f64.atan(); // 56.31 degrees
    let f = fresnel(brewster.cos(), &glass).unwrap();
    assert!(f.reflectance_p() < 1e-30);
    assert!((f.reflectance_s() - 0.1479289940828).abs() < 1e-12); // ((n^2-1)/(n^2+1))^2
}

#[test]
fn mitsuba_layout_of_the_travel_matrix() {
    // Mitsuba 3's `specular_reflection` (include/mitsuba/render/mueller.h) builds, from
    // amplitudes a_s, a_p in the e^{+i omega t} convention (the complex conjugates of ours)
    // and delta_M = arg a_p - arg a_s, the matrix
    // [[a, b, 0, 0], [b, a, 0, 0], [0, 0, c cos dM, -c sin dM], [0, 0, c sin dM, c cos dM]].
    for (ior, cos) in [
        (ComplexIor::new(0.183, 3.424).unwrap(), 0.3),
        (ComplexIor::dielectric(1.5).unwrap(), 0.2),
        (ComplexIor::dielectric(1.0 / 1.5).unwrap(), 0.4),
    ] {
        let f = fresnel(cos, &ior).unwrap();
        let (a_s, a_p) = (f.r_s().conj(), f.r_p().conj());
        let (rs, rp) = (a_s.norm_sqr(), a_p.norm_sqr());
        let (a, b, cc) = ((rs + rp) / 2.0, (rs - rp) / 2.0, (rs * rp).sqrt());
        let dm = a_p.arg() - a_s.arg();
        let m = Matrix4::new(
            a,
            b,
            0.0,
            0.0,
            b,
            a,
            0.0,
            0.0,
            0.0,
            0.0,
            cc * dm.cos(),
            -cc * dm.sin(),
            0.0,
            0.0,
            cc * dm.sin(),
            cc * dm.cos(),
        );
        assert!((f.mueller_travel().matrix() - m).amax() < 1e-14);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn fresnel_satisfies_the_boundary_conditions(ior in any_ior(), theta in 0.0..PI / 2.0) {
        let f = fresnel(theta.cos(), &ior).unwrap();
        let res = boundary_residual(&f, &ior, theta);
        prop_assert!(res < 1e-12, "residual {res}");
    }

    #[test]
    fn reflectances_are_in_the_unit_interval(ior in any_ior(), cos in 0.0f64..=1.0) {
        let f = fresnel(cos, &ior).unwrap();
        for r in [f.reflectance_s(), f.reflectance_p()] {
            prop_assert!((0.0..=1.0 + 1e-15).contains(&r), "{r}");
        }
        prop_assert!(f.phase_difference().is_finite());
        if f.is_total_internal_reflection() {
            prop_assert!((f.reflectance_s() - 1.0).abs() < 1e-14);
            prop_assert!((f.reflectance_p() - 1.0).abs() < 1e-14);
        }
    }

    #[test]
    fn total_internal_reflection_phase(n in 1.1f64..3.0, t in 0.0f64..1.0) {
        // Born & Wolf §1.5.4: tan(-delta/2) = cos sqrt(sin^2 - eta^2) / sin^2.
        let eta = 1.0 / n;
        let crit = eta.asin();
        let theta = crit + t * (PI / 2.0 - crit);
        let f = fresnel(theta.cos(), &ComplexIor::dielectric(eta).unwrap()).unwrap();
        let (s, co) = theta.sin_cos();
        let expect = 2.0 * (co * (s * s - eta * eta).max(0.0).sqrt() / (s * s)).atan();
        prop_assert!((-f.phase_difference() - expect).abs() < 1e-12);
    }

    #[test]
    fn fresnel_mueller_is_realizable(ior in any_ior(), cos in 0.0f64..=1.0, s in polarized_input()) {
        let f = fresnel(cos, &ior).unwrap();
        for m in [f.mueller(), f.mueller_travel()] {
            let out = m.matrix() * s;
            prop_assert!(realizable(&out, 1.0));
            // A pure (Jones) Mueller matrix keeps full polarization: s0^2 = |s|^2.
            let pol2 = out[1] * out[1] + out[2] * out[2] + out[3] * out[3];
            prop_assert!((out[0] * out[0] - pol2).abs() < 1e-12);
        }
    }

    /// The Fresnel Mueller matrix in the frames of `sp_frames`, read in arbitrary frames
    /// of the two rays, maps the Stokes vector of an explicit incident field to that of the
    /// reflected field `r_s (E.s) s + r_p (E.p_i) p_r` (`p = d x s` on each ray, the
    /// convention validated by the boundary conditions above).
    #[test]
    fn mueller_matches_reflected_fields(
        wi in upper(), wo in upper(), ior in any_ior(),
        ai in -4.0f64..4.0, ao in -4.0f64..4.0,
        e in prop::array::uniform4(-1.0f64..1.0),
    ) {
        let h = (wi + wo).normalize();
        let f = fresnel(h.dot(&wi).clamp(0.0, 1.0), &ior).unwrap();
        let s = wi.cross(&wo);
        prop_assume!(s.norm() > 1e-6);
        let s = s.normalize();
        let (di, d_o) = (-wi, wo);
        let (pi, po) = (di.cross(&s), d_o.cross(&s));
        // Incident field (transverse to d_i), amplitudes e^{-i omega t}.
        let ein = cvec(&s) * Complex64::new(e[0], e[1]) + cvec(&pi) * Complex64::new(e[2], e[3]);
        let es = dot(&ein, &cvec(&s));
        let ep = dot(&ein, &cvec(&pi));
        let eout = cvec(&s) * (f.r_s() * es) + cvec(&po) * (f.r_p() * ep);
        let (gi, go) = (frame_on(&wi, ai), frame_on(&wo, ao));
        let (fi, fo) = sp_frames(arr(&wi), arr(&wo)).unwrap();
        let t = MuellerTransform::new(f.mueller(), fi, fo);
        let m = t.matrix_in(&gi, &go).unwrap().matrix();
        let got = m * measure(&ein, &gi);
        let want = measure(&eout, &go);
        prop_assert!((got - want).amax() < 1e-12, "{got} vs {want}");
    }
}

// ------------------------------------------------------------------------- the models

fn models() -> Vec<(&'static str, Box<dyn MuellerField>)> {
    vec![
        (
            "plastic",
            Box::new(PolarizedPlastic::new(0.3, 1.5, 0.5).unwrap()),
        ),
        (
            "plastic smooth",
            Box::new(PolarizedPlastic::new(1e-4, 1.589, 1.0).unwrap()),
        ),
        (
            "conductor",
            Box::new(Conductor::new(0.2, 0.183, 3.424).unwrap()),
        ),
        (
            "iron rough",
            Box::new(Conductor::from_material(2.0, Material::Iron, Channel::Blue).unwrap()),
        ),
        ("lambertian", Box::new(Lambertian::new(0.7).unwrap())),
    ]
}

fn m00(model: &dyn MuellerField, wi: &Vector3<f64>, wo: &Vector3<f64>) -> f64 {
    model.transform(arr(wi), arr(wo)).unwrap().matrix().matrix()[(0, 0)]
}

#[test]
fn microfacet_value_against_walter() {
    // P = F D G2 / (4 cos_o), Walter et al. 2007 (20), (33); G2 = 1/(1 + L_i + L_o),
    // Lambda(v) = (sqrt(1 + alpha^2 tan^2) - 1)/2, written out here.
    let alpha = 0.35;
    let ior = ComplexIor::new(1.2, 2.5).unwrap();
    let model = MicrofacetSpecular::new(alpha, ior).unwrap();
    let (wi, wo) = (unit(0.7, 0.3), unit(1.1, 2.0));
    let h = (wi + wo).normalize();
    let tan2 = |w: &Vector3<f64>| (1.0 - w[2] * w[2]) / (w[2] * w[2]);
    let d = alpha * alpha / (PI * h[2].powi(4) * (alpha * alpha + tan2(&h)).powi(2));
    let lambda = |w: &Vector3<f64>| ((1.0 + alpha * alpha * tan2(w)).sqrt() - 1.0) / 2.0;
    let g2 = 1.0 / (1.0 + lambda(&wi) + lambda(&wo));
    let f = fresnel(h.dot(&wi), &ior).unwrap();
    let expect = f.mueller().matrix() * (d * g2 / (4.0 * wo[2]));
    let got = model
        .transform(arr(&wi), arr(&wo))
        .unwrap()
        .matrix()
        .matrix();
    assert!(
        (got - expect).amax() < 1e-14 * expect.amax(),
        "{got} {expect}"
    );
}

#[test]
fn finite_at_special_pairs() {
    let g = 1e-300f64;
    let dirs = [
        Vector3::new(0.0, 0.0, 1.0),
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(-1.0, 0.0, 0.0),
        Vector3::new(0.0, 1.0, 0.0),
        Vector3::new(1.0, 0.0, g),
        Vector3::new(0.0, -1.0, g),
        Vector3::new(0.6, 0.0, 0.8),
        Vector3::new(-0.6, 0.0, 0.8),
        Vector3::new(0.0, 0.0, -1.0),
        Vector3::new(0.6, 0.0, -0.8),
    ];
    for (name, model) in models() {
        for wi in &dirs {
            for wo in dirs.iter().chain([wi, &-wi]) {
                let t = model.transform(arr(wi), arr(wo)).unwrap();
                let m = t.matrix().matrix();
                assert!(m.iter().all(|v| v.is_finite()), "{name} {wi:?} {wo:?}");
                if wi[2] <= 0.0 || wo[2] < 0.0 {
                    assert_eq!(m, Matrix4::zeros(), "{name} {wi:?} {wo:?}");
                }
                assert!((t.frame_in().z() - wi).norm() < 1e-15);
                assert!((t.frame_out().z() - wo).norm() < 1e-15);
            }
        }
    }
    // Normal incidence and view: the Fresnel part is R_0 times the identity.
    let n = [0.0, 0.0, 1.0];
    let m = Conductor::new(0.5, 0.183, 3.424)
        .unwrap()
        .transform(n, n)
        .unwrap();
    let m = m.matrix().matrix();
    assert!((m - Matrix4::identity() * m[(0, 0)]).amax() < 1e-15 * m[(0, 0)]);
}

#[test]
fn bad_input_is_an_error() {
    let model = PolarizedPlastic::new(0.3, 1.5, 0.5).unwrap();
    let up = [0.0, 0.0, 1.0];
    assert!(matches!(
        model.transform([0.0, 0.0, 1.1], up),
        Err(Error::NonUnitDirection { .. })
    ));
    assert!(matches!(
        model.transform(up, [f64::NAN, 0.0, 1.0]),
        Err(Error::NonFinite { .. })
    ));
    assert!(model.transform([0.0, 0.0, 0.0], up).is_err());
    assert!(model.transform(up, [f64::INFINITY, 0.0, 0.0]).is_err());
    let msg = |e: Error| e.to_string();
    assert!(msg(PolarizedPlastic::new(-0.1, 1.5, 0.5).unwrap_err()).contains("-0.1"));
    assert!(msg(PolarizedPlastic::new(0.1, f64::NAN, 0.5).unwrap_err()).contains("NaN"));
    assert!(msg(PolarizedPlastic::new(0.1, 1.5, 1.5).unwrap_err()).contains("albedo"));
    assert!(msg(Conductor::new(0.1, 0.2, -3.0).unwrap_err()).contains("-3"));
    assert!(msg(Conductor::new(0.1, -0.2, 3.0).unwrap_err()).contains("-0.2"));
    assert!(msg(Conductor::new(f64::INFINITY, 0.2, 3.0).unwrap_err()).contains("inf"));
    assert!(ComplexIor::new(0.0, 0.0).is_err());
    assert!(Lambertian::new(f64::NAN).is_err());
}

#[test]
fn diffuse_depolarizes() {
    let lam = Lambertian::new(0.8).unwrap();
    let (wi, wo) = (unit(0.4, 1.0), unit(1.2, -2.0));
    let t = lam.transform(arr(&wi), arr(&wo)).unwrap();
    let out = t
        .matrix()
        .apply(&StokesComponents::new([1.0, 0.3, -0.5, 0.7]).unwrap());
    assert!((out.s0() - 0.8 / PI * wi[2]).abs() < 1e-15);
    assert_eq!([out.s1(), out.s2(), out.s3()], [0.0, 0.0, 0.0]);
    // The plastic's diffuse part adds only to the (0, 0) entry.
    let plastic = PolarizedPlastic::new(0.3, 1.5, 0.8).unwrap();
    let spec = plastic.specular().transform(arr(&wi), arr(&wo)).unwrap();
    let all = plastic.transform(arr(&wi), arr(&wo)).unwrap();
    let diff = all.matrix().matrix() - spec.matrix().matrix();
    let mut expect = Matrix4::zeros();
    expect[(0, 0)] = 0.8 / PI * wi[2];
    assert!((diff - expect).amax() < 1e-15);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn frame_independence(
        wi in upper(), wo in upper(), ai in -4.0f64..4.0, ao in -4.0f64..4.0,
        s in polarized_input(),
    ) {
        let gi = frame_on(&wi, ai);
        let go = frame_on(&wo, ao);
        for (name, model) in models() {
            let t = model.transform(arr(&wi), arr(&wo)).unwrap();
            let direct = model.matrix_in(&gi, &go).unwrap().matrix() * s;
            // Convert s from G_i to the model's input frame, apply, convert back to G_o,
            // with the rotators of PSH (14) built from the frames here.
            let rot = |from: &Frame, to: &Frame| {
                let a = from.angle_to(to).unwrap();
                psh::stokes::rotator(a).unwrap().matrix()
            };
            let via = rot(t.frame_out(), &go) * t.matrix().matrix() * rot(&gi, t.frame_in()) * s;
            let scale = t.matrix().matrix().amax().max(1e-300);
            prop_assert!((direct - via).amax() <= 1e-12 * scale, "{name}");
        }
    }

    #[test]
    fn models_are_realizable_and_reciprocal(
        wi in upper(), wo in upper(), s in polarized_input(),
    ) {
        for (name, model) in models() {
            let m = model.transform(arr(&wi), arr(&wo)).unwrap().matrix().matrix();
            let scale = m.amax().max(1e-300);
            prop_assert!(m[(0, 0)] >= 0.0, "{name}");
            prop_assert!(realizable(&(m * s), scale), "{name}: {}", m * s);
            // Reciprocity of the scalar BRDF f = P / cos_i (Helmholtz).
            let f_io = m00(model.as_ref(), &wi, &wo) / wi[2];
            let f_oi = m00(model.as_ref(), &wo, &wi) / wo[2];
            prop_assert!((f_io - f_oi).abs() <= 1e-12 * f_io.abs().max(f_oi.abs()), "{name}");
        }
    }
}
