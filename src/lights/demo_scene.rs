//! A procedural many-light scene for the demo and the checks of the adaptive grid: shading
//! points on a floor, small lights just above it (near field) and large lights far away
//! (SHH Sec. 6.2 in miniature).
//!
//! Every grid point must lie outside every light (the coefficients are undefined inside,
//! and [`LightGrid::build`] reports such a point as an error), so the grid box, a thin
//! slab around the floor, stays below the lowest near light.

use crate::lights::grid::{Interpolation, LightGrid};
use crate::lights::source::LightSource;

use crate::error::Result;
use crate::lights::source::Order;
use crate::lights::spherical::SphericalLight;
use crate::random::pseudo_random;

/// Shading points and lights of the scene.
#[derive(Clone, Debug)]
pub struct LightScene {
    /// Shading points: an `n x n` floor grid on `z = 0`, `[-1, 1]^2`, row by row.
    pub points: Vec<[f64; 3]>,
    /// Points per side of the floor.
    pub floor_side: usize,
    /// The near lights, then the far ones.
    pub lights: Vec<SphericalLight>,
    /// The box enclosing the shading points (the grid's root voxel).
    pub bounds: ([f64; 3], [f64; 3]),
}

/// The scene with `near` lights of radius 0.02-0.05 at heights 0.08-0.2 above the floor
/// and `far` lights of radius 1-3 at distance 15-40, from a fixed seed; the grid box is
/// `[-1, 1]^2 x [-0.05, 0.05]`.
pub fn light_scene(floor_side: usize, near: usize, far: usize, seed: u64) -> Result<LightScene> {
    let points = floor_points(floor_side);
    let r = pseudo_random(3 * (near + far), seed);
    let mut k = 0;
    let mut next = || {
        k += 1;
        r[k - 1]
    };
    let mut lights = Vec::with_capacity(near + far);
    for _ in 0..near {
        let (x, y, h) = (0.9 * next(), 0.9 * next(), next());
        let radius = 0.035 + 0.015 * h;
        // Keep the light off the sphere of shading points.
        let (x, y) = if x.hypot(y) < 0.45 {
            (x.signum() * 0.5, y)
        } else {
            (x, y)
        };
        lights.push(SphericalLight::new([x, y, 0.14 + 0.06 * h], radius, 1.0)?);
    }
    for _ in 0..far {
        let (a, b, c) = (next(), next(), next());
        let dist = 27.5 + 12.5 * c;
        let theta = 0.45 * std::f64::consts::PI * (a + 1.0) / 2.0;
        let phi = std::f64::consts::PI * b;
        let dir = [
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        ];
        lights.push(SphericalLight::new(dir.map(|d| d * dist), 2.0 + c, 5.0)?);
    }
    Ok(LightScene {
        points,
        floor_side,
        lights,
        bounds: ([-1.0, -1.0, -0.05], [1.0, 1.0, 0.05]),
    })
}

/// An `n x n` grid of shading points on the floor `z = 0`, `[-1, 1]^2`, row by row (cell
/// centers).
pub(crate) fn floor_points(n: usize) -> Vec<[f64; 3]> {
    let c = |i: usize| -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
    (0..n * n).map(|k| [c(k % n), c(k / n), 0.0]).collect()
}

/// Interpolation errors of a grid against the per-point exact coefficients `exact` (one
/// row per shading point): `(mean squared error per coefficient, mean |L - L_exact|_2,
/// per-point |L - L_exact|_2)`.
pub fn grid_errors(
    grid: &LightGrid,
    points: &[[f64; 3]],
    exact: &[Vec<f64>],
) -> Result<(f64, f64, Vec<f64>)> {
    grid_errors_with(grid, points, exact, Interpolation::Hermite)
}

/// [`grid_errors`] with the interpolation `scheme`.
pub fn grid_errors_with(
    grid: &LightGrid,
    points: &[[f64; 3]],
    exact: &[Vec<f64>],
    scheme: Interpolation,
) -> Result<(f64, f64, Vec<f64>)> {
    let mut sq = 0.0;
    let mut count = 0usize;
    let mut per_point = Vec::with_capacity(points.len());
    for (x, e) in points.iter().zip(exact) {
        let got = grid.interpolate_with(*x, scheme)?;
        let d2: f64 = got.iter().zip(e).map(|(a, b)| (a - b) * (a - b)).sum();
        sq += d2;
        count += e.len();
        per_point.push(d2.sqrt());
    }
    let mean = per_point.iter().sum::<f64>() / per_point.len().max(1) as f64;
    Ok((sq / count.max(1) as f64, mean, per_point))
}

/// The exact coefficients at every shading point (SHH (2) or SHG (4), all lights).
pub fn exact_coefficients(lights: &impl LightSource, points: &[[f64; 3]]) -> Result<Vec<Vec<f64>>> {
    points
        .iter()
        .map(|&x| lights.field(x, Order::Values).map(|f| f.coefficients))
        .collect()
}
