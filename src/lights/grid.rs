//! Grids of light fields (SHH Sec. 5): the Hessian-based interpolation error metric
//! (SHH (21), (22)), Hermite interpolation of the coefficients from their gradients, the
//! occupancy octree and the adaptive grid with shading voxels (SHH Fig. 2), and uniform
//! grids for comparison.
//!
//! Voxels are addressed by `(level, [i, j, k])` inside an axis-aligned box; grid points by
//! their integer coordinates on the finest lattice (`2^max_level` cells per axis), so
//! neighbouring voxels of any level share their corners and every corner is evaluated
//! once.

use super::source::{LightField, LightSource, Order};
use crate::error::{finite, Error, Result};
use nalgebra::{DMatrix, Matrix3, SymmetricEigen};
use std::collections::{HashMap, HashSet};
use std::sync::OnceLock;

/// How [`LightGrid::interpolate_with`] combines the 8 corners of a shading voxel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// Trilinear in the corner values (gradients unused): error `O(h^2)`.
    Trilinear,
    /// Tensor cubic Hermite (`proofs/polygon-lights.md`, Sec. 5) with the mixed derivatives taken as
    /// zero; exact for affine fields, error `O(h^2)` in general.
    Hermite,
    /// The cubic Hermite serendipity interpolant, exact for
    /// cubic polynomials, error `O(h^4)`.
    Serendipity,
}

/// Largest supported finest level (`2^12` cells per axis).
pub const MAX_LEVEL: u32 = 12;

/// The largest absolute eigenvalue of a packed symmetric 3x3 matrix
/// `[xx, xy, xz, yy, yz, zz]`: the `|lambda_l^m|` of SHH Sec. 5.
pub(crate) fn max_abs_eigenvalue(h: &[f64; 6]) -> f64 {
    let m = Matrix3::new(h[0], h[1], h[2], h[1], h[3], h[4], h[2], h[4], h[5]);
    SymmetricEigen::new(m)
        .eigenvalues
        .iter()
        .fold(0.0f64, |a, e| a.max(e.abs()))
}

/// Which error of SHH (22) drives the subdivision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Metric {
    /// `E_abs = |lambda| |dx|^2 / 2`.
    Absolute,
    /// `E_rel = |lambda| |dx|^2 / (2 |L|)`.
    Relative,
}

/// The per-point quantities of SHH (22): `|lambda|` (L2 norm over `(l, m)` of the largest
/// absolute eigenvalues of the Hessians `H_l^m`) and `|L|` (norm of the coefficients).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointError {
    /// `|lambda|`: L2 norm over `(l, m)` of the largest absolute eigenvalues of `H_l^m`.
    pub lambda_norm: f64,
    /// `|L|`: L2 norm of the coefficients `L_lm`.
    pub coefficient_norm: f64,
}

impl PointError {
    /// From a light field evaluated with [`Order::Hessians`].
    pub fn of(field: &LightField) -> Self {
        let lambda2: f64 = field
            .hessians
            .iter()
            .map(|h| max_abs_eigenvalue(h).powi(2))
            .sum();
        let l2: f64 = field.coefficients.iter().map(|c| c * c).sum();
        Self {
            lambda_norm: lambda2.sqrt(),
            coefficient_norm: l2.sqrt(),
        }
    }

    /// SHH (22) for a step of length `dx`: `E_abs` or `E_rel` (infinite when `|L| = 0`
    /// but `|lambda| > 0`, zero when both vanish).
    pub fn error(&self, metric: Metric, dx: f64) -> f64 {
        let abs = self.lambda_norm * dx * dx / 2.0;
        match metric {
            Metric::Absolute => abs,
            Metric::Relative => {
                if abs == 0.0 {
                    0.0
                } else {
                    abs / self.coefficient_norm
                }
            }
        }
    }
}

/// An axis-aligned box subdivided into `2^max_level` cells per axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lattice {
    min: [f64; 3],
    max: [f64; 3],
    max_level: u32,
}

impl Lattice {
    /// A box `min < max` (finite) with the finest level `max_level <= MAX_LEVEL`.
    pub fn new(min: [f64; 3], max: [f64; 3], max_level: u32) -> Result<Self> {
        for i in 0..3 {
            finite("box corner", min[i])?;
            finite("box corner", max[i])?;
            if min[i] >= max[i] {
                return Err(Error::invalid(
                    "box",
                    format!("{min:?} .. {max:?}"),
                    "needs min < max on every axis",
                ));
            }
        }
        if max_level > MAX_LEVEL {
            return Err(Error::invalid(
                "max_level",
                max_level.to_string(),
                format!("at most {MAX_LEVEL}"),
            ));
        }
        Ok(Self {
            min,
            max,
            max_level,
        })
    }

    /// The finest level.
    pub fn max_level(&self) -> u32 {
        self.max_level
    }

    /// The position of a lattice point.
    pub fn point(&self, p: [u32; 3]) -> [f64; 3] {
        let n = (1u64 << self.max_level) as f64;
        std::array::from_fn(|i| self.min[i] + (self.max[i] - self.min[i]) * p[i] as f64 / n)
    }

    /// The voxel of `level` containing `x` (the upper faces belong to the last voxel), or
    /// an error when `x` is outside the box or not finite.
    pub fn voxel_of(&self, x: [f64; 3], level: u32) -> Result<[u32; 3]> {
        let n = 1u32 << level;
        let mut v = [0u32; 3];
        for i in 0..3 {
            finite("point", x[i])?;
            let t = (x[i] - self.min[i]) / (self.max[i] - self.min[i]);
            if !(0.0..=1.0).contains(&t) {
                return Err(Error::invalid(
                    "point",
                    format!("{x:?}"),
                    format!("outside the grid box {:?} .. {:?}", self.min, self.max),
                ));
            }
            v[i] = ((t * n as f64) as u32).min(n - 1);
        }
        Ok(v)
    }

    /// Lattice coordinates of corner `c` (bits x, y, z) of a voxel.
    fn corner(&self, level: u32, v: [u32; 3], c: usize) -> [u32; 3] {
        let s = 1u32 << (self.max_level - level);
        std::array::from_fn(|i| (v[i] + ((c >> i) & 1) as u32) * s)
    }

    /// Edge lengths of a voxel of `level`.
    fn cell(&self, level: u32) -> [f64; 3] {
        let n = (1u64 << level) as f64;
        std::array::from_fn(|i| (self.max[i] - self.min[i]) / n)
    }
}

/// The occupancy octree of SHH Sec. 5.1 and Fig. 2 (top): every node, at every level,
/// that contains a shading point.
#[derive(Clone, Debug)]
pub struct OccupancyOctree {
    occupied: HashSet<(u32, [u32; 3])>,
}

impl OccupancyOctree {
    /// Marks the finest nodes containing the points, then their ancestors (bottom-up).
    pub fn new(lattice: &Lattice, points: &[[f64; 3]]) -> Result<Self> {
        let mut occupied = HashSet::new();
        for &x in points {
            let mut v = lattice.voxel_of(x, lattice.max_level)?;
            for level in (0..=lattice.max_level).rev() {
                if !occupied.insert((level, v)) {
                    break;
                }
                v = v.map(|c| c / 2);
            }
        }
        Ok(Self { occupied })
    }

    /// Whether the node `(level, v)` contains a shading point.
    pub fn is_occupied(&self, level: u32, v: [u32; 3]) -> bool {
        self.occupied.contains(&(level, v))
    }
}

/// A grid point: coefficients and gradients (the Hessians are only used to decide the
/// subdivision and not stored, SHH Sec. 5).
#[derive(Clone, Debug)]
struct GridPoint {
    coefficients: Vec<f64>,
    gradients: Vec<[f64; 3]>,
    error: Option<PointError>,
}

/// A grid of shading voxels with the light field at their corners.
#[derive(Clone, Debug)]
pub struct LightGrid {
    lattice: Lattice,
    lmax: usize,
    points: HashMap<[u32; 3], GridPoint>,
    /// Shading voxels (the leaves that contain shading points).
    leaves: HashSet<(u32, [u32; 3])>,
}

/// How to build a [`LightGrid`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Refinement {
    /// Every occupied voxel down to the finest level (a uniform grid restricted to
    /// shading voxels); no Hessians are evaluated.
    Uniform,
    /// SHH Sec. 5: subdivide an occupied voxel while its error (the mean of its corners'
    /// errors, SHH (22), with `dx` the voxel diagonal) exceeds `threshold`.
    Adaptive {
        /// The error of SHH (22) compared with `threshold`.
        metric: Metric,
        /// Subdivision threshold on that error (finite).
        threshold: f64,
    },
}

impl LightGrid {
    /// Builds the grid for `lights` over the shading `points` (SHH Fig. 2).
    pub fn build<S: LightSource>(
        lights: &S,
        lattice: Lattice,
        points: &[[f64; 3]],
        refinement: Refinement,
    ) -> Result<Self> {
        if let Refinement::Adaptive { threshold, .. } = refinement {
            finite("threshold", threshold)?;
        }
        let octree = OccupancyOctree::new(&lattice, points)?;
        let mut grid = Self {
            lattice,
            lmax: lights.lmax(),
            points: HashMap::new(),
            leaves: HashSet::new(),
        };
        let mut stack = vec![(0u32, [0u32; 3])];
        while let Some((level, v)) = stack.pop() {
            if !octree.is_occupied(level, v) {
                continue;
            }
            let split = level < lattice.max_level
                && match refinement {
                    Refinement::Uniform => true,
                    Refinement::Adaptive { metric, threshold } => {
                        grid.voxel_error(lights, level, v, metric)? > threshold
                    }
                };
            if split {
                for c in 0..8 {
                    stack.push((
                        level + 1,
                        std::array::from_fn(|i| 2 * v[i] + ((c >> i) & 1) as u32),
                    ));
                }
            } else {
                for c in 0..8 {
                    grid.ensure(lights, lattice.corner(level, v, c), false)?;
                }
                grid.leaves.insert((level, v));
            }
        }
        Ok(grid)
    }

    /// Evaluates a grid point once (with Hessians when `hessians`).
    fn ensure<S: LightSource>(
        &mut self,
        lights: &S,
        p: [u32; 3],
        hessians: bool,
    ) -> Result<&GridPoint> {
        let missing = match self.points.get(&p) {
            None => true,
            Some(g) => hessians && g.error.is_none(),
        };
        if missing {
            let order = if hessians {
                Order::Hessians
            } else {
                Order::Gradients
            };
            let field = lights.field(self.lattice.point(p), order)?;
            let error = hessians.then(|| PointError::of(&field));
            self.points.insert(
                p,
                GridPoint {
                    coefficients: field.coefficients,
                    gradients: field.gradients,
                    error,
                },
            );
        }
        Ok(&self.points[&p])
    }

    /// The error of a voxel: the mean over its 8 corners of SHH (22) with `dx` its diagonal.
    fn voxel_error<S: LightSource>(
        &mut self,
        lights: &S,
        level: u32,
        v: [u32; 3],
        metric: Metric,
    ) -> Result<f64> {
        let cell = self.lattice.cell(level);
        let dx = (cell[0] * cell[0] + cell[1] * cell[1] + cell[2] * cell[2]).sqrt();
        let mut sum = 0.0;
        for c in 0..8 {
            let p = self.lattice.corner(level, v, c);
            let e = self
                .ensure(lights, p, true)?
                .error
                .map_or(0.0, |e| e.error(metric, dx));
            sum += e;
        }
        Ok(sum / 8.0)
    }

    /// Number of evaluated grid points.
    pub fn num_points(&self) -> usize {
        self.points.len()
    }

    /// Number of shading voxels.
    pub fn num_leaves(&self) -> usize {
        self.leaves.len()
    }

    /// The shading voxel containing `x`: descends from the root (SHH Sec. 6.3).
    fn leaf_of(&self, x: [f64; 3]) -> Result<(u32, [u32; 3])> {
        for level in 0..=self.lattice.max_level {
            let v = self.lattice.voxel_of(x, level)?;
            if self.leaves.contains(&(level, v)) {
                return Ok((level, v));
            }
        }
        Err(Error::invalid(
            "point",
            format!("{x:?}"),
            "not in a shading voxel of the grid (not among the points it was built for)",
        ))
    }

    /// The coefficients at `x` interpolated from the 8 corners of its shading voxel with
    /// [`Interpolation::Hermite`] (values and gradients; mixed derivatives taken as zero).
    pub fn interpolate(&self, x: [f64; 3]) -> Result<Vec<f64>> {
        self.interpolate_with(x, Interpolation::Hermite)
    }

    /// The coefficients at `x` interpolated from the 8 corners of its shading voxel.
    pub fn interpolate_with(&self, x: [f64; 3], scheme: Interpolation) -> Result<Vec<f64>> {
        let (level, v) = self.leaf_of(x)?;
        let cell = self.lattice.cell(level);
        let origin = self.lattice.point(self.lattice.corner(level, v, 0));
        let t: [f64; 3] = std::array::from_fn(|i| ((x[i] - origin[i]) / cell[i]).clamp(0.0, 1.0));
        let mut out = vec![0.0; crate::sh::num_coeffs(self.lmax)];
        let serendipity =
            (scheme == Interpolation::Serendipity).then(|| serendipity_weights(t, cell));
        for c in 0..8 {
            let p = &self.points[&self.lattice.corner(level, v, c)];
            let (wv, wg) = match (scheme, &serendipity) {
                (Interpolation::Trilinear, _) => {
                    let w = (0..3)
                        .map(|i| if (c >> i) & 1 == 0 { 1.0 - t[i] } else { t[i] })
                        .product();
                    (w, [0.0; 3])
                }
                (_, Some(w)) => w[c],
                _ => hermite_weights(t, c, cell),
            };
            for (k, o) in out.iter_mut().enumerate() {
                let g = p.gradients[k];
                *o += wv * p.coefficients[k] + wg[0] * g[0] + wg[1] * g[1] + wg[2] * g[2];
            }
        }
        Ok(out)
    }
}

/// The 32 monomials `t^a` spanning the cubic serendipity space of the cube (superlinear
/// degree at most 3, Arnold & Awanou 2011): all of degree <= 3, `x^3 y` and the like,
/// `x^2 y z` and the like, `x^3 y z` and the like.
fn serendipity_exponents() -> Vec<[i32; 3]> {
    let mut e = Vec::new();
    for a in 0..=3 {
        for b in 0..=3 {
            for c in 0..=3 {
                let superlinear: i32 = [a, b, c].iter().filter(|&&k| k >= 2).sum();
                if superlinear <= 3 {
                    e.push([a, b, c]);
                }
            }
        }
    }
    e
}

/// `(t^a, d/dt_i t^a)` for `i = 0, 1, 2`.
fn monomial(a: [i32; 3], t: [f64; 3]) -> (f64, [f64; 3]) {
    let p = |i: usize, k: i32| if k < 0 { 0.0 } else { t[i].powi(k) };
    let v = p(0, a[0]) * p(1, a[1]) * p(2, a[2]);
    let d = [
        a[0] as f64 * p(0, a[0] - 1) * p(1, a[1]) * p(2, a[2]),
        a[1] as f64 * p(0, a[0]) * p(1, a[1] - 1) * p(2, a[2]),
        a[2] as f64 * p(0, a[0]) * p(1, a[1]) * p(2, a[2] - 1),
    ];
    (v, d)
}

/// The exponents and the inverse of the 32 x 32 matrix of corner values and gradients
/// of the monomials on the unit cube (computed once).
fn serendipity_basis() -> &'static (Vec<[i32; 3]>, DMatrix<f64>) {
    static BASIS: OnceLock<(Vec<[i32; 3]>, DMatrix<f64>)> = OnceLock::new();
    BASIS.get_or_init(|| {
        let e = serendipity_exponents();
        // Rows: functionals (corner c: value, d/dx, d/dy, d/dz); columns: monomials.
        let m = DMatrix::from_fn(32, e.len(), |r, k| {
            let c = r / 4;
            let corner = std::array::from_fn(|i| ((c >> i) & 1) as f64);
            let (v, d) = monomial(e[k], corner);
            if r % 4 == 0 {
                v
            } else {
                d[r % 4 - 1]
            }
        });
        let inv = m
            .try_inverse()
            .expect("the cubic Hermite serendipity element is unisolvent");
        (e, inv)
    })
}

/// Weights of the 8 corners (bits x, y, z) of a voxel with edge lengths `cell` at local
/// coordinates `t` in `[0, 1]^3`, for their values and gradients: the cubic Hermite
/// serendipity interpolant (the 32-dimensional space of `serendipity_exponents`,
/// fixed by the corner values and gradients). It reproduces every cubic polynomial, so
/// the interpolation error of a smooth field is `O(h^4)`; along each edge it is the 1D
/// cubic Hermite interpolant (`proofs/polygon-lights.md`, Sec. 5).
pub(crate) fn serendipity_weights(t: [f64; 3], cell: [f64; 3]) -> [(f64, [f64; 3]); 8] {
    let (e, inv) = serendipity_basis();
    let mono: Vec<f64> = e.iter().map(|&a| monomial(a, t).0).collect();
    std::array::from_fn(|c| {
        let w = |r: usize| {
            (0..mono.len())
                .map(|k| inv[(k, 4 * c + r)] * mono[k])
                .sum::<f64>()
        };
        (w(0), std::array::from_fn(|i| w(i + 1) * cell[i]))
    })
}

/// Weights of corner `c` (bits x, y, z) of a voxel with edge lengths `cell` at local
/// coordinates `t` in `[0, 1]^3`, for its value and its gradient: the tensor product of
/// the cubic Hermite basis `h0(t) = 1 - 3t^2 + 2t^3` (value at the corner's end,
/// `h0(1 - t)` at the far end) and `h1(t) = t (1 - t)^2` (derivative, `-h1(1 - t)` at the
/// far end), with the mixed derivatives taken as zero. Exact for affine fields, and along
/// each edge the 1D cubic Hermite interpolant.
pub(crate) fn hermite_weights(t: [f64; 3], c: usize, cell: [f64; 3]) -> (f64, [f64; 3]) {
    let h0 = |s: f64| 1.0 - s * s * (3.0 - 2.0 * s);
    let h1 = |s: f64| s * (1.0 - s) * (1.0 - s);
    let mut value = [0.0; 3];
    let mut slope = [0.0; 3];
    for i in 0..3 {
        if (c >> i) & 1 == 0 {
            value[i] = h0(t[i]);
            slope[i] = h1(t[i]) * cell[i];
        } else {
            value[i] = h0(1.0 - t[i]);
            slope[i] = -h1(1.0 - t[i]) * cell[i];
        }
    }
    let wv = value[0] * value[1] * value[2];
    let wg = [
        slope[0] * value[1] * value[2],
        value[0] * slope[1] * value[2],
        value[0] * value[1] * slope[2],
    ];
    (wv, wg)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hermite weights reproduce affine functions exactly and the corner values at the
    /// corners.
    #[test]
    fn hermite_reproduces_affine_fields() {
        let cell = [0.5, 2.0, 1.5];
        let f = |x: [f64; 3]| 0.3 + 1.1 * x[0] - 0.7 * x[1] + 2.0 * x[2];
        let grad = [1.1, -0.7, 2.0];
        for t in [[0.2, 0.7, 0.4], [0.0, 0.0, 0.0], [1.0, 0.5, 0.9]] {
            let x: [f64; 3] = std::array::from_fn(|i| t[i] * cell[i]);
            let mut s = 0.0;
            for c in 0..8 {
                let xc: [f64; 3] = std::array::from_fn(|i| ((c >> i) & 1) as f64 * cell[i]);
                let (wv, wg) = hermite_weights(t, c, cell);
                s += wv * f(xc) + wg[0] * grad[0] + wg[1] * grad[1] + wg[2] * grad[2];
            }
            assert!((s - f(x)).abs() < 1e-14, "{t:?}");
        }
    }

    /// A grid point inside a light, a NaN threshold, a query outside the shading voxels:
    /// errors. At the grid points themselves the interpolation returns the exact values.
    #[test]
    fn grid_errors_and_exact_corners() {
        use crate::lights::spherical::{SphericalLight, SphericalLights};
        let lat = Lattice::new([0.0; 3], [1.0; 3], 2).unwrap();
        let pts = [[0.1, 0.1, 0.1], [0.6, 0.3, 0.2]];
        let inside = SphericalLights::new(
            vec![SphericalLight::new([0.5, 0.5, 0.25], 0.1, 1.0).unwrap()],
            2,
        )
        .unwrap();
        assert!(LightGrid::build(&inside, lat, &pts, Refinement::Uniform).is_err());
        let lights = SphericalLights::new(
            vec![SphericalLight::new([0.5, 0.5, 2.0], 0.3, 1.0).unwrap()],
            2,
        )
        .unwrap();
        let nan = Refinement::Adaptive {
            metric: Metric::Relative,
            threshold: f64::NAN,
        };
        assert!(LightGrid::build(&lights, lat, &pts, nan).is_err());
        let g = LightGrid::build(&lights, lat, &pts, Refinement::Uniform).unwrap();
        assert_eq!(g.num_leaves(), 2);
        assert!(g.interpolate([0.9, 0.9, 0.9]).is_err());
        let corner = [0.0, 0.0, 0.0];
        let exact = lights.field(corner, Order::Values).unwrap().coefficients;
        assert_eq!(g.interpolate(corner).unwrap(), exact);
    }

    /// The serendipity space has 32 monomials; its weights reproduce a cubic and the
    /// corner data at the corners.
    #[test]
    fn serendipity_reproduces_cubics() {
        assert_eq!(serendipity_exponents().len(), 32);
        let cell = [0.5, 2.0, 1.5];
        let f = |x: [f64; 3]| {
            0.3 + x[0] - x[1] * x[2] + x[0] * x[1] * x[2] + 0.5 * x[0].powi(3) - x[1] * x[1] * x[0]
        };
        let g = |x: [f64; 3]| {
            [
                1.0 + x[1] * x[2] + 1.5 * x[0] * x[0] - x[1] * x[1],
                -x[2] + x[0] * x[2] - 2.0 * x[1] * x[0],
                -x[1] + x[0] * x[1],
            ]
        };
        for t in [[0.2, 0.7, 0.4], [0.0, 0.0, 0.0], [1.0, 0.5, 0.9]] {
            let x: [f64; 3] = std::array::from_fn(|i| t[i] * cell[i]);
            let w = serendipity_weights(t, cell);
            let mut s = 0.0;
            for (c, (wv, wg)) in w.iter().enumerate() {
                let xc: [f64; 3] = std::array::from_fn(|i| ((c >> i) & 1) as f64 * cell[i]);
                let gc = g(xc);
                s += wv * f(xc) + wg[0] * gc[0] + wg[1] * gc[1] + wg[2] * gc[2];
            }
            assert!((s - f(x)).abs() < 1e-12, "{t:?}: {s} vs {}", f(x));
        }
    }

    #[test]
    fn eigenvalue_of_diagonal_and_rotated() {
        assert_eq!(max_abs_eigenvalue(&[1.0, 0.0, 0.0, -3.0, 0.0, 2.0]), 3.0);
        // [[0,1,0],[1,0,0],[0,0,0]] has eigenvalues +-1, 0.
        assert!((max_abs_eigenvalue(&[0.0, 1.0, 0.0, 0.0, 0.0, 0.0]) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn occupancy_marks_ancestors_and_rejects_outside_points() {
        let lat = Lattice::new([0.0; 3], [1.0; 3], 3).unwrap();
        let oc = OccupancyOctree::new(&lat, &[[0.1, 0.1, 0.1], [0.9, 0.9, 0.9]]).unwrap();
        assert!(oc.is_occupied(0, [0, 0, 0]));
        assert!(oc.is_occupied(3, [0, 0, 0]) && oc.is_occupied(3, [7, 7, 7]));
        assert!(oc.is_occupied(1, [1, 1, 1]) && !oc.is_occupied(1, [1, 0, 0]));
        assert!(OccupancyOctree::new(&lat, &[[1.5, 0.0, 0.0]]).is_err());
        assert!(OccupancyOctree::new(&lat, &[[f64::NAN, 0.0, 0.0]]).is_err());
        assert!(Lattice::new([0.0; 3], [1.0, 0.0, 1.0], 3).is_err());
    }
}
