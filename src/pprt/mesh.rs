//! Triangle meshes with per-vertex normals: procedural spheres, planes and tori, and
//! triangle soups as files hold them ([`crate::io::obj`] reads OBJ files).

use crate::error::{Error, Result};
use nalgebra::Vector3;
use std::f64::consts::PI;

/// Smallest triangle area accepted (relative to the squared longest edge).
const DEGENERATE_AREA: f64 = 1e-14;

/// A triangle mesh: positions, unit normals and triangles (counter-clockwise seen from
/// the side the normals point to).
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    positions: Vec<[f64; 3]>,
    normals: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    /// Degenerate triangles dropped when reading a file.
    dropped: usize,
}

/// Whether a triangle has (numerically) zero area.
fn degenerate(positions: &[[f64; 3]], t: &[u32; 3]) -> bool {
    let [a, b, c] = t.map(|i| Vector3::from(positions[i as usize]));
    let cross = (b - a).cross(&(c - a));
    let edge = (b - a)
        .norm_squared()
        .max((c - a).norm_squared())
        .max((c - b).norm_squared());
    edge == 0.0 || cross.norm() <= DEGENERATE_AREA * edge
}

impl Mesh {
    /// A mesh from positions, optional normals (computed as area-weighted averages of the
    /// faces' normals when `None`) and triangles. Errors: non-finite positions or normals,
    /// indices out of range, degenerate triangles, a vertex whose normal vanishes; each
    /// naming the index.
    pub fn new(
        positions: Vec<[f64; 3]>,
        normals: Option<Vec<[f64; 3]>>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<Self> {
        let bad =
            |name: &'static str, value: String, reason: &str| Error::invalid(name, value, reason);
        if let Some(i) = positions
            .iter()
            .position(|p| p.iter().any(|x| !x.is_finite()))
        {
            return Err(bad(
                "mesh vertex",
                format!("#{i}: {:?}", positions[i]),
                "finite coordinates",
            ));
        }
        let n = positions.len();
        let mut face_sum = vec![Vector3::zeros(); n];
        for (k, t) in triangles.iter().enumerate() {
            if t.iter().any(|&i| i as usize >= n) {
                return Err(bad(
                    "mesh triangle",
                    format!("#{k}: {t:?}"),
                    "vertex index out of range",
                ));
            }
            if degenerate(&positions, t) {
                return Err(bad(
                    "mesh triangle",
                    format!("#{k}: {t:?}"),
                    "degenerate (zero area)",
                ));
            }
            let [a, b, c] = t.map(|i| Vector3::from(positions[i as usize]));
            let cross = (b - a).cross(&(c - a));
            for &i in t {
                face_sum[i as usize] += cross;
            }
        }
        let normals = match normals {
            Some(v) => {
                crate::error::check_len("mesh normals", n, v.len())?;
                v
            }
            None => face_sum.iter().map(|s| [s.x, s.y, s.z]).collect(),
        };
        let normals = normals
            .iter()
            .enumerate()
            .map(|(i, m)| {
                let v = Vector3::from(*m);
                let len = v.norm();
                if !(len.is_finite() && len > 0.0) {
                    return Err(bad(
                        "mesh normal",
                        format!("#{i}: {m:?}"),
                        "finite and non-zero",
                    ));
                }
                Ok([v.x / len, v.y / len, v.z / len])
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Self {
            positions,
            normals,
            triangles,
            dropped: 0,
        })
    }

    /// A UV sphere of `rings` x `segments` quads (poles closed by triangles). Errors: a
    /// radius not positive, fewer than 2 rings or 3 segments, a mesh over the memory budget.
    pub fn sphere(center: [f64; 3], radius: f64, rings: usize, segments: usize) -> Result<Self> {
        if !(radius.is_finite() && radius > 0.0) || rings < 2 || segments < 3 {
            return Err(Error::invalid(
                "sphere",
                format!("radius {radius}, {rings} rings, {segments} segments"),
                "radius > 0, at least 2 rings and 3 segments",
            ));
        }
        // Per vertex: position and normal (48 bytes), two triangles (24).
        crate::budget::check(
            "sphere mesh",
            &[rings.saturating_add(1), segments.saturating_add(1)],
            72,
        )?;
        let mut positions = vec![[center[0], center[1], center[2] + radius]];
        let mut normals = vec![[0.0, 0.0, 1.0]];
        for r in 1..rings {
            let t = PI * r as f64 / rings as f64;
            for s in 0..segments {
                let p = 2.0 * PI * s as f64 / segments as f64;
                let n = [t.sin() * p.cos(), t.sin() * p.sin(), t.cos()];
                positions.push(std::array::from_fn(|k| center[k] + radius * n[k]));
                normals.push(n);
            }
        }
        positions.push([center[0], center[1], center[2] - radius]);
        normals.push([0.0, 0.0, -1.0]);
        let ring = |r: usize, s: usize| (1 + (r - 1) * segments + s % segments) as u32;
        let last = (positions.len() - 1) as u32;
        let mut triangles = Vec::new();
        for s in 0..segments {
            triangles.push([0, ring(1, s), ring(1, s + 1)]);
            for r in 1..rings - 1 {
                triangles.push([ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)]);
                triangles.push([ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)]);
            }
            triangles.push([ring(rings - 1, s), last, ring(rings - 1, s + 1)]);
        }
        Self::new(positions, Some(normals), triangles)
    }

    /// A torus about the axis `+z` through `center`: tube of radius `minor` around a
    /// circle of radius `major`, in `rings` x `segments` quads (around the axis, around
    /// the tube).
    pub fn torus(
        center: [f64; 3],
        major: f64,
        minor: f64,
        rings: usize,
        segments: usize,
    ) -> Result<Self> {
        if !(minor.is_finite() && minor > 0.0 && major.is_finite() && major > minor)
            || rings < 3
            || segments < 3
        {
            return Err(Error::invalid(
                "torus",
                format!("radii {major} and {minor}, {rings} rings, {segments} segments"),
                "major > minor > 0, at least 3 rings and 3 segments",
            ));
        }
        let mut positions = Vec::with_capacity(rings * segments);
        let mut normals = Vec::with_capacity(rings * segments);
        for r in 0..rings {
            let u = 2.0 * PI * r as f64 / rings as f64;
            for s in 0..segments {
                let v = 2.0 * PI * s as f64 / segments as f64;
                let n = [v.cos() * u.cos(), v.cos() * u.sin(), v.sin()];
                let radial = [u.cos(), u.sin(), 0.0];
                positions.push(std::array::from_fn(|k| {
                    center[k] + major * radial[k] + minor * n[k]
                }));
                normals.push(n);
            }
        }
        let id = |r: usize, s: usize| ((r % rings) * segments + s % segments) as u32;
        let mut triangles = Vec::with_capacity(2 * rings * segments);
        for r in 0..rings {
            for s in 0..segments {
                triangles.push([id(r, s), id(r + 1, s), id(r + 1, s + 1)]);
                triangles.push([id(r, s), id(r + 1, s + 1), id(r, s + 1)]);
            }
        }
        Self::new(positions, Some(normals), triangles)
    }

    /// A square in the plane `z = center[2]`, normal `+z`, of half-size `half`, split into
    /// `n x n` quads.
    pub fn plane(center: [f64; 3], half: f64, n: usize) -> Result<Self> {
        if !(half.is_finite() && half > 0.0) || n == 0 {
            return Err(Error::invalid(
                "plane",
                format!("half-size {half}, {n} quads"),
                "half-size > 0 and at least one quad",
            ));
        }
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                positions.push([
                    center[0] + half * (2.0 * u - 1.0),
                    center[1] + half * (2.0 * v - 1.0),
                    center[2],
                ]);
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let normals = vec![[0.0, 0.0, 1.0]; positions.len()];
        Self::new(positions, Some(normals), triangles)
    }

    /// A mesh from a triangle soup as files hold it: degenerate triangles (as n-gon
    /// triangulation leaves them) dropped and counted by [`Self::dropped`], normals
    /// computed when `normals` is `None`. Errors: an index out of range, no triangle of
    /// non-zero area, and as [`Self::new`].
    pub fn from_soup(
        positions: Vec<[f64; 3]>,
        normals: Option<Vec<[f64; 3]>>,
        mut triangles: Vec<[u32; 3]>,
    ) -> Result<Self> {
        let value = format!(
            "{} vertices, {} triangles",
            positions.len(),
            triangles.len()
        );
        let bad = |reason: String| Error::invalid("mesh", value.clone(), reason);
        if let Some(k) = triangles
            .iter()
            .position(|t| t.iter().any(|&i| i as usize >= positions.len()))
        {
            return Err(bad(format!("triangle {k}: vertex index out of range")));
        }
        let total = triangles.len();
        triangles.retain(|t| !degenerate(&positions, t));
        if triangles.is_empty() {
            return Err(bad(format!(
                "no triangles of non-zero area ({total} given)"
            )));
        }
        let dropped = total - triangles.len();
        let mut mesh = Self::new(positions, normals, triangles)?;
        mesh.dropped = dropped;
        Ok(mesh)
    }

    /// Degenerate triangles dropped when reading a file.
    pub fn dropped(&self) -> usize {
        self.dropped
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.positions
    }

    /// Unit vertex normals.
    pub fn normals(&self) -> &[[f64; 3]] {
        &self.normals
    }

    /// Triangles.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The mesh rotated by `r` about the origin.
    pub fn rotated(&self, r: &nalgebra::Rotation3<f64>) -> Mesh {
        let turn = |v: &[f64; 3]| {
            let w = r * Vector3::from(*v);
            [w.x, w.y, w.z]
        };
        Mesh {
            positions: self.positions.iter().map(turn).collect(),
            normals: self.normals.iter().map(turn).collect(),
            triangles: self.triangles.clone(),
            dropped: self.dropped,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn procedural_meshes_and_errors() {
        let s = Mesh::sphere([0.0, 0.0, 1.0], 0.5, 8, 12).unwrap();
        assert_eq!(s.positions().len(), 2 + 7 * 12);
        // Outward normals: the triangles wind counter-clockwise seen from outside.
        for t in s.triangles() {
            let [a, b, c] = t.map(|i| Vector3::from(s.positions()[i as usize]));
            let n = (b - a).cross(&(c - a));
            let centroid = (a + b + c) / 3.0 - Vector3::new(0.0, 0.0, 1.0);
            assert!(n.dot(&centroid) > 0.0);
        }
        let p = Mesh::plane([0.0; 3], 2.0, 3).unwrap();
        assert_eq!((p.positions().len(), p.triangles().len()), (16, 18));
        let computed = Mesh::new(p.positions().to_vec(), None, p.triangles().to_vec()).unwrap();
        assert_eq!(computed.normals()[5], [0.0, 0.0, 1.0]);
        let e = Mesh::new(
            vec![[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
            None,
            vec![[0, 1, 2]],
        )
        .unwrap_err();
        assert!(e.to_string().contains("degenerate"), "{e}");
        let e = Mesh::new(vec![[0.0; 3]], None, vec![[0, 1, 2]]).unwrap_err();
        assert!(e.to_string().contains("out of range"), "{e}");
        let tri = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let m = Mesh::from_soup(tri.clone(), None, vec![[0, 1, 2], [0, 1, 1]]).unwrap();
        assert_eq!((m.triangles().len(), m.dropped()), (1, 1));
        let e = Mesh::from_soup(tri.clone(), None, vec![[0, 1, 1]]).unwrap_err();
        assert!(e.to_string().contains("non-zero area"), "{e}");
        let e = Mesh::from_soup(tri, None, vec![[0, 1, 4]]).unwrap_err();
        assert!(e.to_string().contains("out of range"), "{e}");
    }

    /// The torus is closed (every edge shared by exactly two triangles, in opposite
    /// directions), its triangles face along its vertex normals, and each vertex lies at
    /// the tube radius from the core circle along its normal.
    #[test]
    fn torus_is_closed_and_faces_out() {
        let c = [0.5, -1.0, 0.3];
        let t = Mesh::torus(c, 1.0, 0.25, 24, 12).unwrap();
        assert_eq!((t.positions().len(), t.triangles().len()), (288, 576));
        let mut edges = std::collections::HashMap::new();
        for tri in t.triangles() {
            for k in 0..3 {
                *edges.entry((tri[k], tri[(k + 1) % 3])).or_insert(0) += 1;
            }
            let [a, b, d] = tri.map(|i| Vector3::from(t.positions()[i as usize]));
            let face = (b - a).cross(&(d - a));
            let n: Vector3<f64> = tri
                .iter()
                .map(|&i| Vector3::from(t.normals()[i as usize]))
                .sum();
            assert!(face.dot(&n) > 0.0);
        }
        for (&(a, b), &count) in &edges {
            assert_eq!((count, edges.get(&(b, a))), (1, Some(&1)), "edge {a}-{b}");
        }
        for (p, n) in t.positions().iter().zip(t.normals()) {
            let q: [f64; 3] = std::array::from_fn(|k| p[k] - c[k] - 0.25 * n[k]);
            assert!((q[2].abs() + ((q[0] * q[0] + q[1] * q[1]).sqrt() - 1.0).abs()) < 1e-14);
        }
        for bad in [(0.2, 0.25), (1.0, 0.0), (f64::NAN, 0.1)] {
            let e = Mesh::torus(c, bad.0, bad.1, 24, 12).unwrap_err();
            assert!(e.to_string().contains("torus"), "{e}");
        }
    }
}
