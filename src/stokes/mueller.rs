//! Mueller matrices (numeric) and Mueller transforms (geometric), PSH (14), (21), (22),
//! (49), (59).
//!
//! A [`MuellerMatrix`] is a numeric `4 x 4` matrix; a [`MuellerTransform`] is
//! `[M]_{F_i -> F_o}` (PSH (22)): a matrix together with the input frame `F_i` (on the
//! incident ray `w_i`) and the output frame `F_o` (on `w_o`) in which it acts. Derivations
//! of the frame change (PSH (49)) and of the rotation (PSH (59)) in
//! `proofs/stokes-frames.md`.

use super::components::StokesComponents;
use super::vector::StokesVector;
use crate::error::relabel;
use crate::error::{finite, Result};
use crate::geometry::frame::Frame;
use nalgebra::{Matrix4, Rotation3};
use std::ops::Mul;

/// The rotator `C(vartheta)` of PSH (14): the Mueller matrix converting Stokes components
/// measured in a frame `F` into those measured in `F' = R_z(vartheta) F`, the frame turned
/// by `vartheta` (radians, right-handed) about the ray:
///
/// ```text
/// C(vartheta) = [ 1      0              0          0 ]
///               [ 0  cos 2 vartheta  sin 2 vartheta 0 ]
///               [ 0 -sin 2 vartheta  cos 2 vartheta 0 ]
///               [ 0      0              0          1 ]
/// ```
///
/// i.e. `s1' + i s2' = e^{-2 i vartheta} (s1 + i s2)` (derived from the definitions of
/// `s1`, `s2` in `proofs/stokes-frames.md`). `C(a) C(b) = C(a + b)`, `C(-a) = C(a)^T`.
/// Error: non-finite angle.
pub fn rotator(vartheta: f64) -> Result<MuellerMatrix> {
    finite("rotator angle", vartheta)?;
    let (s, c) = vartheta.sin_cos();
    Ok(rotator_cos_sin(c, s))
}

/// `C(vartheta)` from `(cos vartheta, sin vartheta)` by the double-angle formulas.
pub(crate) fn rotator_cos_sin(c: f64, s: f64) -> MuellerMatrix {
    let (c2, s2) = (c * c - s * s, 2.0 * c * s);
    MuellerMatrix {
        m: Matrix4::new(
            1.0, 0.0, 0.0, 0.0, //
            0.0, c2, s2, 0.0, //
            0.0, -s2, c2, 0.0, //
            0.0, 0.0, 0.0, 1.0,
        ),
    }
}

/// A numeric Mueller matrix `M` (PSH Table 1): meaningful only with its two frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MuellerMatrix {
    m: Matrix4<f64>,
}

impl MuellerMatrix {
    /// A Mueller matrix. Error: a non-finite entry.
    pub fn new(m: Matrix4<f64>) -> Result<Self> {
        for &v in m.iter() {
            finite("Mueller matrix entry", v)?;
        }
        Ok(Self { m })
    }

    /// A Mueller matrix from its rows. Error: a non-finite entry.
    pub fn from_rows(rows: [[f64; 4]; 4]) -> Result<Self> {
        Self::new(Matrix4::from_fn(|i, j| rows[i][j]))
    }

    /// The identity.
    pub fn identity() -> Self {
        Self {
            m: Matrix4::identity(),
        }
    }

    /// The matrix.
    pub fn matrix(&self) -> Matrix4<f64> {
        self.m
    }

    /// Entry `(row, column)`, both in `0..4`; `None` otherwise.
    pub fn get(&self, row: usize, col: usize) -> Option<f64> {
        (row < 4 && col < 4).then(|| self.m[(row, col)])
    }

    /// `M s`.
    pub fn apply(&self, s: &StokesComponents) -> StokesComponents {
        StokesComponents::from_vector_unchecked(self.m * s.vector())
    }

    /// The transpose.
    pub fn transpose(&self) -> Self {
        Self {
            m: self.m.transpose(),
        }
    }

    /// The inverse, if `M` is invertible.
    pub fn try_inverse(&self) -> Option<Self> {
        self.m.try_inverse().map(|m| Self { m })
    }

    /// The matrix after turning the input frame by `theta_in` and the output frame by
    /// `theta_out` about their rays (PSH (49)):
    /// `M' = C(theta_out) M C(theta_in)^{-1} = C(theta_out) M C(-theta_in)`.
    /// In PSH's printed (49), `R^{2x2}(e^{-2 i alpha}) M R^{2x2}(e^{2 i beta})`, `alpha` is
    /// the output frame's angle and `beta` the input's (derivation and the naming of the
    /// angles in `proofs/stokes-frames.md`). Error: non-finite angle.
    pub fn reframed(&self, theta_in: f64, theta_out: f64) -> Result<Self> {
        Ok(rotator(theta_out)? * *self * rotator(-theta_in)?)
    }

    /// Whether every entry agrees within `tol`.
    pub fn approx_eq(&self, other: &MuellerMatrix, tol: f64) -> bool {
        (self.m - other.m).amax() <= tol
    }
}

impl Mul for MuellerMatrix {
    type Output = MuellerMatrix;
    /// The numeric product: meaningful when the first factor's input frame is the second
    /// one's output frame (see [`MuellerTransform::compose`] for the checked product).
    fn mul(self, rhs: MuellerMatrix) -> MuellerMatrix {
        MuellerMatrix { m: self.m * rhs.m }
    }
}

impl Mul<StokesComponents> for MuellerMatrix {
    type Output = StokesComponents;
    fn mul(self, s: StokesComponents) -> StokesComponents {
        self.apply(&s)
    }
}

/// A Mueller transform `[M]_{F_i -> F_o}` (PSH (21), (22)): a linear map from the Stokes
/// vectors of the ray `w_i = F_i[:, 3]` to those of `w_o = F_o[:, 3]`, stored as the
/// matrix `M` acting on components in `F_i` and returning components in `F_o`. Compare
/// transforms with [`MuellerTransform::approx_eq`] (no `PartialEq`: the same transform
/// has different matrices in different frames).
///
/// # Example
///
/// An ideal linear polarizer along `x` of `F`: applied twice it is applied once; in the
/// frame `F' = R_z(pi/2) F` (`x' = y`, `y' = -x`) its matrix is a polarizer along `y'`
/// (PSH (49)).
///
/// ```
/// use psh::geometry::Frame;
/// use psh::stokes::{MuellerMatrix, MuellerTransform, StokesComponents, StokesVector};
/// use std::f64::consts::FRAC_PI_2;
///
/// let f = Frame::from_z([0.0, 0.6, 0.8])?;
/// let (a, z) = ([0.5, 0.5, 0.0, 0.0], [0.0; 4]);
/// let pol = MuellerTransform::new(MuellerMatrix::from_rows([a, a, z, z])?, f, f);
/// assert!(pol.compose(&pol)?.approx_eq(&pol, 1e-15)?);
///
/// let f2 = f.rotated_about_z(FRAC_PI_2)?;
/// let (b, c) = ([0.5, -0.5, 0.0, 0.0], [-0.5, 0.5, 0.0, 0.0]);
/// let along_y = MuellerMatrix::from_rows([b, c, z, z])?;
/// assert!(pol.matrix_in(&f2, &f2)?.approx_eq(&along_y, 1e-15));
///
/// // Unpolarized light, stored in `F'`, leaves at half intensity, polarized along `x`.
/// let out = pol.apply(&StokesVector::new(StokesComponents::unpolarized(1.0)?, f2))?;
/// let s = out.components_in(&f)?;
/// assert!(s.approx_eq(&StokesComponents::new([0.5, 0.5, 0.0, 0.0])?, 1e-15));
/// # Ok::<(), psh::Error>(())
/// ```
#[derive(Clone, Copy, Debug)]
pub struct MuellerTransform {
    m: MuellerMatrix,
    frame_in: Frame,
    frame_out: Frame,
}

impl MuellerTransform {
    /// `[M]_{F_i -> F_o}` (PSH (22)).
    pub fn new(m: MuellerMatrix, frame_in: Frame, frame_out: Frame) -> Self {
        Self {
            m,
            frame_in,
            frame_out,
        }
    }

    /// The identity of the Stokes space of `frame`'s ray, `[I]_{F -> F}`.
    pub fn identity(frame: Frame) -> Self {
        Self::new(MuellerMatrix::identity(), frame, frame)
    }

    /// The rotation `R_S` of PSH (19) as a Mueller transform from the ray of `frame_in`
    /// to the rotated ray: `[I]_{F -> R F}`. Its action on a Stokes vector equals
    /// [`StokesVector::rotate`]. Error: `r` not a rotation.
    pub fn rotation(r: &Rotation3<f64>, frame_in: Frame) -> Result<Self> {
        Ok(Self::new(
            MuellerMatrix::identity(),
            frame_in,
            frame_in.rotated(r)?,
        ))
    }

    /// The input frame `F_i`.
    pub fn frame_in(&self) -> &Frame {
        &self.frame_in
    }

    /// The output frame `F_o`.
    pub fn frame_out(&self) -> &Frame {
        &self.frame_out
    }

    /// The incident ray direction `w_i`.
    pub fn direction_in(&self) -> [f64; 3] {
        self.frame_in.direction()
    }

    /// The outgoing ray direction `w_o`.
    pub fn direction_out(&self) -> [f64; 3] {
        self.frame_out.direction()
    }

    /// The matrix in the transform's own frames, `[M]^{F_i -> F_o}` with the `F_i`, `F_o`
    /// of [`MuellerTransform::frame_in`] and [`MuellerTransform::frame_out`].
    pub fn matrix(&self) -> MuellerMatrix {
        self.m
    }

    /// `[M]^{F_i' -> F_o'}` (PSH (22)) in other frames of the same two rays, by PSH (49):
    /// `C(theta_o) M C(-theta_i)` with `F_i' = R_z(theta_i) F_i`,
    /// `F_o' = R_z(theta_o) F_o`. Error: `frame_in` not on the ray `w_i`, or `frame_out`
    /// not on `w_o` ([`crate::Error::DifferentRays`]).
    pub fn matrix_in(&self, frame_in: &Frame, frame_out: &Frame) -> Result<MuellerMatrix> {
        let (ci, si) = cos_sin(&self.frame_in, frame_in, "Mueller transform input frame")?;
        let (co, so) = cos_sin(&self.frame_out, frame_out, "Mueller transform output frame")?;
        Ok(rotator_cos_sin(co, so) * self.m * rotator_cos_sin(ci, -si))
    }

    /// The same transform stored in other frames of its rays (PSH (49)).
    pub fn in_frames(&self, frame_in: &Frame, frame_out: &Frame) -> Result<Self> {
        Ok(Self::new(
            self.matrix_in(frame_in, frame_out)?,
            *frame_in,
            *frame_out,
        ))
    }

    /// `M s` (PSH (21)): `s` is read in `F_i` (converted by PSH (14) if stored in another
    /// frame of `w_i`), the result is `[M [s]^{F_i}]_{F_o}`. Error: `s` is not a Stokes
    /// vector of the ray `w_i`.
    pub fn apply(&self, s: &StokesVector) -> Result<StokesVector> {
        let c = s.components_in(&self.frame_in)?;
        Ok(StokesVector::new(self.m.apply(&c), self.frame_out))
    }

    /// The composition `self . first` (first `first`, then `self`): defined when the
    /// output ray of `first` is the input ray of `self` ([`crate::geometry::frame::RAY_TOLERANCE`]).
    /// The frames may differ by a rotation `vartheta` about that ray (from `first`'s output
    /// frame to `self`'s input frame); the rotator is inserted:
    /// `[M_self C(vartheta) M_first]_{F_i(first) -> F_o(self)}`. Error: the rays differ.
    pub fn compose(&self, first: &MuellerTransform) -> Result<MuellerTransform> {
        let (c, s) = first
            .frame_out
            .cos_sin_to(&self.frame_in)
            .map_err(|e| relabel(e, "composition of Mueller transforms"))?;
        Ok(Self::new(
            self.m * rotator_cos_sin(c, s) * first.m,
            first.frame_in,
            self.frame_out,
        ))
    }

    /// The composition `next . self` (first `self`, then `next`); see
    /// [`MuellerTransform::compose`].
    pub fn then(&self, next: &MuellerTransform) -> Result<MuellerTransform> {
        next.compose(self)
    }

    /// The rotation `R_M[M] = R_S M R_S^{-1}` of PSH (59): a transform from the ray
    /// `R w_i` to `R w_o` with the same matrix in the rotated frames,
    /// `[M]_{R F_i -> R F_o}` (derivation in `proofs/stokes-frames.md`). Error: `r` not a
    /// rotation.
    pub fn rotate(&self, r: &Rotation3<f64>) -> Result<MuellerTransform> {
        Ok(Self::new(
            self.m,
            self.frame_in.rotated(r)?,
            self.frame_out.rotated(r)?,
        ))
    }

    /// Whether `other` is the same transform within `tol` (entrywise, both read in
    /// `self`'s frames). Error: the rays differ.
    pub fn approx_eq(&self, other: &MuellerTransform, tol: f64) -> Result<bool> {
        let m = other.matrix_in(&self.frame_in, &self.frame_out)?;
        Ok(self.m.approx_eq(&m, tol))
    }
}

fn cos_sin(from: &Frame, to: &Frame, what: &'static str) -> Result<(f64, f64)> {
    from.cos_sin_to(to).map_err(|e| relabel(e, what))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Error;
    use nalgebra::Vector3;
    use std::f64::consts::PI;

    fn m(rows: [[f64; 4]; 4]) -> MuellerMatrix {
        MuellerMatrix::from_rows(rows).unwrap()
    }

    /// A horizontal linear polarizer (transmits along x), hand-written.
    fn polarizer_x() -> MuellerMatrix {
        m([
            [0.5, 0.5, 0., 0.],
            [0.5, 0.5, 0., 0.],
            [0., 0., 0., 0.],
            [0., 0., 0., 0.],
        ])
    }

    #[test]
    fn rotator_entries_and_group_law() {
        let c = rotator(PI / 8.0).unwrap();
        let h = 0.5f64.sqrt();
        // cos(pi/4) = sin(pi/4) = 1/sqrt 2, written out from PSH (14).
        assert!(c.approx_eq(
            &m([
                [1., 0., 0., 0.],
                [0., h, h, 0.],
                [0., -h, h, 0.],
                [0., 0., 0., 1.]
            ]),
            1e-15
        ));
        let (a, b) = (0.37, -1.9);
        assert!(
            (rotator(a).unwrap() * rotator(b).unwrap()).approx_eq(&rotator(a + b).unwrap(), 1e-15)
        );
        assert!(rotator(-a)
            .unwrap()
            .approx_eq(&rotator(a).unwrap().transpose(), 0.0));
        // Period pi.
        assert!(rotator(a + PI)
            .unwrap()
            .approx_eq(&rotator(a).unwrap(), 1e-15));
        assert!(rotator(f64::NAN).is_err());
    }

    #[test]
    fn matrix_validation() {
        let mut rows = [[0.0; 4]; 4];
        rows[2][3] = f64::NAN;
        assert!(MuellerMatrix::from_rows(rows).is_err());
        assert_eq!(polarizer_x().get(0, 1), Some(0.5));
        assert_eq!(polarizer_x().get(4, 0), None);
        assert!(polarizer_x().try_inverse().is_none());
    }

    /// A polarizer transmitting along x, re-expressed in frames turned by 45 degrees on
    /// both sides, transmits along the new frame's `(x' - y')/sqrt 2` (the old x): its
    /// matrix is the -45-degree polarizer, written out by hand.
    #[test]
    fn reframed_polarizer_by_hand() {
        let f = Frame::world();
        let g = f.rotated_about_z(PI / 4.0).unwrap();
        let t = MuellerTransform::new(polarizer_x(), f, f);
        let want = m([
            [0.5, 0., -0.5, 0.],
            [0., 0., 0., 0.],
            [-0.5, 0., 0.5, 0.],
            [0., 0., 0., 0.],
        ]);
        assert!(t.matrix_in(&g, &g).unwrap().approx_eq(&want, 1e-15));
        assert!(polarizer_x()
            .reframed(PI / 4.0, PI / 4.0)
            .unwrap()
            .approx_eq(&want, 1e-15));
    }

    #[test]
    fn different_rays_are_errors() {
        let a = Frame::world();
        let b = Frame::from_z([1., 0., 0.]).unwrap();
        let t = MuellerTransform::new(polarizer_x(), a, b);
        assert!(matches!(
            t.matrix_in(&b, &b),
            Err(Error::DifferentRays { .. })
        ));
        // compose: t's output ray (x) is not t's input ray (z).
        assert!(matches!(t.compose(&t), Err(Error::DifferentRays { .. })));
        let s = StokesVector::new(StokesComponents::unpolarized(1.0).unwrap(), b);
        assert!(matches!(t.apply(&s), Err(Error::DifferentRays { .. })));
        let ok = StokesVector::new(StokesComponents::unpolarized(1.0).unwrap(), a);
        let out = t.apply(&ok).unwrap();
        assert_eq!(out.frame(), &b);
        assert_eq!(out.components().to_array(), [0.5, 0.5, 0., 0.]);
    }

    /// Composition across frames differing by 90 degrees about the ray: two x-polarizers
    /// whose frames are crossed are crossed polarizers, so the product vanishes.
    #[test]
    fn composition_inserts_the_rotator() {
        let f = Frame::world();
        let g = f.rotated_about_z(PI / 2.0).unwrap();
        let p1 = MuellerTransform::new(polarizer_x(), f, f);
        let p2 = MuellerTransform::new(polarizer_x(), g, g);
        let both = p2.compose(&p1).unwrap();
        assert!(both.matrix().approx_eq(&m([[0.0; 4]; 4]), 1e-15));
        assert!(p1.then(&p2).unwrap().approx_eq(&both, 0.0).unwrap());
        // Same frames: plain product, and P^2 = P.
        let pp = p1.compose(&p1).unwrap();
        assert!(pp.matrix().approx_eq(&polarizer_x(), 1e-15));
    }

    #[test]
    fn rotation_keeps_the_matrix_and_moves_the_frames() {
        let r = Rotation3::from_axis_angle(&Vector3::y_axis(), 0.4);
        let f = Frame::world();
        let t = MuellerTransform::new(polarizer_x(), f, f)
            .rotate(&r)
            .unwrap();
        assert_eq!(t.matrix(), polarizer_x());
        let rz = r * Vector3::z();
        assert!((Vector3::from(t.direction_in()) - rz).norm() < 1e-15);
        assert!((Vector3::from(t.direction_out()) - rz).norm() < 1e-15);
    }
}
