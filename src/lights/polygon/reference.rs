//! The reference for the checks: SH coefficients (and gradients) of a polygonal light by
//! adaptive quadrature over the planar light itself, independent of the spherical
//! polygon and of the boundary recurrences.
//!
//! The integrand is that of [`super::cubature`] (SHG (4) over the planar light; the
//! gradient over the fixed domain, Annen et al., SHG Sec. 4.2 "Discussion"), so the
//! gradient checks the Reynolds boundary form independently. The polygon (clipped to
//! the horizon when asked) is fan-triangulated; each triangle is integrated with the
//! 12x12 collapsed-square rule [`super::cubature::rule`] and split into four at its edge
//! midpoints, largest error first, until the error estimates (the change from a
//! triangle's rule to the sum over its four parts) sum below the tolerance.

#[cfg(feature = "verify")]
use super::cubature::add_gradients;
use super::cubature::{add_values, fan, rule, Anchored};
use super::PolygonalLight;
use crate::error::{Error, Result};
use crate::sh::evaluation::harmonics::ShEvaluator;
#[cfg(feature = "verify")]
use crate::sh::evaluation::solid::SolidHarmonics;
use crate::sh::num_coeffs;
use crate::sh::transform::grid::GaussLegendre;

/// Gauss-Legendre points per direction of the triangle rule.
const NODES: usize = 12;
/// Relative change between the rules on a piece taken as rounding (about `50 eps`).
const ROUNDING: f64 = 1e-14;
/// Deepest subdivision.
const MAX_DEPTH: u32 = 14;

/// Adds `sum_k w_k g(d_k)` over nodes `d_k` (relative to `x`) with weights `w_k`.
type Integrand<'a> = dyn Fn(&[[f64; 3]], &[f64], &mut [f64]) -> Result<()> + 'a;

/// One triangle of the adaptive partition: its estimate (the sum over its four halves)
/// and the error estimate (the change from the whole-triangle rule).
struct Piece {
    triangle: Anchored,
    value: Vec<f64>,
    error: f64,
    depth: u32,
}

/// Globally adaptive integration of `f` (adds `sum_k w_k g(d_k)` to its output of length
/// `len`) over the triangles: the piece of largest error estimate is split into four
/// until the estimates sum to at most `tol` times the largest component of the first
/// estimate (a relative tolerance).
fn integrate(triangles: &[Anchored], len: usize, tol: f64, f: &Integrand) -> Result<Vec<f64>> {
    let gl = GaussLegendre::new(NODES)?;
    let estimate = |t: &Anchored| -> Result<Vec<f64>> {
        let (nodes, weights) = rule(&gl, t);
        let mut out = vec![0.0; len];
        f(&nodes, &weights, &mut out)?;
        Ok(out)
    };
    let piece = |t: Anchored, whole: &[f64], depth: u32| -> Result<Piece> {
        let value = quarters(&t)
            .iter()
            .map(estimate)
            .try_fold(vec![0.0; len], |mut acc, p| {
                p.map(|p| {
                    acc.iter_mut().zip(&p).for_each(|(a, b)| *a += b);
                    acc
                })
            })?;
        let change = value
            .iter()
            .zip(whole)
            .fold(0.0f64, |a, (v, w)| a.max((v - w).abs()));
        // A change at the rounding level of the piece is no evidence of an error.
        let size = value.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let error = if change <= ROUNDING * size {
            0.0
        } else {
            change
        };
        Ok(Piece {
            triangle: t,
            value,
            error,
            depth,
        })
    };
    let mut pieces = Vec::new();
    for t in triangles {
        pieces.push(piece(*t, &estimate(t)?, 0)?);
    }
    let scale = pieces
        .iter()
        .flat_map(|p| &p.value)
        .fold(0.0f64, |a, v| a.max(v.abs()));
    let tol = tol * scale;
    loop {
        let total: f64 = pieces.iter().map(|p| p.error).sum();
        if total <= tol {
            break;
        }
        let worst = (0..pieces.len())
            .max_by(|&a, &b| pieces[a].error.total_cmp(&pieces[b].error))
            .unwrap_or(0);
        let p = pieces.swap_remove(worst);
        if p.depth >= MAX_DEPTH {
            return Err(Error::invalid(
                "tolerance",
                tol.to_string(),
                format!("reference quadrature not converged (error estimate {total:e})"),
            ));
        }
        for q in quarters(&p.triangle) {
            let whole = estimate(&q)?;
            pieces.push(piece(q, &whole, p.depth + 1)?);
        }
    }
    Ok(pieces.iter().fold(vec![0.0; len], |mut acc, p| {
        acc.iter_mut().zip(&p.value).for_each(|(a, b)| *a += b);
        acc
    }))
}

/// The four halves-of-edges subtriangles of `t` (same anchor).
fn quarters(&(anchor, t): &Anchored) -> [Anchored; 4] {
    let m: [[f64; 3]; 3] = std::array::from_fn(|k| {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        std::array::from_fn(|i| 0.5 * (a[i] + b[i]))
    });
    [
        (anchor, [t[0], m[0], m[2]]),
        (anchor, [m[0], t[1], m[1]]),
        (anchor, [m[2], m[1], t[2]]),
        (anchor, [m[0], m[1], m[2]]),
    ]
}

/// The anchored fan triangles of `light` seen from `x`, clipped to the horizon when
/// given.
fn triangles(
    light: &PolygonalLight,
    x: [f64; 3],
    horizon: Option<[f64; 3]>,
) -> Result<Vec<Anchored>> {
    Ok(fan(&light.seen_from(x, horizon)?))
}

/// `L_lm(x)`, `l <= lmax`, by adaptive quadrature to the relative tolerance `tol`.
pub fn coefficients(
    light: &PolygonalLight,
    x: [f64; 3],
    horizon: Option<[f64; 3]>,
    lmax: usize,
    tol: f64,
) -> Result<Vec<f64>> {
    let ev = ShEvaluator::new(lmax)?;
    let n = num_coeffs(lmax);
    let f = |nodes: &[[f64; 3]], weights: &[f64], out: &mut [f64]| {
        add_values(&ev, light, nodes, weights, out)
    };
    integrate(&triangles(light, x, horizon)?, n, tol, &f)
}

/// `grad_x L_lm(x)`, `l <= lmax` (no horizon: the domain must not depend on `x`), by
/// adaptive quadrature of `-grad_d [Y_lm(d/|d|) |N . d| / |d|^3]` to the relative
/// tolerance `tol` (`psh verify`'s reference).
#[cfg(feature = "verify")]
pub fn gradients(
    light: &PolygonalLight,
    x: [f64; 3],
    lmax: usize,
    tol: f64,
) -> Result<Vec<[f64; 3]>> {
    let sh = SolidHarmonics::new(lmax)?;
    let n = num_coeffs(lmax);
    let f = |nodes: &[[f64; 3]], weights: &[f64], out: &mut [f64]| {
        add_gradients(&sh, light, nodes, weights, out)
    };
    let flat = integrate(&triangles(light, x, None)?, 3 * n, tol, &f)?;
    Ok(flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::polygon::boundary::triangle_solid_angle;
    use std::f64::consts::PI;

    /// The reference quadrature keeps the relative precision of a small light far from the
    /// origin: its `L_00` is the solid angle (Van Oosterom-Strackee from the edges, exact to
    /// rounding) over `2 sqrt(pi)` to 2e-15 (measured at most 1.0e-15), for triangles of edges 1e-3 to 1e-5 at distance
    /// 1 (Newell's normal from absolute positions, or midpoints of absolute positions in the
    /// subdivision, lost `eps / T`: 1.5e-11 at 1e-3).
    #[test]
    fn reference_l0_of_small_lights() {
        let base = [[0.3, 0.2, 0.9], [0.301, 0.2, 0.9], [0.3, 0.2008, 0.9005]];
        for scale in [1.0, 0.1, 0.01] {
            let v: Vec<[f64; 3]> = base
                .iter()
                .map(|p| std::array::from_fn(|i| base[0][i] + scale * (p[i] - base[0][i])))
                .collect();
            let light = PolygonalLight::new(v.clone(), 1.0).unwrap();
            let want = triangle_solid_angle(v[0], v[1], v[2]).abs() / (2.0 * PI.sqrt());
            let got = coefficients(&light, [0.0; 3], None, 2, 1e-13).unwrap()[0];
            println!(
                "edges {:.0e}: L_00 relative error {:.1e}",
                1e-3 * scale,
                got / want - 1.0
            );
            assert!((got / want - 1.0).abs() < 2e-15, "scale {scale}");
        }
    }
}
