//! Polygonal lights (SHG): invariants of the coefficients and gradients, clipping, bad
//! input, and the per-case errors of the `psh verify` checks (printed).

use nalgebra::{Rotation3, Vector3};
use proptest::prelude::*;
use psh::lights::Order;
use psh::lights::{PolygonalLight, PolygonalLights};
use psh::verify::polygon::{
    coefficient_errors, gradient_fd_errors, gradient_quadrature_errors, switch_errors,
};
use std::f64::consts::PI;

/// The per-case errors behind `psh verify --filter polygon`, for the record.
#[test]
fn per_case_errors() {
    for (name, abs, rel) in coefficient_errors().unwrap() {
        println!("coefficients  {name:<45} abs {abs:.2e} rel {rel:.2e}");
        assert!(abs < 1e-12, "{name}");
        // Small lights by the area rule: relative accuracy too.
        assert!(!name.starts_with("small") || rel < 1e-14, "{name}");
    }
    for (name, rel) in gradient_quadrature_errors().unwrap() {
        println!("grad vs quad  {name:<45} rel {rel:.2e}");
        assert!(!name.starts_with("small") || rel < 1e-14, "{name}");
    }
    for (name, rel) in gradient_fd_errors().unwrap() {
        println!("grad vs FD    {name:<45} rel {rel:.2e}");
    }
}

/// At the small-light switch (`proofs/small-polygon-lights.md`): just inside, the fixed
/// 12x12 area rule agrees with the adaptive quadrature to rounding (its truncation error
/// is far below it); just outside, the boundary method stays within 1e-12 relative.
#[test]
fn small_light_switch() {
    for inside in [true, false] {
        for (lmax, tilt, rel, rel_g) in switch_errors(inside).unwrap() {
            println!(
                "inside {inside:<5} l <= {lmax:<2} tilt {tilt:>2}: coefficients {rel:.1e}, gradients {rel_g:.1e}"
            );
            let tol = if inside { 1e-14 } else { 1e-12 };
            assert!(rel < tol && rel_g < tol, "{inside} {lmax} {tilt}");
        }
    }
}

fn field(v: Vec<[f64; 3]>, x: [f64; 3], lmax: usize) -> psh::lights::LightField {
    PolygonalLights::new(vec![PolygonalLight::new(v, 1.0).unwrap()], lmax)
        .unwrap()
        .field(x, Order::Gradients)
        .unwrap()
}

/// A random triangle in front of the origin (z between 0.5 and 1.5).
fn triangle() -> impl Strategy<Value = Vec<[f64; 3]>> {
    prop::array::uniform3(prop::array::uniform3(-0.6..0.6f64)).prop_filter_map("degenerate", |p| {
        let v: Vec<[f64; 3]> = p.iter().map(|q| [q[0], q[1], 1.0 + 0.5 * q[2]]).collect();
        PolygonalLight::new(v.clone(), 1.0).ok().map(|_| v)
    })
}

fn band_energy(c: &[f64], l: usize) -> f64 {
    c[l * l..(l + 1) * (l + 1)].iter().map(|x| x * x).sum()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// `L_00 = Omega / (2 sqrt(pi))` with the solid angle of the planar triangle by Van
    /// Oosterom-Strackee from its raw vertices; the band energies `sum_m L_lm^2` are
    /// invariant when polygon and point rotate together; gradients rotate as vectors.
    #[test]
    fn l0_and_rotation_invariance(v in triangle(), axis in prop::array::uniform3(-1.0..1.0f64), angle in 0.1..3.0f64) {
        prop_assume!(Vector3::from(axis).norm() > 0.1);
        let lmax = 8;
        let f = field(v.clone(), [0.0; 3], lmax);
        let [a, b, c] = [v[0], v[1], v[2]].map(|p| Vector3::from(p).normalize());
        let omega = 2.0 * a.dot(&b.cross(&c)).abs().atan2(1.0 + a.dot(&b) + b.dot(&c) + c.dot(&a));
        prop_assert!((f.coefficients[0] - omega / (2.0 * PI.sqrt())).abs() < 1e-15);
        let r = Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(Vector3::from(axis)), angle);
        let x = [0.3, -0.2, 0.1];
        let vr: Vec<[f64; 3]> = v.iter().map(|p| (r * (Vector3::from(*p) + Vector3::from(x))).into()).collect();
        let g = field(vr, (r * Vector3::from(x)).into(), lmax);
        let f = field(v.iter().map(|p| [p[0] + x[0], p[1] + x[1], p[2] + x[2]]).collect(), x, lmax);
        for l in 0..=lmax {
            let (e0, e1) = (band_energy(&f.coefficients, l), band_energy(&g.coefficients, l));
            prop_assert!((e0 - e1).abs() < 1e-13, "l = {l}: {e0} vs {e1}");
        }
        // |grad L_00| is rotation invariant.
        let n0 = Vector3::from(f.gradients[0]).norm();
        let n1 = Vector3::from(g.gradients[0]).norm();
        prop_assert!((n0 - n1).abs() < 1e-13);
    }

    /// Splitting a quad along a diagonal: coefficients and gradients add; a cyclic shift
    /// or reversal of the vertices changes nothing.
    #[test]
    fn additivity_and_vertex_order(v in triangle(), t in 0.2..0.8f64) {
        let lmax = 10;
        let x = [0.1, 0.05, -0.2];
        // A fourth vertex beyond the edge v1 v2, in the plane, keeping the quad convex.
        let d: [f64; 3] = std::array::from_fn(|i| (1.0 - t) * v[1][i] + t * v[2][i] - v[0][i]);
        let p3: [f64; 3] = std::array::from_fn(|i| v[0][i] + 1.5 * d[i]);
        let quad = vec![v[0], v[1], p3, v[2]];
        prop_assume!(PolygonalLight::new(quad.clone(), 1.0).is_ok());
        let q = field(quad, x, lmax);
        let a = field(vec![v[0], v[1], p3], x, lmax);
        let b = field(vec![v[0], p3, v[2]], x, lmax);
        let scale = q.coefficients.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        for k in 0..q.coefficients.len() {
            prop_assert!((q.coefficients[k] - a.coefficients[k] - b.coefficients[k]).abs() < 1e-13 * scale.max(1.0));
            for i in 0..3 {
                prop_assert!((q.gradients[k][i] - a.gradients[k][i] - b.gradients[k][i]).abs() < 1e-12);
            }
        }
        let shifted = field(vec![v[1], v[2], v[0]], x, lmax);
        let reversed = field(vec![v[2], v[1], v[0]], x, lmax);
        let t0 = field(v.clone(), x, lmax);
        for k in 0..t0.coefficients.len() {
            prop_assert!((t0.coefficients[k] - shifted.coefficients[k]).abs() < 1e-14);
            prop_assert!((t0.coefficients[k] - reversed.coefficients[k]).abs() < 1e-14);
        }
    }
}

/// A light wholly below the horizon contributes nothing; wholly above, clipping changes
/// nothing.
#[test]
fn horizon_clipping_extremes() {
    let light = PolygonalLight::new(
        vec![[1.0, -0.5, 0.2], [1.0, 0.5, 0.3], [1.2, 0.0, 0.8]],
        2.0,
    )
    .unwrap();
    let free = PolygonalLights::new(vec![light.clone()], 6).unwrap();
    let up = free.clone().with_horizon([0.0, 0.0, 1.0]).unwrap();
    let down = free.clone().with_horizon([0.0, 0.0, -1.0]).unwrap();
    let x = [0.0; 3];
    assert_eq!(
        free.field(x, Order::Gradients).unwrap(),
        up.field(x, Order::Gradients).unwrap()
    );
    let d = down.field(x, Order::Gradients).unwrap();
    assert!(d.coefficients.iter().all(|c| *c == 0.0));
    assert!(d.gradients.iter().flatten().all(|c| *c == 0.0));
}

/// Degenerate, non-planar, non-convex and non-finite polygons, points on the light's
/// plane, a bad horizon, Hessians: errors naming the value.
#[test]
fn bad_input_is_an_error() {
    let err = |v: Vec<[f64; 3]>| PolygonalLight::new(v, 1.0).unwrap_err().to_string();
    assert!(err(vec![[0.0; 3], [1.0, 0.0, 0.0]]).contains("at least 3"));
    assert!(err(vec![[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]).contains("degenerate"));
    assert!(err(vec![[0.0; 3], [0.0; 3], [1.0, 1.0, 0.0]]).contains("degenerate"));
    assert!(err(vec![
        [0.0; 3],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.1],
        [0.0, 1.0, 0.0]
    ])
    .contains("non-planar"));
    assert!(err(vec![
        [0.0; 3],
        [2.0, 0.0, 0.0],
        [1.0, 0.5, 0.0],
        [1.0, 2.0, 0.0]
    ])
    .contains("non-convex"));
    // A pentagram: every turn has the same sign but the boundary winds twice.
    let star: Vec<[f64; 3]> = (0..5)
        .map(|k| {
            let a = 2.0 * PI * (2 * k) as f64 / 5.0;
            [a.cos(), a.sin(), 0.0]
        })
        .collect();
    assert!(err(star).contains("winds"));
    assert!(
        PolygonalLight::new(vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, f64::NAN, 0.0]], 1.0).is_err()
    );
    assert!(PolygonalLight::new(
        vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        f64::INFINITY
    )
    .is_err());
    let light =
        PolygonalLight::new(vec![[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]], 1.0).unwrap();
    let lights = PolygonalLights::new(vec![light], 4).unwrap();
    let on_plane = lights
        .field([5.0, 5.0, 1.0], Order::Values)
        .unwrap_err()
        .to_string();
    assert!(on_plane.contains("[5.0, 5.0, 1.0]") && on_plane.contains("plane"));
    assert!(lights.field([0.1, 0.1, f64::NAN], Order::Values).is_err());
    assert!(lights
        .field([0.1, 0.1, 0.0], Order::Hessians)
        .unwrap_err()
        .to_string()
        .contains("Hessians"));
    assert!(lights.clone().with_horizon([0.0, 0.0, 2.0]).is_err());
    // Just off the plane: finite.
    let f = lights
        .field([0.2, 0.2, 1.0 - 1e-6], Order::Gradients)
        .unwrap();
    assert!(f
        .coefficients
        .iter()
        .chain(f.gradients.iter().flatten())
        .all(|c| c.is_finite()));
}

/// The measured orders of the grid interpolants (the check `polygon.hermite_order`
/// requires the serendipity slope to be at least 3.5).
#[test]
fn interpolation_orders() {
    let slopes = psh::verify::polygon::interpolation_slopes().unwrap();
    for (scheme, errs, slope) in &slopes {
        println!("{scheme:?}: slope {slope:.2}, (h, max error) {errs:?}");
    }
    assert!(slopes[0].2 > 1.7 && slopes[2].2 > 3.5);
}
