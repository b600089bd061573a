//! A procedural scene of many triangular lights over a floor of shading points, for the
//! demo (`psh polygon-lights-demo`).
//!
//! The near lights hang 0.3-0.6 above the floor, tilted at most 5 degrees along x and y,
//! so that their planes (where the two-sided light's field has a kink) stay clear of the
//! grid box; four tall wall lights beyond the floor cross its horizon and are clipped.

use crate::error::Result;
use crate::lights::demo_scene::floor_points;
use crate::lights::polygon::PolygonalLight;
use crate::random::pseudo_random;

/// Shading points and lights.
#[derive(Clone, Debug)]
pub struct PolygonScene {
    /// An `n x n` floor grid on `z = 0`, `[-1, 1]^2`, row by row.
    pub points: Vec<[f64; 3]>,
    /// Points per side of the floor.
    pub floor_side: usize,
    /// The near triangles, then the four walls.
    pub lights: Vec<PolygonalLight>,
    /// The grid box `[-1, 1]^2 x [-0.05, 0.05]`.
    pub bounds: ([f64; 3], [f64; 3]),
    /// The floor's normal (the horizon of every shading point).
    pub normal: [f64; 3],
}

/// The scene with `near` random triangles (edges 0.1-0.3, radiance 1-2) and four walls.
pub fn polygon_scene(floor_side: usize, near: usize, seed: u64) -> Result<PolygonScene> {
    let points = floor_points(floor_side);
    let r = pseudo_random(8 * near, seed);
    let mut lights = Vec::with_capacity(near + 4);
    for c in r.chunks_exact(8) {
        let center = [0.9 * c[0], 0.9 * c[1], 0.45 + 0.15 * c[2]];
        let size = 0.2 + 0.1 * c[3];
        let (tx, ty) = (0.087 * c[4], 0.087 * c[5]);
        let spin = std::f64::consts::PI * c[6];
        let vertices = (0..3)
            .map(|k| {
                let a = spin + 2.0 * std::f64::consts::PI * k as f64 / 3.0;
                let (dx, dy) = (0.6 * size * a.cos(), 0.6 * size * a.sin());
                [
                    center[0] + dx,
                    center[1] + dy,
                    center[2] + tx * dx + ty * dy,
                ]
            })
            .collect();
        lights.push(PolygonalLight::new(vertices, 1.5 + 0.5 * c[7])?);
    }
    for k in 0..4 {
        let (s, c) = (std::f64::consts::FRAC_PI_2 * k as f64).sin_cos();
        let at = |u: f64, z: f64| [1.5 * c - u * s, 1.5 * s + u * c, z];
        lights.push(PolygonalLight::new(
            vec![at(-0.8, -0.5), at(0.8, -0.5), at(0.8, 0.9), at(-0.8, 0.9)],
            0.3,
        )?);
    }
    Ok(PolygonScene {
        points,
        floor_side,
        lights,
        bounds: ([-1.0, -1.0, -0.05], [1.0, 1.0, 0.05]),
        normal: [0.0, 0.0, 1.0],
    })
}
