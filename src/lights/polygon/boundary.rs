//! Boundary integrals over one edge (arc) of a spherical polygon, by recurrences in `l`
//! (`proofs/polygon-lights.md`, Secs. 2-3).
//!
//! An arc runs from the unit vector `a` to `b` on the great circle of unit normal
//! `n = a x b / |a x b|`, `w(t) = a cos t + (n x a) sin t`, `t in [0, T]`. For a lobe
//! direction `v` let `h(t) = v . w(t)`. The recurrence yields
//! `D_l = int_0^T P_l'(h(t)) dt`, which gives the ZH integral over the polygon by
//! Stokes' theorem on the sphere (SHG (5); Wang & Ramamoorthi 2018):
//! `int_Q P_l(v . w) dw = sum_edges (v . n) D_l / (l (l + 1))`, `l >= 1`;
//! and, for an edge that moves with the shading point, the Reynolds boundary term
//! (SHG (14)-(18)) `U_l = int_0^T P_l(h(t)) / ell(t) dt` with `ell(t)` the distance from
//! the shading point to the light's edge along `w(t)`.

use crate::sh::transform::grid::GaussLegendre;
use std::sync::OnceLock;

/// One arc of a spherical polygon.
#[derive(Clone, Copy, Debug)]
pub struct Arc {
    pub a: [f64; 3],
    pub b: [f64; 3],
    /// Unit normal `a x b / |a x b|` (the polygon's interior is on its side).
    pub n: [f64; 3],
    /// Unit tangents `n x a`, `n x b` at the ends.
    ta: [f64; 3],
    tb: [f64; 3],
    /// Length `T` (radians), `sin T`, `cos T`.
    len: f64,
    sin: f64,
    cos: f64,
    /// For an edge of the light: `(1/ell(0), 1/ell(T))`; `None` for an arc fixed on
    /// the horizon (no Reynolds term).
    inv_dist: Option<(f64, f64)>,
}

pub(crate) fn dot(u: [f64; 3], v: [f64; 3]) -> f64 {
    u[0] * v[0] + u[1] * v[1] + u[2] * v[2]
}

pub(crate) fn cross(u: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

pub(crate) fn norm(u: [f64; 3]) -> f64 {
    dot(u, u).sqrt()
}

impl Arc {
    /// The arc from the direction of `qa` to that of `qb` (positions relative to the
    /// shading point), or `None` if it has no length or its ends are antipodal.
    /// `inv_dist` as in the field of the same name. `a x b` is taken as
    /// `qa x (qb - qa) / (|qa| |qb|)`: the edge `qb - qa` keeps its relative precision for
    /// a short arc, where the cross product of the two nearly parallel unit vectors would
    /// lose `eps / T`.
    pub fn new(qa: [f64; 3], qb: [f64; 3], inv_dist: Option<(f64, f64)>) -> Option<Self> {
        let (da, db) = (norm(qa), norm(qb));
        let (a, b) = (qa.map(|x| x / da), qb.map(|x| x / db));
        let edge = std::array::from_fn(|k| qb[k] - qa[k]);
        let c = cross(qa, edge).map(|x| x / (da * db));
        let sin = norm(c);
        if sin == 0.0 {
            return None;
        }
        let n = c.map(|x| x / sin);
        let cos = dot(a, b);
        Some(Self {
            a,
            b,
            n,
            ta: cross(n, a),
            tb: cross(n, b),
            len: sin.atan2(cos),
            sin,
            cos,
            inv_dist,
        })
    }

    /// Whether the arc moves with the shading point (an edge of the light).
    pub fn moves(&self) -> bool {
        self.inv_dist.is_some()
    }

    /// Fills `d[l] = D_l` for `l < d.len()` and, when `u` is given and the arc moves,
    /// `u[l] = U_l` (`u.len() == d.len()`), for the lobe direction `v`.
    ///
    /// With `B_k = int P_k(h)`, `C_k = int h P_k(h)` and `P_k` at the ends:
    /// `C_k = (k B_{k-1} - (v . n)^2 D_k - [h' P_k(h)]_0^T) / (k + 1)`,
    /// `B_{k+1} = ((2k + 1) C_k - k B_{k-1}) / (k + 1)` (Bonnet),
    /// `D_{k+1} = D_{k-1} + (2k + 1) B_k`; and with `g(t) = 1/ell(t) = g1 cos t + g2 sin t`,
    /// `c = g1 h(0) + g2 h'(0)`, `W_k = int g P_k'(h)`:
    /// `U_k = (c D_k - W_{k-1} - [g' P_k(h)]_0^T) / (k + 1)`,
    /// `W_{k+1} = W_{k-1} + (2k + 1) U_k` (`proofs/polygon-lights.md`).
    ///
    /// Short arcs (`T (lmax + 1) <= SHORT_ARC`) take `integrals_by_quadrature`
    /// instead: the recurrence's end-point differences cancel there, to `eps / T`.
    pub fn integrals(&self, v: [f64; 3], d: &mut [f64], u: Option<&mut [f64]>) {
        if self.len * d.len() as f64 <= SHORT_ARC {
            if let Some(rule) = short_arc_rule() {
                return self.integrals_by_quadrature(rule, v, d, u);
            }
        }
        let (h0, h1) = (dot(v, self.a), dot(v, self.b));
        let (dh0, dh1) = (dot(v, self.ta), dot(v, self.tb));
        let vn = dot(v, self.n);
        let vn2 = vn * vn;
        // g = 1/ell: g(0) = g1, g(T) = g1 cos T + g2 sin T.
        let grad = self.inv_dist.map(|(i0, i1)| {
            let g1 = i0;
            let g2 = (i1 - self.cos * i0) / self.sin;
            (g1 * h0 + g2 * dh0, g2, -g1 * self.sin + g2 * self.cos)
        });
        let (mut p0m, mut p0) = (0.0, 1.0);
        let (mut p1m, mut p1) = (0.0, 1.0);
        let (mut bm, mut b) = (0.0, self.len);
        let (mut dm, mut dk) = (0.0, 0.0);
        let (mut wm, mut wk) = (0.0, 0.0);
        let mut u = u.filter(|_| grad.is_some());
        for k in 0..d.len() {
            let kf = k as f64;
            let k1 = kf + 1.0;
            let two = 2.0 * kf + 1.0;
            d[k] = dk;
            if let (Some(u), Some((c, dg0, dg1))) = (u.as_deref_mut(), grad) {
                let uk = (c * dk - wm - (dg1 * p1 - dg0 * p0)) / k1;
                u[k] = uk;
                (wm, wk) = (wk, wm + two * uk);
            }
            let ck = (kf * bm - vn2 * dk - (dh1 * p1 - dh0 * p0)) / k1;
            (bm, b) = (b, (two * ck - kf * bm) / k1);
            (dm, dk) = (dk, dm + two * bm);
            (p0m, p0) = (p0, (two * h0 * p0 - kf * p0m) / k1);
            (p1m, p1) = (p1, (two * h1 * p1 - kf * p1m) / k1);
        }
    }
}

/// Arcs with `T (lmax + 1)` at most this are integrated by [`short_arc_rule`]: the
/// integrands are trigonometric polynomials of degree `<= lmax` in `t`, whose
/// `n`-point Gauss-Legendre error on `[0, T]` is bounded by about
/// `(lmax T / 2)^(2n) / (2n)!`, below `1e-35` for `n = 16` here.
const SHORT_ARC: f64 = 2.0;

/// The 16-point Gauss-Legendre rule (built once).
fn short_arc_rule() -> Option<&'static GaussLegendre> {
    static RULE: OnceLock<Option<GaussLegendre>> = OnceLock::new();
    RULE.get_or_init(|| GaussLegendre::new(16).ok()).as_ref()
}

impl Arc {
    /// [`Self::integrals`] by the Gauss-Legendre `rule` on `[0, T]`: at each node
    /// `P_k(h)` by Bonnet's recurrence and `P_k'(h)` by `P_{k+1}' = P_{k-1}' + (2k+1) P_k`,
    /// and `g = 1/ell` as in [`Self::integrals`].
    fn integrals_by_quadrature(
        &self,
        rule: &GaussLegendre,
        v: [f64; 3],
        d: &mut [f64],
        u: Option<&mut [f64]>,
    ) {
        let (h0, dh0) = (dot(v, self.a), dot(v, self.ta));
        let g = self
            .inv_dist
            .map(|(i0, i1)| (i0, (i1 - self.cos * i0) / self.sin));
        let mut u = u.filter(|_| g.is_some());
        d.fill(0.0);
        if let Some(u) = u.as_deref_mut() {
            u.fill(0.0);
        }
        for (x, w) in rule.cos_theta.iter().zip(&rule.weights) {
            let t = 0.5 * self.len * (1.0 + x);
            let wt = 0.5 * self.len * w;
            let (st, ct) = t.sin_cos();
            let h = h0 * ct + dh0 * st;
            let gt = g.map_or(0.0, |(g1, g2)| g1 * ct + g2 * st);
            let (mut pm, mut p) = (0.0, 1.0);
            let (mut dpm, mut dp) = (0.0, 0.0);
            for k in 0..d.len() {
                d[k] += wt * dp;
                if let Some(u) = u.as_deref_mut() {
                    u[k] += wt * gt * p;
                }
                let kf = k as f64;
                let two = 2.0 * kf + 1.0;
                (dpm, dp) = (dp, dpm + two * p);
                (pm, p) = (p, (two * h * p - kf * pm) / (kf + 1.0));
            }
        }
    }
}

/// The signed solid angle of the spherical triangle of the directions of `qa`, `qb`,
/// `qc` (positions relative to the shading point),
/// `2 atan2(a . (b x c), 1 + a.b + b.c + c.a)` (Van Oosterom & Strackee 1983) with the
/// determinant taken from the edges, `qa . ((qb - qa) x (qc - qa)) / (|qa| |qb| |qc|)`, so
/// that a small triangle keeps its relative precision; positive when `a, b, c` turn
/// counter-clockwise seen from outside the sphere.
pub fn triangle_solid_angle(qa: [f64; 3], qb: [f64; 3], qc: [f64; 3]) -> f64 {
    let (da, db, dc) = (norm(qa), norm(qb), norm(qc));
    let e1 = std::array::from_fn(|k| qb[k] - qa[k]);
    let e2 = std::array::from_fn(|k| qc[k] - qa[k]);
    let det = dot(qa, cross(e1, e2)) / (da * db * dc);
    let (a, b, c) = (qa.map(|x| x / da), qb.map(|x| x / db), qc.map(|x| x / dc));
    2.0 * det.atan2(1.0 + dot(a, b) + dot(b, c) + dot(c, a))
}
