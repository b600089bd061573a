//! Projection PSH (32) of cube maps by the symmetry of the cube. The six faces are one
//! face turned by the cube's rotations `R_F` (`R_F C_Front = C_F` for the face cameras
//! `C`), and the cube-map frame field turns with them (`F_F(R_F w) = R_F F_Front(w)`, the
//! perspective rule being rotation covariant). So face `F`'s texels, read on the Front
//! face with the same components, are the field turned by `R_F^-1` (PSH (25)), and
//!
//! ```text
//! f = sum_F R_F [ project over the Front face of the data of F ]       (PSH (35))
//! ```
//!
//! The SH and spin-weighted SH are evaluated at one face's texels only, shared by all six
//! faces and every channel; the rotations are exact, so the result equals the texel-wise
//! quadrature over the whole cross ([`project_image`]) to rounding. The six faces'
//! coefficients are held at once: above [`FOLD_BYTES`] of them (high degrees), the cross is
//! projected as a whole instead, in the work space of one output.

use super::image::check_texel;
use super::{project_image, Codomain, PshVector};
use crate::error::{check_len, Result};
use crate::geometry::frame::{CubeMapFrameField, PerspectiveFrameField};
use crate::geometry::image_grid::{CubeCross, CubeFace, PixelGrid};
use nalgebra::Rotation3;

/// Bytes of the six faces' coefficients up to which the faces are folded onto one.
pub(crate) const FOLD_BYTES: usize = 64 << 20;

/// The faces, each with its block of the cross.
const FACES: [CubeFace; 6] = [
    CubeFace::Front,
    CubeFace::Right,
    CubeFace::Back,
    CubeFace::Left,
    CubeFace::Up,
    CubeFace::Down,
];

/// The texels of one face of a cross, row-major over the face.
struct Face<'a> {
    cross: &'a CubeCross,
    face: CubeFace,
}

impl Face<'_> {
    /// Index in the cross of the face's texel `k`.
    fn cross_index(&self, k: usize) -> usize {
        let e = self.cross.edge;
        let (br, bc) = self.face.block();
        (br * e + k / e) * self.cross.width() + bc * e + k % e
    }
}

impl PixelGrid for Face<'_> {
    fn len(&self) -> usize {
        self.cross.edge * self.cross.edge
    }

    fn direction(&self, k: usize) -> [f64; 3] {
        self.cross.direction(self.cross_index(k))
    }

    fn solid_angle(&self, k: usize) -> f64 {
        self.cross.solid_angle(self.cross_index(k))
    }
}

/// PSH coefficients of `l <= lmax` of cube-cross Stokes images whose components are in
/// the cube-map frame field ([`CubeMapFrameField`]); equal to
/// `project_image(grid, &CubeMapFrameField, channels, codomain, lmax)` to rounding, about
/// six times less basis evaluation (up to 64 MiB of face coefficients). A NaN or
/// infinite component on a face is an error naming the texel.
pub fn project_cube_map(
    grid: &CubeCross,
    channels: &[&[[f64; 4]]],
    codomain: Codomain,
    lmax: usize,
) -> Result<PshVector> {
    let nch = channels.len();
    for ch in channels {
        check_len("Stokes image", grid.len(), ch.len())?;
    }
    crate::sh::check_lmax(lmax)?;
    let face_values = crate::sh::num_coeffs(lmax).saturating_mul(codomain.components().len() * nch);
    if face_values.saturating_mul(6 * 8) > FOLD_BYTES {
        return project_image(grid, &CubeMapFrameField, channels, codomain, lmax);
    }
    let front = Face {
        cross: grid,
        face: CubeFace::Front,
    };
    // Channel `f * nch + c`: channel c of face FACES[f], on the Front face's texels.
    let mut folded = Vec::with_capacity(6 * nch);
    for &face in &FACES {
        let f = Face { cross: grid, face };
        for (c, ch) in channels.iter().enumerate() {
            let texels = (0..f.len())
                .map(|k| {
                    let i = f.cross_index(k);
                    check_texel(c, i, ch[i]).map(|()| ch[i])
                })
                .collect::<Result<Vec<[f64; 4]>>>()?;
            folded.push(texels);
        }
    }
    let refs: Vec<&[[f64; 4]]> = folded.iter().map(|v| v.as_slice()).collect();
    let camera = CubeMapFrameField::camera_frame(CubeFace::Front);
    let faces = project_image(
        &front,
        &PerspectiveFrameField::new(camera),
        &refs,
        codomain,
        lmax,
    )?;
    let per_face = faces.data().len() / 6;
    let mut sum = vec![0.0; per_face];
    for (f, &face) in FACES.iter().enumerate() {
        let part = PshVector::from_data(
            lmax,
            codomain,
            nch,
            faces.data()[f * per_face..(f + 1) * per_face].to_vec(),
        )?;
        let part = if face == CubeFace::Front {
            part
        } else {
            let m = CubeMapFrameField::camera_frame(face).matrix() * camera.matrix().transpose();
            // Each rotation is used once: its Wigner blocks streamed, not stored.
            part.rotated(&Rotation3::from_matrix_unchecked(m))?
        };
        for (s, x) in sum.iter_mut().zip(part.data()) {
            *s += x;
        }
    }
    PshVector::from_data(lmax, codomain, nch, sum)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Equal to the texel-wise quadrature over the whole cross, for every codomain.
    #[test]
    fn equals_the_whole_cross_quadrature() {
        let g = CubeCross::new(6).unwrap();
        let r = crate::random::pseudo_random(g.len() * 8, 7);
        let chans: Vec<Vec<[f64; 4]>> = (0..2)
            .map(|c| {
                (0..g.len())
                    .map(|i| std::array::from_fn(|p| r[(c * g.len() + i) * 4 + p]))
                    .collect()
            })
            .collect();
        let refs: Vec<&[[f64; 4]]> = chans.iter().map(|v| v.as_slice()).collect();
        for cod in [Codomain::Linear, Codomain::NoCircular, Codomain::Full] {
            let fast = project_cube_map(&g, &refs, cod, 7).unwrap();
            let slow = project_image(&g, &CubeMapFrameField, &refs, cod, 7).unwrap();
            let err = fast
                .data()
                .iter()
                .zip(slow.data())
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(err < 1e-14, "{cod:?}: {err}");
        }
        let mut bad = chans[1].clone();
        bad[g.width() * 7 + 2][3] = f64::NAN;
        let e = project_cube_map(&g, &[&chans[0], &bad], Codomain::Full, 3).unwrap_err();
        assert!(
            e.to_string()
                .contains(&format!("texel {}", g.width() * 7 + 2)),
            "{e}"
        );
    }
}
