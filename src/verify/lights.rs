//! Checks of the spherical lights (`psh::lights::spherical`, SHH (2)-(8), (15), (20)).

use super::Check;
use crate::error::Result;
use crate::lights::spherical::{half_angle, LightField, Order, SphericalLight, SphericalLights};
use crate::sh::grid::GaussLegendre;
use crate::sh::harmonics::ShEvaluator;
use crate::sh::solid::hessian_index;
use std::f64::consts::PI;

pub fn checks() -> Vec<Check> {
    vec![
        Check {
            id: "lights.coefficients_quadrature",
            source: "SHH (2)-(5)",
            description: "SH coefficients l <= 12 of single lights (near, far, tiny) vs Gauss-Legendre x uniform quadrature of the real SH over the light's cap (relative to the largest coefficient)",
            tolerance: 1e-13,
            proof: Some("proofs/spherical-lights.md"),
            run: coefficients_quadrature,
        },
        Check {
            id: "lights.gradient_fd",
            source: "SHH (6)-(8)",
            description: "gradients of the summed coefficients of 5 lights, l <= 8, vs central differences (step 1e-5 |y - x|) of the coefficients (relative to the largest gradient)",
            tolerance: 1e-8,
            proof: Some("proofs/spherical-lights.md"),
            run: gradient_fd,
        },
        Check {
            id: "lights.hessian_fd",
            source: "SHH (15), (20)",
            description: "Hessians of the summed coefficients of 5 lights, l <= 8, vs central differences (step 1e-5 |y - x|) of the gradients (relative to the largest Hessian)",
            tolerance: 1e-8,
            proof: Some("proofs/spherical-lights.md"),
            run: hessian_fd,
        },
        Check {
            id: "lights.half_angle_fd",
            source: "SHH (5), (8), Sec. 4.4",
            description: "gradient and Hessian of a(x) = asin(r/|y-x|) vs central differences (relative)",
            tolerance: 1e-8,
            proof: Some("proofs/spherical-lights.md"),
            run: half_angle_fd,
        },
        Check {
            id: "lights.adaptive_error_falls",
            source: "SHH Sec. 5, Fig. 10",
            description: "adaptive grids (E_abs thresholds 1, 0.3, 0.1; finest level 6) on the demo scene (32x32 floor points, 12 near and 20 far lights, l <= 4): largest ratio of successive mean interpolation errors |L - L_exact| at the shading points (must be < 1: the error falls with the threshold)",
            tolerance: 0.5,
            proof: None,
            run: adaptive_error_falls,
        },
    ]
}

fn adaptive_error_falls() -> Result<f64> {
    use crate::lights::grid::{Lattice, LightGrid, Metric, Refinement};
    use crate::lights::scene::{demo_scene, exact_coefficients, grid_errors};
    let scene = demo_scene(32, 12, 20, 5)?;
    let lights = SphericalLights::new(scene.lights.clone(), 4)?;
    let exact = exact_coefficients(&lights, &scene.points)?;
    let mut errors = Vec::new();
    for threshold in [1.0, 0.3, 0.1] {
        let lattice = Lattice::new(scene.bounds.0, scene.bounds.1, 6)?;
        let refinement = Refinement::Adaptive {
            metric: Metric::Absolute,
            threshold,
        };
        let grid = LightGrid::build(&lights, lattice, &scene.points, refinement)?;
        errors.push(grid_errors(&grid, &scene.points, &exact)?.1);
    }
    Ok(errors.windows(2).map(|w| w[1] / w[0]).fold(0.0, f64::max))
}

/// Lights near and far from the origin and one tiny one (a cap of 1e-4 rad).
pub(crate) fn test_lights() -> Result<Vec<SphericalLight>> {
    [
        ([0.2, 1.0, 0.3], 0.4, 1.0),
        ([-3.0, 0.5, 2.0], 1.0, 2.0),
        ([0.0, 0.0, -1.5], 0.3, 0.5),
        ([40.0, -30.0, 10.0], 2.0, 3.0),
        ([0.1, -0.7, 0.0], 1e-4 * 0.7072, 1.0),
    ]
    .into_iter()
    .map(|(c, r, e)| SphericalLight::new(c, r, e))
    .collect()
}

fn coefficients_quadrature() -> Result<f64> {
    let lmax = 12;
    let ev = ShEvaluator::new(lmax)?;
    let gl = GaussLegendre::new(lmax + 1)?;
    let n_phi = 2 * lmax + 2;
    let mut worst = 0.0f64;
    let x = [0.05, -0.1, 0.02];
    for light in test_lights()? {
        let field = SphericalLights::new(vec![light], lmax)?.field(x, Order::Values)?;
        let c = light.center();
        let d = [c[0] - x[0], c[1] - x[1], c[2] - x[2]];
        let dist = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let w = d.map(|v| v / dist);
        // An orthonormal frame (u, v, w).
        let t = if w[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let dot = t[0] * w[0] + t[1] * w[1] + t[2] * w[2];
        let u = [t[0] - dot * w[0], t[1] - dot * w[1], t[2] - dot * w[2]];
        let un = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
        let u = u.map(|c| c / un);
        let v = [
            w[1] * u[2] - w[2] * u[1],
            w[2] * u[0] - w[0] * u[2],
            w[0] * u[1] - w[1] * u[0],
        ];
        // cos of the polar angle about w runs over [alpha, 1]: 1 - alpha = s^2 / (1 + alpha).
        let s = light.radius() / dist;
        let alpha = ((dist - light.radius()) * (dist + light.radius())).sqrt() / dist;
        let width = s * s / (1.0 + alpha);
        let mut dirs = Vec::new();
        let mut weights = Vec::new();
        for (j, &xj) in gl.cos_theta.iter().enumerate() {
            // Node of [alpha, 1]: 1 - width (1 - xj)/2; sin from the same half-width.
            let one_minus = width * (1.0 - xj) / 2.0;
            let ct = 1.0 - one_minus;
            let st = (one_minus * (2.0 - one_minus)).sqrt();
            for k in 0..n_phi {
                let ph = 2.0 * PI * k as f64 / n_phi as f64;
                let (sp, cp) = ph.sin_cos();
                dirs.push(std::array::from_fn(|i| {
                    ct * w[i] + st * (cp * u[i] + sp * v[i])
                }));
                weights.push(gl.weights[j] * width / 2.0 * 2.0 * PI / n_phi as f64);
            }
        }
        let n = ev.len();
        let mut y = vec![0.0; dirs.len() * n];
        ev.real_batch(&dirs, &mut y)?;
        let mut quad = vec![0.0; n];
        for (row, wt) in y.chunks_exact(n).zip(&weights) {
            for (q, v) in quad.iter_mut().zip(row) {
                *q += light.radiance() * wt * v;
            }
        }
        let scale = quad.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        for (a, b) in field.coefficients.iter().zip(&quad) {
            worst = worst.max((a - b).abs() / scale);
        }
    }
    Ok(worst)
}

fn field_at(lights: &SphericalLights, x: [f64; 3]) -> Result<LightField> {
    lights.field(x, Order::Hessians)
}

/// Relative error of central differences of the coefficients (`second = false`) or of
/// the gradients (`second = true`) at a few shading points.
fn light_fd(second: bool) -> Result<f64> {
    let lights = SphericalLights::new(test_lights()?[..4].to_vec(), 8)?;
    let mut worst = 0.0f64;
    for x in [
        [0.0, 0.0, 0.0],
        [0.5, 0.0, -0.5],
        [-0.5, 0.0, 0.5],
        [1.0, 2.0, -0.2],
    ] {
        let f0 = field_at(&lights, x)?;
        let step = 1e-5;
        let scale = if second {
            f0.hessians
                .iter()
                .flatten()
                .fold(0.0f64, |a, b| a.max(b.abs()))
        } else {
            f0.gradients
                .iter()
                .flatten()
                .fold(0.0f64, |a, b| a.max(b.abs()))
        };
        for i in 0..3 {
            let (mut a, mut b) = (x, x);
            a[i] += step;
            b[i] -= step;
            let (fa, fb) = (field_at(&lights, a)?, field_at(&lights, b)?);
            for k in 0..f0.coefficients.len() {
                if second {
                    for j in 0..3 {
                        let fd = (fa.gradients[k][j] - fb.gradients[k][j]) / (2.0 * step);
                        worst = worst.max((fd - f0.hessians[k][hessian_index(i, j)]).abs() / scale);
                    }
                } else {
                    let fd = (fa.coefficients[k] - fb.coefficients[k]) / (2.0 * step);
                    worst = worst.max((fd - f0.gradients[k][i]).abs() / scale);
                }
            }
        }
    }
    Ok(worst)
}

fn gradient_fd() -> Result<f64> {
    light_fd(false)
}

fn hessian_fd() -> Result<f64> {
    light_fd(true)
}

fn half_angle_fd() -> Result<f64> {
    let r = 0.4;
    let mut worst = 0.0f64;
    let offset = |x: [f64; 3]| {
        let d = [0.2 - x[0], 1.0 - x[1], 0.3 - x[2]];
        (d, (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt())
    };
    for x in [[0.0, 0.0, 0.0], [0.5, 0.0, -0.5], [-0.3, 0.2, 0.1]] {
        let (d, dist) = offset(x);
        let (_, g, h) = half_angle(d, dist, r);
        let step = 1e-5;
        let gs = g.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        let hs = h.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        for i in 0..3 {
            let (mut a, mut b) = (x, x);
            a[i] += step;
            b[i] -= step;
            let (da, na) = offset(a);
            let (db, nb) = offset(b);
            let (aa, ga, _) = half_angle(da, na, r);
            let (ab, gb, _) = half_angle(db, nb, r);
            worst = worst.max(((aa - ab) / (2.0 * step) - g[i]).abs() / gs);
            for j in 0..3 {
                let fd = (ga[j] - gb[j]) / (2.0 * step);
                worst = worst.max((fd - h[hessian_index(i, j)]).abs() / hs);
            }
        }
    }
    Ok(worst)
}
