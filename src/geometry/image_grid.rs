//! Pixel grids on the sphere: the direction and exact solid angle of every texel of an
//! equirectangular image or of a cube map stored as a 3 x 4 cross.
//!
//! Cube cross (`docs/conventions.md` §12): an image of `3e` rows by `4e` columns;
//! Up at row-block 0 column-block 1; Left, Front, Right, Back at row-block 1, columns 0..3;
//! Down at row-block 2 column-block 1; world `x, y, z` = Right, Front, Up. Each face is a
//! 90-degree perspective camera with image-right `r`, image-up `u` and forward `f`:
//!
//! | face | f | r | u |
//! |---|---|---|---|
//! | Front | +y | +x | +z |
//! | Right | +x | -y | +z |
//! | Back | -y | -x | +z |
//! | Left | -x | +y | +z |
//! | Up | +z | +x | -y |
//! | Down | -z | +x | +y |
//!
//! Texel `(i, j)` of a face (row `i` from the top) has face coordinates
//! `a = 2 (j + 1/2)/e - 1` (right), `b = 1 - 2 (i + 1/2)/e` (up), direction
//! `normalize(f + a r + b u)`, and solid angle by the exact formula for a rectangle on the
//! plane at unit distance, `Omega = F(a1, b1) - F(a0, b1) - F(a1, b0) + F(a0, b0)` with
//! `F(a, b) = atan(a b / sqrt(1 + a^2 + b^2))` (derived in `proofs/pixel-solid-angles.md`).
//!
//! Equirectangular: `H` rows by `W` columns, row `i` spans polar angles
//! `[pi i / H, pi (i+1) / H]` (theta from +z), column `j` spans azimuths
//! `[2 pi j / W, 2 pi (j+1) / W]` (phi from +x towards +y); texel solid angle
//! `(cos theta_0 - cos theta_1) 2 pi / W`.

use crate::error::{Error, Result};
use std::f64::consts::PI;

/// A set of texels covering the sphere, each with a direction and a solid angle.
pub trait PixelGrid {
    /// Number of texels (row-major over the image).
    fn len(&self) -> usize;
    /// Whether there are no texels.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Unit direction of texel `i`'s centre.
    fn direction(&self, i: usize) -> [f64; 3];
    /// Exact solid angle of texel `i`.
    fn solid_angle(&self, i: usize) -> f64;
    /// Spherical angles `(theta, phi)` of texel `i`'s centre (by default from its
    /// direction; grids of constant-theta rows give the row's exact angle, so that
    /// texels of one row share it bit for bit). Error: a texel without a direction.
    fn angles(&self, i: usize) -> Result<(f64, f64)> {
        crate::geometry::direction_angles(self.direction(i))
    }
}

/// Faces of the cube cross.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CubeFace {
    /// Forward `+y`; block `(1, 1)` of the cross.
    Front,
    /// Forward `+x`; block `(1, 2)`.
    Right,
    /// Forward `-y`; block `(1, 3)`.
    Back,
    /// Forward `-x`; block `(1, 0)`.
    Left,
    /// Forward `+z`; block `(0, 1)`.
    Up,
    /// Forward `-z`; block `(2, 1)`.
    Down,
}

impl CubeFace {
    /// `(forward, right, up)` of the face's camera.
    pub fn basis(self) -> ([f64; 3], [f64; 3], [f64; 3]) {
        match self {
            CubeFace::Front => ([0., 1., 0.], [1., 0., 0.], [0., 0., 1.]),
            CubeFace::Right => ([1., 0., 0.], [0., -1., 0.], [0., 0., 1.]),
            CubeFace::Back => ([0., -1., 0.], [-1., 0., 0.], [0., 0., 1.]),
            CubeFace::Left => ([-1., 0., 0.], [0., 1., 0.], [0., 0., 1.]),
            CubeFace::Up => ([0., 0., 1.], [1., 0., 0.], [0., -1., 0.]),
            CubeFace::Down => ([0., 0., -1.], [1., 0., 0.], [0., 1., 0.]),
        }
    }

    /// The block `(row, col)` of the face in the 3 x 4 cross.
    pub fn block(self) -> (usize, usize) {
        match self {
            CubeFace::Up => (0, 1),
            CubeFace::Left => (1, 0),
            CubeFace::Front => (1, 1),
            CubeFace::Right => (1, 2),
            CubeFace::Back => (1, 3),
            CubeFace::Down => (2, 1),
        }
    }

    /// The face at block `(row, col)` of the 3 x 4 cross, if any.
    pub fn at_block(row: usize, col: usize) -> Option<Self> {
        [
            CubeFace::Up,
            CubeFace::Left,
            CubeFace::Front,
            CubeFace::Right,
            CubeFace::Back,
            CubeFace::Down,
        ]
        .into_iter()
        .find(|f| f.block() == (row, col))
    }
}

/// A cube map stored as a 3 x 4 cross of faces of `edge` x `edge` texels. Texels are
/// indexed row-major over the whole `3 edge x 4 edge` image; the six unused blocks of
/// the cross have zero solid angle.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CubeCross {
    /// Face edge length in texels.
    pub edge: usize,
}

impl CubeCross {
    /// A cross of faces of `edge` texels.
    pub fn new(edge: usize) -> Result<Self> {
        if edge == 0 {
            return Err(Error::GridTooSmall {
                reason: "a cube map face needs at least one texel".into(),
            });
        }
        // The cross has 12 e^2 texels: sizes that overflow are refused here, so that every
        // later product fits.
        let texels = edge
            .checked_mul(3)
            .zip(edge.checked_mul(4))
            .and_then(|(h, w)| h.checked_mul(w));
        if texels.is_none() {
            return Err(Error::invalid(
                "cube map edge",
                edge.to_string(),
                "the cross's 3e x 4e texels overflow",
            ));
        }
        Ok(Self { edge })
    }

    /// The cross layout of an image of `height x width`, which must be `3e x 4e`.
    pub fn from_image_size(height: usize, width: usize) -> Result<Self> {
        if height == 0 || !height.is_multiple_of(3) || width * 3 != height * 4 {
            return Err(Error::invalid(
                "cube cross size",
                format!("{height} x {width}"),
                "a cube cross has 3e rows and 4e columns",
            ));
        }
        Self::new(height / 3)
    }

    /// Image height `3 edge`.
    pub fn height(&self) -> usize {
        3 * self.edge
    }

    /// Image width `4 edge`.
    pub fn width(&self) -> usize {
        4 * self.edge
    }

    /// The texel containing the direction `w` (any length; `None` for zero or non-finite):
    /// the face whose forward axis has the largest component of `w` (the first of `x`, `y`,
    /// `z` on a tie), and on it the texel whose rectangle holds `(a, b) = (w.r, w.u) / w.f`
    /// (the inverse of the module's texel map; a point on a texel edge goes to the texel
    /// right of it or below it).
    pub fn texel_at(&self, w: [f64; 3]) -> Option<usize> {
        let abs = w.map(f64::abs);
        if !abs.iter().all(|x| x.is_finite()) || abs.iter().all(|&x| x == 0.0) {
            return None;
        }
        let axis = if abs[0] >= abs[1] && abs[0] >= abs[2] {
            0
        } else if abs[1] >= abs[2] {
            1
        } else {
            2
        };
        let face = match (axis, w[axis] > 0.0) {
            (0, true) => CubeFace::Right,
            (0, false) => CubeFace::Left,
            (1, true) => CubeFace::Front,
            (1, false) => CubeFace::Back,
            (_, true) => CubeFace::Up,
            (_, false) => CubeFace::Down,
        };
        let (f, r, u) = face.basis();
        let dot = |v: [f64; 3]| w[0] * v[0] + w[1] * v[1] + w[2] * v[2];
        let d = dot(f);
        let (a, b) = (dot(r) / d, dot(u) / d);
        let e = self.edge;
        let cell = |t: f64| ((0.5 * t * e as f64).floor() as usize).min(e - 1);
        let (j, i) = (cell(a + 1.0), cell(1.0 - b));
        let (block_row, block_col) = face.block();
        Some((block_row * e + i) * self.width() + block_col * e + j)
    }

    /// The face and face coordinates `(a0, a1, b0, b1)` (texel rectangle on the unit-distance
    /// plane, `a` to the right, `b` up) of image texel `i`, or `None` off the cross.
    pub fn texel(&self, i: usize) -> Option<(CubeFace, [f64; 4])> {
        let e = self.edge;
        let (row, col) = (i / self.width(), i % self.width());
        let face = CubeFace::at_block(row / e, col / e)?;
        let (ti, tj) = ((row % e) as f64, (col % e) as f64);
        let s = 2.0 / e as f64;
        Some((
            face,
            [
                tj * s - 1.0,
                (tj + 1.0) * s - 1.0,
                1.0 - (ti + 1.0) * s,
                1.0 - ti * s,
            ],
        ))
    }
}

fn face_area(a: f64, b: f64) -> f64 {
    (a * b / (1.0 + a * a + b * b).sqrt()).atan()
}

impl PixelGrid for CubeCross {
    fn len(&self) -> usize {
        self.height() * self.width()
    }

    fn direction(&self, i: usize) -> [f64; 3] {
        let Some((face, [a0, a1, b0, b1])) = self.texel(i) else {
            return [0.0, 0.0, 0.0];
        };
        let (f, r, u) = face.basis();
        let (a, b) = (0.5 * (a0 + a1), 0.5 * (b0 + b1));
        let v = [0, 1, 2].map(|k| f[k] + a * r[k] + b * u[k]);
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|c| c / n)
    }

    fn solid_angle(&self, i: usize) -> f64 {
        match self.texel(i) {
            Some((_, [a0, a1, b0, b1])) => {
                face_area(a1, b1) - face_area(a0, b1) - face_area(a1, b0) + face_area(a0, b0)
            }
            None => 0.0,
        }
    }
}

/// An equirectangular image of `height x width` texels.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Equirect {
    /// Rows (polar angle).
    pub height: usize,
    /// Columns (azimuth).
    pub width: usize,
}

impl Equirect {
    /// An equirectangular grid (both sizes at least 1).
    pub fn new(height: usize, width: usize) -> Result<Self> {
        if height == 0 || width == 0 {
            return Err(Error::GridTooSmall {
                reason: format!("equirectangular image {height} x {width} is empty"),
            });
        }
        if height.checked_mul(width).is_none() {
            return Err(Error::invalid(
                "equirectangular image",
                format!("{height} x {width}"),
                "the number of texels overflows",
            ));
        }
        Ok(Self { height, width })
    }

    /// The texel containing the direction `w` (any length; `None` for zero or non-finite):
    /// row `floor(theta H / pi)`, column `floor(phi W / 2 pi)` (the last row and column
    /// take `theta = pi`, `phi` rounded to `2 pi`).
    pub fn texel_at(&self, w: [f64; 3]) -> Option<usize> {
        if !w.iter().all(|x| x.is_finite()) || w.iter().all(|&x| x == 0.0) {
            return None;
        }
        let theta = w[0].hypot(w[1]).atan2(w[2]);
        let phi = w[1].atan2(w[0]).rem_euclid(2.0 * PI);
        let row = ((theta / PI * self.height as f64).floor() as usize).min(self.height - 1);
        let col = ((phi / (2.0 * PI) * self.width as f64).floor() as usize).min(self.width - 1);
        Some(row * self.width + col)
    }

    /// `(theta, phi)` of the centre of texel `i`.
    fn cell_centre(&self, i: usize) -> (f64, f64) {
        let (row, col) = (i / self.width, i % self.width);
        (
            PI * (row as f64 + 0.5) / self.height as f64,
            2.0 * PI * (col as f64 + 0.5) / self.width as f64,
        )
    }
}

impl PixelGrid for Equirect {
    fn len(&self) -> usize {
        self.height * self.width
    }

    fn direction(&self, i: usize) -> [f64; 3] {
        let (theta, phi) = self.cell_centre(i);
        crate::geometry::direction(theta, phi)
    }

    fn angles(&self, i: usize) -> Result<(f64, f64)> {
        Ok(self.cell_centre(i))
    }

    fn solid_angle(&self, i: usize) -> f64 {
        let row = i / self.width;
        let t0 = PI * row as f64 / self.height as f64;
        let t1 = PI * (row + 1) as f64 / self.height as f64;
        // cos t0 - cos t1 = 2 sin((t0+t1)/2) sin((t1-t0)/2), without cancellation.
        2.0 * (0.5 * (t0 + t1)).sin() * (0.5 * (t1 - t0)).sin() * 2.0 * PI / self.width as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sizes whose texel count overflows are errors, never an overflow (debug builds
    /// check every product).
    #[test]
    fn overflowing_sizes_are_refused() {
        for edge in [usize::MAX / 4 + 1, usize::MAX / 3, 1 << 32, usize::MAX] {
            assert!(CubeCross::new(edge).is_err(), "{edge}");
        }
        assert!(CubeCross::new(1 << 20).is_ok());
        assert!(Equirect::new(usize::MAX, 2).is_err());
        assert!(Equirect::new(1 << 20, 1 << 21).is_ok());
    }

    #[test]
    fn solid_angles_sum_to_the_sphere() {
        for g in [CubeCross::new(1).unwrap(), CubeCross::new(7).unwrap()] {
            let s: f64 = (0..g.len()).map(|i| g.solid_angle(i)).sum();
            assert!((s - 4.0 * PI).abs() < 1e-12, "{s}");
        }
        let e = Equirect::new(9, 17).unwrap();
        let s: f64 = (0..e.len()).map(|i| e.solid_angle(i)).sum();
        assert!((s - 4.0 * PI).abs() < 1e-12);
    }

    /// Adjacent faces meet: the texel of Front's top row and the texel of Up's bottom row
    /// in the same column are neighbours across the edge (their directions are close).
    #[test]
    fn cross_faces_are_continuous_across_edges() {
        let g = CubeCross::new(32).unwrap();
        let e = g.edge;
        let w = g.width();
        let dist = |i: usize, j: usize| {
            let (a, b) = (g.direction(i), g.direction(j));
            ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
        };
        let step = 2.0 / e as f64;
        for k in [0, 5, e - 1] {
            // Up bottom row / Front top row, column k of block 1.
            assert!(dist((e - 1) * w + e + k, e * w + e + k) < 1.5 * step);
            // Front bottom row / Down top row.
            assert!(dist((2 * e - 1) * w + e + k, 2 * e * w + e + k) < 1.5 * step);
            // Front right column / Right left column, row k of block 1.
            assert!(dist((e + k) * w + 2 * e - 1, (e + k) * w + 2 * e) < 1.5 * step);
            // Back right column / Left left column (wrap around).
            assert!(dist((e + k) * w + 4 * e - 1, (e + k) * w) < 1.5 * step);
        }
    }

    /// `texel_at` inverts `direction` on every texel of the cross and of an
    /// equirectangular grid, and puts random directions (and the poles, the axes, face
    /// edges and the azimuth seam) in the texel whose rectangle holds them.
    #[test]
    fn texel_at_finds_the_texel_holding_a_direction() {
        let g = CubeCross::new(7).unwrap();
        for i in (0..g.len()).filter(|&i| g.texel(i).is_some()) {
            assert_eq!(g.texel_at(g.direction(i)), Some(i), "{i}");
        }
        let q = Equirect::new(9, 18).unwrap();
        for i in 0..q.len() {
            assert_eq!(q.texel_at(q.direction(i)), Some(i), "{i}");
        }
        let r = crate::random::pseudo_random(3 * 4000, 5);
        let mut dirs: Vec<[f64; 3]> = r
            .chunks_exact(3)
            .map(|c| [c[0] - 0.5, c[1] - 0.5, c[2] - 0.5])
            .collect();
        let s = std::f64::consts::FRAC_1_SQRT_2;
        dirs.extend([
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [s, s, 0.0],
            [s, 0.0, -s],
            [1.0, -1e-300, 0.3],
            [1.0, 1.0, 1.0],
        ]);
        for w in dirs {
            // Cube: the face coordinates of w lie in the texel's rectangle.
            let i = g.texel_at(w).unwrap();
            let (face, [a0, a1, b0, b1]) = g.texel(i).unwrap();
            let (f, rr, u) = face.basis();
            let dot = |v: [f64; 3]| w[0] * v[0] + w[1] * v[1] + w[2] * v[2];
            let (a, b) = (dot(rr) / dot(f), dot(u) / dot(f));
            assert!(dot(f) > 0.0, "{w:?}");
            let eps = 1e-12;
            assert!(
                a0 - eps <= a && a <= a1 + eps && b0 - eps <= b && b <= b1 + eps,
                "{w:?}"
            );
            // Equirect: the angles of w lie in the texel's row and column.
            let i = q.texel_at(w).unwrap();
            let (theta, phi) = crate::geometry::direction_angles({
                let n = dot(w).sqrt();
                w.map(|x| x / n)
            })
            .unwrap();
            let (row, col) = (i / q.width, i % q.width);
            let (dt, dp) = (PI / q.height as f64, 2.0 * PI / q.width as f64);
            assert!(row as f64 * dt - eps <= theta && theta <= (row + 1) as f64 * dt + eps);
            let phi = phi.rem_euclid(2.0 * PI);
            let inside = col as f64 * dp - eps <= phi && phi <= (col + 1) as f64 * dp + eps;
            let wrapped = col == q.width - 1 && phi < eps;
            assert!(inside || wrapped, "{w:?} {phi} {col}");
        }
        for bad in [[0.0; 3], [f64::NAN, 0.0, 1.0], [f64::INFINITY, 0.0, 0.0]] {
            assert_eq!(g.texel_at(bad), None);
            assert_eq!(q.texel_at(bad), None);
        }
    }

    #[test]
    fn bad_sizes_are_errors() {
        assert!(CubeCross::from_image_size(64 * 3, 64 * 3).is_err());
        assert!(CubeCross::from_image_size(0, 0).is_err());
        assert!(CubeCross::from_image_size(192, 256).is_ok());
        assert!(Equirect::new(0, 4).is_err());
    }
}
