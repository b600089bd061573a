//! SH coefficients and gradients of a polygonal light as an area integral over the planar
//! light, by Gauss-Legendre rules on its fan triangles: the integrand of the reference
//! ([`super::reference`], adaptive) and of small lights ([`SmallLights`], one fixed rule).
//!
//! Seen from `x`, the area element `dA` at `y` subtends `dw = |N . d| / |d|^3 dA`,
//! `d = y - x`, so `L_lm(x) = E int_A Y_lm(d/|d|) |N . d| / |d|^3 dA` (SHG (4)). Over a
//! domain `A` fixed in space, the gradient in `x` is the integral of
//! `-grad_d [Y_lm(d/|d|) |N . d| / |d|^3]` (the parameterization of Annen et al., SHG
//! Sec. 4.2 "Discussion" and App. C): no boundary term. Rule and error bound:
//! `proofs/small-polygon-lights.md`.

use super::boundary::{cross, dot, norm};
use super::clip::ClippedPolygon;
use super::PolygonalLight;
use crate::error::Result;
use crate::sh::evaluation::harmonics::ShEvaluator;
use crate::sh::evaluation::solid::SolidHarmonics;
use crate::sh::transform::grid::GaussLegendre;

/// A triangle as an anchor (relative to `x`) and its vertices relative to the anchor:
/// subdividing the small offsets keeps the pieces an exact tiling to `eps` of the
/// triangle's size, where midpoints of positions far from the anchor would misplace the
/// pieces' vertices by `eps |p|` (a relative error `eps |p| / size` of a small light).
pub type Anchored = ([f64; 3], [[f64; 3]; 3]);

/// The fan triangles of `polygon` (positions relative to `x`), anchored at its first
/// vertex.
pub fn fan(polygon: &ClippedPolygon) -> Vec<Anchored> {
    let Some(&(apex, _)) = polygon.first() else {
        return Vec::new();
    };
    let local = |q: [f64; 3]| std::array::from_fn(|i| q[i] - apex[i]);
    (1..polygon.len().saturating_sub(1))
        .map(|i| {
            (
                apex,
                [[0.0; 3], local(polygon[i].0), local(polygon[i + 1].0)],
            )
        })
        .collect()
}

/// Nodes `d` (relative to `x`) and weights (with the Jacobian) of the tensor rule `gl`
/// on the collapsed square (Duffy) of `t`: `y = p0 + u e1 + u v e2`,
/// `dA = u |e1 x e2| du dv`; exact for polynomials of total degree `2n - 2` in `y`.
pub fn rule(gl: &GaussLegendre, (anchor, t): &Anchored) -> (Vec<[f64; 3]>, Vec<f64>) {
    let [p0, p1, p2] = *t;
    let e1: [f64; 3] = std::array::from_fn(|i| p1[i] - p0[i]);
    let e2: [f64; 3] = std::array::from_fn(|i| p2[i] - p1[i]);
    let area2 = norm(cross(e1, e2));
    let mut nodes = Vec::with_capacity(gl.len() * gl.len());
    let mut weights = Vec::with_capacity(gl.len() * gl.len());
    for (xu, wu) in gl.cos_theta.iter().zip(&gl.weights) {
        let u = 0.5 * (1.0 + xu);
        for (xv, wv) in gl.cos_theta.iter().zip(&gl.weights) {
            let v = 0.5 * (1.0 + xv);
            nodes.push(std::array::from_fn(|i| {
                anchor[i] + (p0[i] + u * e1[i] + u * v * e2[i])
            }));
            weights.push(0.25 * wu * wv * u * area2);
        }
    }
    (nodes, weights)
}

/// Adds `E sum_k w_k Y_lm(d_k/|d_k|) |N . d_k| / |d_k|^3` (SHG (4)) to `out` (flat SH
/// order, `(lmax + 1)^2` entries of `ev`).
pub fn add_values(
    ev: &ShEvaluator,
    light: &PolygonalLight,
    nodes: &[[f64; 3]],
    weights: &[f64],
    out: &mut [f64],
) -> Result<()> {
    let n = ev.len();
    let (normal, e) = (light.normal(), light.radiance());
    let dirs: Vec<[f64; 3]> = nodes.iter().map(|d| d.map(|c| c / norm(*d))).collect();
    let mut y = vec![0.0; nodes.len() * n];
    ev.real_batch(&dirs, &mut y)?;
    for (k, (d, w)) in nodes.iter().zip(weights).enumerate() {
        let r = norm(*d);
        let s = e * w * dot(normal, *d).abs() / (r * r * r);
        for (o, yv) in out.iter_mut().zip(&y[k * n..(k + 1) * n]) {
            *o += s * yv;
        }
    }
    Ok(())
}

/// Adds `-E sum_k w_k grad_d [Y_lm(d/|d|) |N . d| / |d|^3]` at `d = d_k` (the
/// x-gradient over a fixed domain) to `out[3 (lm) + i]`.
pub fn add_gradients(
    sh: &SolidHarmonics,
    light: &PolygonalLight,
    nodes: &[[f64; 3]],
    weights: &[f64],
    out: &mut [f64],
) -> Result<()> {
    let (n, m) = (sh.len(), nodes.len());
    let (normal, e) = (light.normal(), light.radiance());
    let (mut ys, mut gys, mut hys) = (
        vec![0.0; m * n],
        vec![[0.0; 3]; m * n],
        vec![[0.0; 6]; m * n],
    );
    let dirs: Vec<[f64; 3]> = nodes.iter().map(|d| d.map(|c| c / norm(*d))).collect();
    sh.eval_batch(&dirs, &mut ys, &mut gys, &mut hys)?;
    for (p, (d, w)) in nodes.iter().zip(weights).enumerate() {
        let r = norm(*d);
        let (y, gy) = (&ys[p * n..(p + 1) * n], &gys[p * n..(p + 1) * n]);
        let s = dot(normal, *d);
        let q = s.abs() / (r * r * r);
        // grad_d q = sign(s) N / r^3 - 3 |s| d / r^5; grad_d Y(d/r) = grad Y / r.
        let gq: [f64; 3] = std::array::from_fn(|i| {
            s.signum() * normal[i] / (r * r * r) - 3.0 * q * d[i] / (r * r)
        });
        for k in 0..n {
            for i in 0..3 {
                out[3 * k + i] -= e * w * (gy[k][i] / r * q + y[k] * gq[i]);
            }
        }
    }
    Ok(())
}

/// Lights with `diameter * max(lmax + 3, 24) <= SMALL_LIGHT * distance` (diameter of the
/// polygon, distance from `x` to its nearest vertex) and not cut by the horizon take
/// [`SmallLights`]: the boundary sums cancel there to `O(T^2)` from `O(T)` terms
/// (relative error 4.4e-12 for edges of 1e-3 rad at `l <= 20`, at most 1.5e-13 just
/// above the switch), while the rule's error is bounded by `6e-20 / cos(gamma)` at
/// `l <= 20`, `gamma` the angle between the light's normal and the line of sight
/// (`proofs/small-polygon-lights.md` Sec. 4).
pub const SMALL_LIGHT: f64 = 1.5;

/// Gauss-Legendre points per direction of the small-light rule: at least 12, and
/// `ceil(lmax / 2) + 2` above `l = 20` (`proofs/small-polygon-lights.md`).
pub fn small_rule_nodes(lmax: usize) -> usize {
    12.max(lmax.div_ceil(2) + 2)
}

/// Whether `polygon` (seen from `x`, clipping flags included) is small for `lmax` (see
/// [`SMALL_LIGHT`]).
pub fn is_small(polygon: &ClippedPolygon, lmax: usize) -> bool {
    if polygon.len() < 3 || polygon.iter().any(|(_, on_light)| !on_light) {
        return false;
    }
    let distance = polygon
        .iter()
        .map(|(p, _)| norm(*p))
        .fold(f64::INFINITY, f64::min);
    let diameter = polygon
        .iter()
        .flat_map(|(p, _)| {
            polygon
                .iter()
                .map(move |(q, _)| norm(std::array::from_fn(|i| p[i] - q[i])))
        })
        .fold(0.0, f64::max);
    diameter * (lmax + 3).max(24) as f64 <= SMALL_LIGHT * distance
}

/// The fixed rule for small lights: [`small_rule_nodes`]^2 points per fan triangle.
#[derive(Clone, Debug)]
pub struct SmallLights {
    rule: GaussLegendre,
    values: ShEvaluator,
    gradients: SolidHarmonics,
}

impl SmallLights {
    /// The rule and SH evaluators for `l <= lmax`.
    pub fn new(lmax: usize) -> Result<Self> {
        Ok(Self {
            rule: GaussLegendre::new(small_rule_nodes(lmax))?,
            values: ShEvaluator::new(lmax)?,
            gradients: SolidHarmonics::new(lmax)?,
        })
    }

    /// Adds the coefficients of `light` seen as `polygon` to `values` and, when given,
    /// their gradients to `gradients` (flat, `3 (lm) + i`).
    pub fn add(
        &self,
        light: &PolygonalLight,
        polygon: &ClippedPolygon,
        values: &mut [f64],
        gradients: Option<&mut [f64]>,
    ) -> Result<()> {
        let (mut nodes, mut weights) = (Vec::new(), Vec::new());
        for t in fan(polygon) {
            let (n, w) = rule(&self.rule, &t);
            nodes.extend(n);
            weights.extend(w);
        }
        add_values(&self.values, light, &nodes, &weights, values)?;
        if let Some(g) = gradients {
            add_gradients(&self.gradients, light, &nodes, &weights, g)?;
        }
        Ok(())
    }
}
