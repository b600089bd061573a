//! Checks of the polygonal lights (`psh::lights::polygon`, SHG (3)-(18)).

use super::Check;
use crate::error::Result;
use crate::lights::grid::{Interpolation, Lattice, LightGrid, Refinement};
use crate::lights::polygon::cubature::SMALL_LIGHT;
use crate::lights::polygon::{reference, PolygonalLight, PolygonalLights};
use crate::lights::source::Order;

/// Band limit of the checks.
const LMAX: usize = 20;

/// The checks of the polygonal lights, in `psh verify`'s order.
pub fn checks() -> Vec<Check> {
    vec![
        Check {
            id: "polygon.coefficients_vs_quadrature",
            source: "SHG (3)-(5)",
            description: "SH coefficients l <= 20 of triangles and quads (small, large, near the horizon, clipped across it) vs adaptive Gauss-Legendre quadrature over the planar light to 1e-13 relative (max absolute error, unit radiance; relative errors are printed by tests/library/polygon.rs, at most 6e-15)",
            tolerance: 1e-12,
            proof: Some("proofs/polygon-lights.md"),
            run: coefficients_vs_quadrature,
        },
        Check {
            id: "polygon.gradient_vs_quadrature",
            source: "SHG (6)-(18)",
            description: "gradients l <= 20 (unclipped cases) vs adaptive quadrature of the x-derivative of the area integrand over the fixed light (Annen's parameterization, independent of the Reynolds boundary form), relative to the case's largest gradient",
            tolerance: 1e-9,
            proof: Some("proofs/polygon-lights.md"),
            run: gradient_vs_quadrature,
        },
        Check {
            id: "polygon.gradient_vs_fd",
            source: "SHG (6)-(18)",
            description: "gradients l <= 20 (all cases, clipped included) vs 8th-order central differences (step 2e-3 of the smallest distance from the point to a vertex, to the light's plane, or from a vertex to the horizon plane) of the analytic coefficients, relative to the case's largest gradient",
            tolerance: 1e-9,
            proof: Some("proofs/polygon-lights.md"),
            run: gradient_vs_fd,
        },
        Check {
            id: "polygon.hermite_order",
            source: "SHG Sec. 6.2",
            description: "cubic Hermite serendipity interpolation on uniform grids (levels 1-4 of a 0.4-wide box 0.6-1.2 from a triangle and a quad, l <= 8): 4 minus the least-squares slope of log(max error) vs log(h) (the slope must be >= 3.5; tests/library/polygon.rs prints it with the trilinear and zero-cross-derivative Hermite slopes)",
            tolerance: 0.5,
            proof: Some("proofs/polygon-lights.md"),
            run: hermite_order,
        },
        Check {
            id: "polygon.small_light_relative",
            source: "SHG (4), App. C",
            description: "the 1e-3 triangle at distance 1, l <= 20, and triangles at the small-light switch (diameter x max(l + 3, 24) = 1.5 x distance, face-on and at 80 degrees, l = 0, 4, 20): largest relative error of coefficients and gradients vs quadrature; small lights take a fixed 12x12 Duffy Gauss-Legendre rule over the planar light (the boundary sums cancel to O(T^2) from O(T) terms: 4.4e-12 for the 1e-3 triangle)",
            tolerance: 1e-14,
            proof: Some("proofs/small-polygon-lights.md"),
            run: small_light,
        },
    ]
}

/// A named case: light, shading point and optional horizon normal.
pub struct Case {
    /// What the case is, as the tests print it.
    pub name: &'static str,
    /// The light, unit radiance.
    pub light: PolygonalLight,
    /// The shading point.
    pub x: [f64; 3],
    /// The unit normal whose upper hemisphere the light is clipped to; `None`: unclipped.
    pub horizon: Option<[f64; 3]>,
}

/// The cases of the checks (also printed by the tests).
pub fn cases() -> Result<Vec<Case>> {
    let up = Some([0.0, 0.0, 1.0]);
    let tri = |v: [[f64; 3]; 3]| PolygonalLight::new(v.to_vec(), 1.0);
    let quad = |v: [[f64; 3]; 4]| PolygonalLight::new(v.to_vec(), 1.0);
    Ok(vec![
        Case {
            name: "small triangle (1e-3 at distance 1)",
            light: tri([[0.3, 0.2, 0.9], [0.301, 0.2, 0.9], [0.3, 0.2008, 0.9005]])?,
            x: [0.0; 3],
            horizon: None,
        },
        Case {
            name: "triangle",
            light: tri([[0.3, -0.2, 1.0], [1.0, 0.4, 1.2], [-0.2, 0.8, 0.9]])?,
            x: [0.1, 0.05, -0.1],
            horizon: None,
        },
        Case {
            name: "large triangle, 0.05 from its plane",
            light: tri([[-2.0, -1.5, 0.5], [2.5, -1.0, 0.5], [0.0, 2.0, 0.5]])?,
            x: [0.1, 0.2, 0.45],
            horizon: None,
        },
        Case {
            name: "quad",
            light: quad([
                [-0.5, 1.0, 0.2],
                [0.5, 1.1, 0.3],
                [0.6, 1.3, 1.2],
                [-0.4, 1.2, 1.1],
            ])?,
            x: [0.0, -0.2, 0.1],
            horizon: None,
        },
        Case {
            name: "large quad, 0.02 from its plane",
            light: quad([
                [-2.0, -2.0, 1.0],
                [2.0, -2.0, 1.0],
                [2.0, 2.0, 1.0],
                [-2.0, 2.0, 1.0],
            ])?,
            x: [0.3, -0.4, 0.98],
            horizon: None,
        },
        Case {
            name: "triangle just above the horizon",
            light: tri([[1.0, -0.5, 0.001], [1.0, 0.5, 0.002], [1.2, 0.0, 0.6]])?,
            x: [0.0; 3],
            horizon: up,
        },
        Case {
            name: "triangle across the horizon (clipped)",
            light: tri([[1.0, -0.5, -0.4], [1.0, 0.5, -0.2], [1.2, 0.0, 0.7]])?,
            x: [0.0; 3],
            horizon: up,
        },
        Case {
            name: "large quad across the horizon (clipped)",
            light: quad([
                [0.2, -2.0, -1.0],
                [0.2, 2.0, -1.0],
                [0.2, 2.0, 1.5],
                [0.2, -2.0, 1.5],
            ])?,
            x: [0.0, 0.1, 0.0],
            horizon: up,
        },
    ])
}

fn max_abs<'a>(v: impl Iterator<Item = &'a f64>) -> f64 {
    v.fold(0.0, |a, b| a.max(b.abs()))
}

/// The largest difference of the gradients relative to the largest reference entry.
fn relative_error(got: &[[f64; 3]], want: &[[f64; 3]]) -> f64 {
    let scale = max_abs(want.iter().flatten());
    let err = got
        .iter()
        .flatten()
        .zip(want.iter().flatten())
        .fold(0.0f64, |a, (g, w)| a.max((g - w).abs()));
    err / scale
}

/// Per case, the largest absolute coefficient error (unit radiance) and that error
/// relative to the case's largest coefficient.
pub fn coefficient_errors() -> Result<Vec<(&'static str, f64, f64)>> {
    cases()?
        .into_iter()
        .map(|c| {
            let mut lights = PolygonalLights::new(vec![c.light.clone()], LMAX)?;
            if let Some(n) = c.horizon {
                lights = lights.with_horizon(n)?;
            }
            let got = lights.field(c.x, Order::Values)?.coefficients;
            let want = reference::coefficients(&c.light, c.x, c.horizon, LMAX, 1e-13)?;
            let scale = max_abs(want.iter());
            let err = max_abs(
                got.iter()
                    .zip(&want)
                    .map(|(a, b)| a - b)
                    .collect::<Vec<_>>()
                    .iter(),
            );
            Ok((c.name, err, err / scale))
        })
        .collect()
}

fn coefficients_vs_quadrature() -> Result<f64> {
    Ok(coefficient_errors()?.iter().fold(0.0, |a, e| a.max(e.1)))
}

/// Name prefix of the small light, whose relative accuracy is checked separately.
const SMALL: &str = "small";

/// The largest error over the cases.
fn worst(errors: Vec<(&'static str, f64)>) -> f64 {
    errors.iter().fold(0.0, |a, e| a.max(e.1))
}

fn gradient_vs_quadrature() -> Result<f64> {
    Ok(worst(gradient_quadrature_errors()?))
}

fn gradient_vs_fd() -> Result<f64> {
    Ok(worst(gradient_fd_errors()?))
}

/// The small light: relative errors of its coefficients and gradients against the
/// quadrature (central differences would amplify the coefficients' relative error by
/// `|y - x| / h`, so they are not a test of it), and those of the lights at the switch.
fn small_light() -> Result<f64> {
    let mut all: Vec<(&'static str, f64)> = coefficient_errors()?
        .into_iter()
        .map(|(n, _, rel)| (n, rel))
        .collect();
    all.extend(gradient_quadrature_errors()?);
    let small = all
        .iter()
        .filter(|e| e.0.starts_with(SMALL))
        .fold(0.0f64, |a, e| a.max(e.1));
    Ok(switch_errors(true)?
        .iter()
        .fold(small, |a, e| a.max(e.2).max(e.3)))
}

/// Triangles at the small-light switch: for `l = 0, 4, 20`, face-on and at 80 degrees to
/// the line of sight, scaled to `diameter x max(l + 3, 24) = SMALL_LIGHT x distance`
/// times `1 - 1e-9` (`inside`: the area rule) or `1 + 1e-3` (the boundary method).
/// Per light: `(lmax, tilt in degrees, relative coefficient error, relative gradient
/// error)` against the quadrature.
pub fn switch_errors(inside: bool) -> Result<Vec<(usize, f64, f64, f64)>> {
    let factor = if inside { 1.0 - 1e-9 } else { 1.0 + 1e-3 };
    let mut out = Vec::new();
    for lmax in [0, 4, 20] {
        for tilt in [0.0f64, 80.0] {
            // An equilateral triangle (edge sqrt(3) x circumradius) about (0, 0, 1), seen
            // from the origin, tilted about the x axis; its circumradius `r` is fixed so
            // that `sqrt(3) r = ratio x (distance to the nearest vertex)` (a contraction).
            let (s, c) = tilt.to_radians().sin_cos();
            let ratio = factor * SMALL_LIGHT / (lmax + 3).max(24) as f64;
            let vertices = |r: f64| -> Vec<[f64; 3]> {
                (0..3)
                    .map(|k| {
                        let a = 2.0 * std::f64::consts::PI * k as f64 / 3.0 + 0.3;
                        let (px, py) = (r * a.cos(), r * a.sin());
                        [px, c * py, 1.0 + s * py]
                    })
                    .collect()
            };
            let nearest = |v: &[[f64; 3]]| {
                v.iter()
                    .map(|p| p.iter().map(|c| c * c).sum::<f64>().sqrt())
                    .fold(f64::INFINITY, f64::min)
            };
            let mut r = ratio / 3f64.sqrt();
            for _ in 0..20 {
                r = ratio * nearest(&vertices(r)) / 3f64.sqrt();
            }
            let v = vertices(r);
            let light = PolygonalLight::new(v, 1.0)?;
            let lights = PolygonalLights::new(vec![light.clone()], lmax)?;
            let got = lights.field([0.0; 3], Order::Gradients)?;
            let want = reference::coefficients(&light, [0.0; 3], None, lmax, 1e-13)?;
            let want_g = reference::gradients(&light, [0.0; 3], lmax, 1e-13)?;
            let err = got
                .coefficients
                .iter()
                .zip(&want)
                .fold(0.0f64, |a, (g, w)| a.max((g - w).abs()));
            out.push((
                lmax,
                tilt,
                err / max_abs(want.iter()),
                relative_error(&got.gradients, &want_g),
            ));
        }
    }
    Ok(out)
}

/// Per unclipped case, the gradient error against the quadrature, relative to the
/// largest gradient.
pub fn gradient_quadrature_errors() -> Result<Vec<(&'static str, f64)>> {
    let mut errors = Vec::new();
    for c in cases()?.into_iter().filter(|c| c.horizon.is_none()) {
        let lights = PolygonalLights::new(vec![c.light.clone()], LMAX)?;
        let got = lights.field(c.x, Order::Gradients)?.gradients;
        let want = reference::gradients(&c.light, c.x, LMAX, 1e-12)?;
        errors.push((c.name, relative_error(&got, &want)));
    }
    Ok(errors)
}

/// The 8th-order central difference of `f` at `x` along each axis with step `h`.
pub fn central_difference_8(
    f: &dyn Fn([f64; 3]) -> Result<Vec<f64>>,
    x: [f64; 3],
    h: f64,
) -> Result<Vec<[f64; 3]>> {
    const C: [f64; 4] = [4.0 / 5.0, -1.0 / 5.0, 4.0 / 105.0, -1.0 / 280.0];
    let mut out: Vec<[f64; 3]> = Vec::new();
    for i in 0..3 {
        for (k, c) in C.iter().enumerate() {
            let (mut a, mut b) = (x, x);
            a[i] += (k + 1) as f64 * h;
            b[i] -= (k + 1) as f64 * h;
            let (fa, fb) = (f(a)?, f(b)?);
            out.resize(fa.len(), [0.0; 3]);
            for (o, (u, v)) in out.iter_mut().zip(fa.iter().zip(&fb)) {
                o[i] += c * (u - v) / h;
            }
        }
    }
    Ok(out)
}

/// The distance from `x` to the plane of `light`.
fn plane_distance(light: &PolygonalLight, x: [f64; 3]) -> f64 {
    let (n, v) = (light.normal(), light.vertices()[0]);
    (0..3).map(|i| n[i] * (v[i] - x[i])).sum::<f64>().abs()
}

/// Per case, the gradient error against 8th-order central differences, relative to the
/// largest gradient.
pub fn gradient_fd_errors() -> Result<Vec<(&'static str, f64)>> {
    let mut errors = Vec::new();
    for c in cases()? {
        let mut lights = PolygonalLights::new(vec![c.light.clone()], LMAX)?;
        if let Some(n) = c.horizon {
            lights = lights.with_horizon(n)?;
        }
        let got = lights.field(c.x, Order::Gradients)?.gradients;
        let near = c
            .light
            .vertices()
            .iter()
            .map(|v| (0..3).map(|i| (v[i] - c.x[i]).powi(2)).sum::<f64>().sqrt())
            .fold(plane_distance(&c.light, c.x), f64::min);
        // Keep the stencil from moving a vertex across the horizon (a kink).
        let near = c.horizon.map_or(near, |n| {
            c.light
                .vertices()
                .iter()
                .map(|v| (0..3).map(|i| n[i] * (v[i] - c.x[i])).sum::<f64>().abs())
                .fold(near, f64::min)
        });
        let f = |x: [f64; 3]| lights.field(x, Order::Values).map(|f| f.coefficients);
        let want = central_difference_8(&f, c.x, 2e-3 * near)?;
        errors.push((c.name, relative_error(&got, &want)));
    }
    Ok(errors)
}

fn hermite_order() -> Result<f64> {
    let slopes = interpolation_slopes()?;
    Ok(4.0 - slopes[2].2)
}

/// An interpolation scheme, its `(h, largest error)` per grid level and the fitted slope.
pub type Convergence = (Interpolation, Vec<(f64, f64)>, f64);

/// For trilinear, zero-cross-derivative Hermite and serendipity interpolation: the
/// largest interpolation error at 64 points of the box at grid levels 1-4 and the
/// least-squares slope of `log(error)` against `log(h)`.
pub fn interpolation_slopes() -> Result<Vec<Convergence>> {
    let lights = PolygonalLights::new(
        vec![
            PolygonalLight::new(
                vec![[-0.4, -0.3, 1.0], [0.6, -0.2, 1.1], [0.0, 0.5, 0.9]],
                1.0,
            )?,
            PolygonalLight::new(
                vec![
                    [1.0, -0.5, -0.3],
                    [1.2, 0.5, -0.3],
                    [1.2, 0.5, 0.4],
                    [1.0, -0.5, 0.4],
                ],
                0.5,
            )?,
        ],
        8,
    )?;
    let (lo, hi) = ([-0.2, -0.2, -0.2], [0.2, 0.2, 0.2]);
    let r = crate::random::pseudo_random(3 * 64, 11);
    let points: Vec<[f64; 3]> = r
        .chunks_exact(3)
        .map(|c| std::array::from_fn(|i| 0.19 * c[i]))
        .collect();
    let exact: Vec<Vec<f64>> = points
        .iter()
        .map(|&x| lights.field(x, Order::Values).map(|f| f.coefficients))
        .collect::<Result<_>>()?;
    let mut out = Vec::new();
    for scheme in [
        Interpolation::Trilinear,
        Interpolation::Hermite,
        Interpolation::Serendipity,
    ] {
        let mut errs = Vec::new();
        for level in 1..=4 {
            let grid = LightGrid::build(
                &lights,
                Lattice::new(lo, hi, level)?,
                &points,
                Refinement::Uniform,
            )?;
            let mut e = 0.0f64;
            for (x, want) in points.iter().zip(&exact) {
                let got = grid.interpolate_with(*x, scheme)?;
                e = got
                    .iter()
                    .zip(want)
                    .fold(e, |a, (g, w)| a.max((g - w).abs()));
            }
            errs.push((0.4 / (1u32 << level) as f64, e));
        }
        let n = errs.len() as f64;
        let (lx, ly): (Vec<f64>, Vec<f64>) = errs.iter().map(|(h, e)| (h.ln(), e.ln())).unzip();
        let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
        let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
        let sxx: f64 = lx.iter().map(|x| (x - mx) * (x - mx)).sum();
        out.push((scheme, errs, sxy / sxx));
    }
    Ok(out)
}
