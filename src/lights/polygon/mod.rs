//! Uniform polygonal lights (SHG): analytic SH coefficients of the light seen from a
//! shading point (SHG (4), (5)) and their spatial gradients (SHG (6)-(18)), summed over
//! many lights.
//!
//! - [`zonal_factorization`]: SHG (3), lobes and weights;
//! - [`boundary`]: the per-edge recurrences for the zonal integrals and the Reynolds
//!   boundary terms;
//! - [`clip`]: clipping against the horizon of a shading point;
//! - [`cubature`]: SHG (4) as an area integral by Gauss-Legendre rules on the planar
//!   light, for small lights (where the boundary sums cancel) and for the reference;
//! - `reference`: adaptive quadrature over the planar light, the independent oracle
//!   (feature `verify`);
//!
//! A light is a planar, convex polygon (vertices in order, at least 3) of uniform
//! radiance `E`, emitting on both sides. Seen from `x` it covers the spherical polygon
//! `Q(x)`; `L_lm(x) = E int_Q Y_lm` (SHG (4)). With a horizon normal `n` the polygon is
//! first clipped to `n . (y - x) >= 0`. Derivations: `proofs/polygon-lights.md`.

pub(crate) mod boundary;
pub(crate) mod clip;
pub(crate) mod cubature;
pub(crate) mod demo_scene;
#[cfg(any(test, feature = "verify"))]
pub(crate) mod reference;
pub(crate) mod zonal_factorization;

use crate::error::{finite, Error, Result};
use crate::lights::source::{LightField, Order};
use crate::sh::num_coeffs;
use boundary::{cross, dot, norm, triangle_solid_angle, Arc};
use clip::{clip_to_horizon, ClippedPolygon};
use cubature::{is_small, SmallLights};
pub use demo_scene::{polygon_scene, PolygonScene};
pub use zonal_factorization::{BandLobes, ZonalFactorization};

/// Relative tolerance of the planarity and convexity checks and of "on the plane".
pub const GEOMETRY_TOLERANCE: f64 = 1e-10;

/// A planar convex polygon of uniform radiance.
#[derive(Clone, Debug, PartialEq)]
pub struct PolygonalLight {
    vertices: Vec<[f64; 3]>,
    radiance: f64,
    /// Unit normal (right-hand rule on the vertex order).
    normal: [f64; 3],
    /// Longest edge, the length scale of the tolerances.
    size: f64,
}

fn invalid(value: String, reason: String) -> Error {
    Error::invalid("polygon", value, reason)
}

fn sub(u: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    [u[0] - v[0], u[1] - v[1], u[2] - v[2]]
}

impl PolygonalLight {
    /// A light with finite `vertices` (at least 3, in order) and finite `radiance`. Errors
    /// name the polygon: a repeated vertex or zero area (degenerate), a vertex off the
    /// plane by more than [`GEOMETRY_TOLERANCE`] times the longest edge (non-planar), a
    /// reflex vertex or a boundary winding more than once (non-convex: split it into
    /// convex pieces, e.g. triangles).
    pub fn new(vertices: Vec<[f64; 3]>, radiance: f64) -> Result<Self> {
        let show = || format!("{vertices:?}");
        if vertices.len() < 3 {
            return Err(invalid(show(), "needs at least 3 vertices".into()));
        }
        for v in &vertices {
            for &c in v {
                finite("polygon vertex", c)?;
            }
        }
        finite("polygon radiance", radiance)?;
        let nv = vertices.len();
        let edge = |i: usize| sub(vertices[(i + 1) % nv], vertices[i]);
        let size = (0..nv).map(|i| norm(edge(i))).fold(0.0, f64::max);
        if (0..nv).any(|i| norm(edge(i)) == 0.0) {
            return Err(invalid(show(), "degenerate: a repeated vertex".into()));
        }
        // Newell's normal: twice the vector area, from the vertices relative to the
        // first one (absolute positions would cancel to `eps |v|^2 / area`).
        let rel: Vec<[f64; 3]> = vertices.iter().map(|v| sub(*v, vertices[0])).collect();
        let area2 = (0..nv).fold([0.0; 3], |acc, i| {
            let c = cross(rel[i], rel[(i + 1) % nv]);
            [acc[0] + c[0], acc[1] + c[1], acc[2] + c[2]]
        });
        let a2 = norm(area2);
        if a2 <= GEOMETRY_TOLERANCE * size * size {
            return Err(invalid(
                show(),
                format!("degenerate: area {} ~ 0", a2 / 2.0),
            ));
        }
        let normal = area2.map(|c| c / a2);
        for v in &vertices {
            let off = dot(normal, sub(*v, vertices[0]));
            if off.abs() > GEOMETRY_TOLERANCE * size {
                return Err(invalid(
                    show(),
                    format!("non-planar: vertex {v:?} is {off:e} off the plane"),
                ));
            }
        }
        let mut turning = 0.0;
        for i in 0..nv {
            let (e0, e1) = (edge((i + nv - 1) % nv), edge(i));
            let s = dot(cross(e0, e1), normal);
            if s < -GEOMETRY_TOLERANCE * size * size {
                return Err(invalid(
                    show(),
                    format!("non-convex: reflex vertex {:?}", vertices[i]),
                ));
            }
            turning += s.atan2(dot(e0, e1));
        }
        if turning > 3.0 * std::f64::consts::PI {
            return Err(invalid(
                show(),
                "non-convex: the boundary winds more than once".into(),
            ));
        }
        Ok(Self {
            vertices,
            radiance,
            normal,
            size,
        })
    }

    /// The vertices.
    pub fn vertices(&self) -> &[[f64; 3]] {
        &self.vertices
    }

    /// The radiance `E`.
    pub fn radiance(&self) -> f64 {
        self.radiance
    }

    /// The unit normal (right-hand rule on the vertex order).
    pub fn normal(&self) -> [f64; 3] {
        self.normal
    }

    /// The polygon relative to `x`, clipped to the horizon `normal . (y - x) >= 0` when
    /// given; an error when `x` is not finite or lies on the light's plane (within
    /// [`GEOMETRY_TOLERANCE`] of the polygon's size and distance).
    pub fn seen_from(&self, x: [f64; 3], horizon: Option<[f64; 3]>) -> Result<ClippedPolygon> {
        for &c in &x {
            finite("shading point", c)?;
        }
        let rel: Vec<([f64; 3], bool)> = self.vertices.iter().map(|v| (sub(*v, x), true)).collect();
        let offset = dot(self.normal, rel[0].0);
        let scale = self.size.max(norm(rel[0].0));
        if offset.abs() <= GEOMETRY_TOLERANCE * scale {
            return Err(Error::invalid(
                "shading point",
                format!("{x:?}"),
                format!(
                    "on the plane of the polygonal light {:?} (offset {offset:e})",
                    self.vertices
                ),
            ));
        }
        Ok(match horizon {
            Some(n) => clip_to_horizon(&rel, n),
            None => rel,
        })
    }
}

/// The arcs of the spherical polygon of `polygon` (relative positions), oriented so that
/// the interior is on the side of each arc's normal, and its solid angle.
pub fn spherical_polygon(polygon: &ClippedPolygon) -> (Vec<Arc>, f64) {
    let nv = polygon.len();
    if nv < 3 {
        return (Vec::new(), 0.0);
    }
    let dist: Vec<f64> = polygon.iter().map(|(p, _)| norm(*p)).collect();
    let q: Vec<[f64; 3]> = polygon.iter().map(|(p, _)| *p).collect();
    let omega: f64 = (1..nv - 1)
        .map(|i| triangle_solid_angle(q[0], q[i], q[i + 1]))
        .sum();
    let flip = omega < 0.0;
    let arcs = (0..nv)
        .filter_map(|i| {
            let j = (i + 1) % nv;
            let inv = polygon[i].1.then(|| (1.0 / dist[i], 1.0 / dist[j]));
            if flip {
                Arc::new(q[j], q[i], inv.map(|(a, b)| (b, a)))
            } else {
                Arc::new(q[i], q[j], inv)
            }
        })
        .collect();
    (arcs, omega.abs())
}

/// Many polygonal lights with SH up to `lmax`, optionally seen through the horizon of a
/// fixed shading normal.
#[derive(Clone, Debug)]
pub struct PolygonalLights {
    lights: Vec<PolygonalLight>,
    factorization: ZonalFactorization,
    small: SmallLights,
    horizon: Option<[f64; 3]>,
}

impl PolygonalLights {
    /// The lights, with SH up to `lmax` and no horizon clipping.
    pub fn new(lights: Vec<PolygonalLight>, lmax: usize) -> Result<Self> {
        Ok(Self {
            lights,
            factorization: ZonalFactorization::new(lmax)?,
            small: SmallLights::new(lmax)?,
            horizon: None,
        })
    }

    /// Clip every light to the upper hemisphere of the unit `normal` at each shading point.
    pub fn with_horizon(mut self, normal: [f64; 3]) -> Result<Self> {
        for &c in &normal {
            finite("horizon normal", c)?;
        }
        crate::geometry::check_direction(normal)?;
        self.horizon = Some(normal);
        Ok(self)
    }

    /// The lights.
    pub fn lights(&self) -> &[PolygonalLight] {
        &self.lights
    }

    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.factorization.lmax()
    }

    /// The zonal factorization in use (SHG (3)).
    pub fn factorization(&self) -> &ZonalFactorization {
        &self.factorization
    }

    /// The summed light field at `x`: coefficients SHG (4)-(5) and, for
    /// [`Order::Gradients`], their gradients in `x` (SHG (6), (11), (15)); lights small
    /// for the band limit (`cubature::SMALL_LIGHT`) by the fixed area rule of
    /// `SmallLights` instead. Hessians are not derived for polygonal lights:
    /// [`Order::Hessians`] is an error.
    pub fn field(&self, x: [f64; 3], order: Order) -> Result<LightField> {
        if order == Order::Hessians {
            return Err(Error::invalid(
                "order",
                "Hessians",
                "Hessians of polygonal lights are not derived (coefficients and gradients only)",
            ));
        }
        let grads = order == Order::Gradients;
        let f = &self.factorization;
        let stride = f.lmax() + 1;
        let nz = f.directions.len() * stride;
        // Per lobe j and band l: E int_Q P_l(w_j . w) and its gradient.
        let mut z = vec![0.0; nz];
        let mut gz = vec![vec![0.0; nz]; if grads { 3 } else { 0 }];
        let mut d = vec![0.0; stride];
        let mut u = vec![0.0; stride];
        let n = num_coeffs(f.lmax());
        // The small lights' coefficients and gradients (flat, `3 (lm) + i`).
        let mut coefficients = vec![0.0; n];
        let mut small_gradients = vec![0.0; if grads { 3 * n } else { 0 }];
        for light in &self.lights {
            let polygon = light.seen_from(x, self.horizon)?;
            if is_small(&polygon, f.lmax()) {
                let g = grads.then_some(&mut small_gradients[..]);
                self.small.add(light, &polygon, &mut coefficients, g)?;
                continue;
            }
            let (arcs, omega) = spherical_polygon(&polygon);
            if arcs.is_empty() {
                continue;
            }
            let e = light.radiance;
            for (j, &w) in f.directions.iter().enumerate() {
                let top = f.top_band[j] + 1;
                let zj = &mut z[j * stride..j * stride + top];
                zj[0] += e * omega;
                for arc in &arcs {
                    let want_u = grads && arc.moves();
                    arc.integrals(w, &mut d[..top], want_u.then_some(&mut u[..top]));
                    let wn = e * dot(w, arc.n);
                    for l in 1..top {
                        zj[l] += wn * d[l] / (l * (l + 1)) as f64;
                    }
                    if want_u {
                        for (c, g) in gz.iter_mut().enumerate() {
                            let en = e * arc.n[c];
                            for l in 0..top {
                                g[j * stride + l] += en * u[l];
                            }
                        }
                    }
                }
            }
        }
        f.combine(&z, &mut coefficients);
        let mut gradients = Vec::new();
        if grads {
            gradients = vec![[0.0; 3]; n];
            let mut tmp = vec![0.0; n];
            for (c, g) in gz.iter().enumerate() {
                tmp.fill(0.0);
                f.combine(g, &mut tmp);
                for (k, (o, t)) in gradients.iter_mut().zip(&tmp).enumerate() {
                    o[c] = small_gradients[3 * k + c] + t;
                }
            }
        }
        Ok(LightField {
            coefficients,
            gradients,
            hessians: Vec::new(),
        })
    }
}

impl crate::lights::source::LightSource for PolygonalLights {
    fn lmax(&self) -> usize {
        PolygonalLights::lmax(self)
    }

    fn field(&self, x: [f64; 3], order: Order) -> Result<LightField> {
        PolygonalLights::field(self, x, order)
    }
}
