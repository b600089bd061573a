//! Unit directions on the sphere: validation, spherical angles (theta from +z, phi from
//! +x towards +y) and the spherical Fibonacci lattice.

use crate::error::{finite, Error, Result};

/// Tolerance on `|w| - 1` for a direction to count as a unit vector.
pub const UNIT_TOLERANCE: f64 = 1e-10;

/// Checks a direction: finite components and unit norm within [`UNIT_TOLERANCE`].
pub fn check_direction(w: [f64; 3]) -> Result<[f64; 3]> {
    for &c in &w {
        finite("direction component", c)?;
    }
    let norm = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    if (norm - 1.0).abs() > UNIT_TOLERANCE {
        return Err(Error::NonUnitDirection { value: w, norm });
    }
    Ok(w)
}

/// Checks a polar angle: finite and in `[0, pi]`.
pub fn check_theta(theta: f64) -> Result<f64> {
    crate::error::finite("theta", theta)?;
    if !(0.0..=std::f64::consts::PI).contains(&theta) {
        return Err(Error::invalid(
            "theta",
            theta.to_string(),
            "the polar angle must lie in [0, pi]",
        ));
    }
    Ok(theta)
}

/// Spherical angles `(theta, phi)` of a unit direction (theta from +z, phi from +x
/// towards +y, in `(-pi, pi]`).
pub fn direction_angles(w: [f64; 3]) -> Result<(f64, f64)> {
    check_direction(w)?;
    let rho = w[0].hypot(w[1]);
    Ok((rho.atan2(w[2]), w[1].atan2(w[0])))
}

/// The unit direction of spherical angles `(theta, phi)`.
pub fn direction(theta: f64, phi: f64) -> [f64; 3] {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    [st * cp, st * sp, ct]
}

/// The golden angle `pi (3 - sqrt 5)`, the azimuth step of the Fibonacci lattice.
pub const GOLDEN_ANGLE: f64 = 2.399_963_229_728_653;

/// Point `k` of the spherical Fibonacci lattice of `n` points: `z_k = 1 - (2k + 1)/n`,
/// azimuth `k` golden angles (quasi-uniform; each point stands for `4 pi / n`).
pub fn fibonacci_point(k: usize, n: usize) -> [f64; 3] {
    let z = 1.0 - (2 * k + 1) as f64 / n as f64;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (sp, cp) = (GOLDEN_ANGLE * k as f64).sin_cos();
    [r * cp, r * sp, z]
}

/// The `n` points of the spherical Fibonacci lattice ([`fibonacci_point`]).
pub fn fibonacci_directions(n: usize) -> Vec<[f64; 3]> {
    (0..n).map(|k| fibonacci_point(k, n)).collect()
}
