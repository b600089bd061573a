//! Orthonormal right-handed frames and frame fields (PSH Sec. 4.2, 5.1, Table 1-2).
//!
//! A [`Frame`] `F = [x, y, z]` is a geometric object of PSH Table 1 (`F in F^3`): three
//! orthonormal world vectors with `x cross y = z`. For a Stokes frame `z` is the ray
//! direction `w` (PSH Sec. 4.2.1: `S_w = { [s]_F | F[:, 3] = w }`); `x` and `y` are the
//! directions along which the linear polarization `s1` (and, at 45 degrees between them,
//! `s2`) is measured.
//!
//! A *frame field* (PSH Sec. 5.1) assigns such a frame to every direction: [`FrameField`],
//! with the theta-phi field [`ThetaPhiFrameField`] of PSH Sec. 5.1, the perspective camera
//! field [`PerspectiveFrameField`] (the convention of Mitsuba 3's polarized sensors) and
//! the cube-map field [`CubeMapFrameField`] of the shared environment maps. Every frame
//! field has a singularity somewhere (hairy ball theorem, PSH Sec. 5.1); each type says
//! what it returns there.
//!
//! Derivations and the checks that verify them: `proofs/stokes-frames.md`.
//!
//! Tolerances:
//! - [`FRAME_TOLERANCE`] (`1e-10`): the axes handed to [`Frame::new`] must have norms
//!   within it of 1 and pairwise dot products within it of 0. Accepted frames are
//!   re-orthonormalized (keeping the direction of `z`, then the plane of `z, x`), so every
//!   stored frame is orthonormal to rounding.
//! - [`RAY_TOLERANCE`] (`1e-9`): two frames belong to the same ray when their `z` axes
//!   differ by at most this much in Euclidean distance (about the angle in radians).

use crate::error::{finite, Error, Result};
use crate::geometry::check_direction;
use crate::geometry::image_grid::{CubeCross, CubeFace};
use nalgebra::{Matrix3, Rotation3, Vector3};

/// Largest deviation from orthonormality accepted by [`Frame::new`] (norms within
/// `1 +- 1e-10`, pairwise dot products within `+- 1e-10`).
pub const FRAME_TOLERANCE: f64 = 1e-10;

/// Largest Euclidean distance between the `z` axes of two frames that still counts as the
/// same ray (PSH (17), (18): operations are defined only within one Stokes space `S_w`).
pub const RAY_TOLERANCE: f64 = 1e-9;

/// Below this norm of `y_camera x w` the perspective frame is taken from the camera's `x`
/// axis instead (see [`PerspectiveFrameField`]).
const PERSPECTIVE_SINGULAR: f64 = 1e-12;

/// An orthonormal right-handed frame `[x, y, z]` in world coordinates (PSH Table 1).
///
/// The axes are private: a frame can only be built through the validating constructors,
/// so every `Frame` is orthonormal and right-handed to rounding.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Columns `x, y, z`.
    m: Matrix3<f64>,
}

fn arr(v: &Vector3<f64>) -> [f64; 3] {
    [v[0], v[1], v[2]]
}

fn check_finite_vec(name: &'static str, v: &Vector3<f64>) -> Result<()> {
    for &c in v.iter() {
        finite(name, c)?;
    }
    Ok(())
}

impl Frame {
    /// The world frame `[e_x, e_y, e_z]`.
    pub fn world() -> Self {
        Self {
            m: Matrix3::identity(),
        }
    }

    /// A frame from its three axes (world coordinates).
    ///
    /// Errors: a non-finite component ([`Error::NonFinite`]); an axis whose norm differs
    /// from 1 by more than [`FRAME_TOLERANCE`], two axes whose dot product exceeds it, or a
    /// left-handed triple (`(x cross y) . z < 0`) ([`Error::InvalidArgument`] naming the
    /// axes). The accepted axes are re-orthonormalized: `z` normalized, `x` made
    /// orthogonal to `z` and normalized, `y = z cross x`; this moves them by at most a few
    /// times the tolerance.
    pub fn new(x: [f64; 3], y: [f64; 3], z: [f64; 3]) -> Result<Self> {
        Self::from_axes(Vector3::from(x), Vector3::from(y), Vector3::from(z))
    }

    /// A frame from a matrix whose columns are `x, y, z` (validated as in [`Frame::new`]).
    pub fn from_matrix(m: &Matrix3<f64>) -> Result<Self> {
        Self::from_axes(
            m.column(0).into_owned(),
            m.column(1).into_owned(),
            m.column(2).into_owned(),
        )
    }

    /// The frame `R [e_x, e_y, e_z]` of a rotation (columns of its matrix), validated as
    /// in [`Frame::new`] (a `Rotation3` built with `from_matrix_unchecked` may be anything).
    pub fn from_rotation(r: &Rotation3<f64>) -> Result<Self> {
        Self::from_matrix(r.matrix())
    }

    fn from_axes(x: Vector3<f64>, y: Vector3<f64>, z: Vector3<f64>) -> Result<Self> {
        check_finite_vec("frame axis x component", &x)?;
        check_finite_vec("frame axis y component", &y)?;
        check_finite_vec("frame axis z component", &z)?;
        let show = || format!("x = {:?}, y = {:?}, z = {:?}", arr(&x), arr(&y), arr(&z));
        for (name, v) in [("x", &x), ("y", &y), ("z", &z)] {
            let n = v.norm();
            if (n - 1.0).abs() > FRAME_TOLERANCE {
                return Err(Error::invalid(
                    "frame",
                    show(),
                    format!("axis {name} has norm {n}, not 1 within {FRAME_TOLERANCE:e}"),
                ));
            }
        }
        for (name, d) in [("x.y", x.dot(&y)), ("y.z", y.dot(&z)), ("z.x", z.dot(&x))] {
            if d.abs() > FRAME_TOLERANCE {
                return Err(Error::invalid(
                    "frame",
                    show(),
                    format!("axes not orthogonal: {name} = {d:e} exceeds {FRAME_TOLERANCE:e}"),
                ));
            }
        }
        let det = x.cross(&y).dot(&z);
        if det < 0.0 {
            return Err(Error::invalid(
                "frame",
                show(),
                format!("left-handed: (x cross y) . z = {det}"),
            ));
        }
        Ok(Self::orthonormalized(&z, &x))
    }

    /// Gram-Schmidt from `z` then `x`; callers guarantee `z` nonzero and `x` not parallel.
    fn orthonormalized(z: &Vector3<f64>, x: &Vector3<f64>) -> Self {
        let z = z.normalize();
        let x = (x - z * z.dot(x)).normalize();
        let y = z.cross(&x);
        Self {
            m: Matrix3::from_columns(&[x, y, z]),
        }
    }

    /// The frame with `z` the unit direction `z` and `x` the normalized component of
    /// `x_hint` orthogonal to `z`; `y = z cross x`.
    ///
    /// Errors: `z` non-finite or not unit within [`super::UNIT_TOLERANCE`];
    /// `x_hint` non-finite, or parallel to `z` (its orthogonal part shorter than
    /// `1e-12 |x_hint|`, or zero).
    pub fn from_z_and_x(z: [f64; 3], x_hint: [f64; 3]) -> Result<Self> {
        let z = Vector3::from(check_direction(z)?);
        let h = Vector3::from(x_hint);
        check_finite_vec("x hint component", &h)?;
        Self::from_z_hint(&z, &h, "x hint").map(|(f, _)| f)
    }

    /// The frame with `z` the unit direction `z` and `y` the normalized component of
    /// `y_hint` orthogonal to `z`; `x = y cross z`. Errors as [`Frame::from_z_and_x`].
    pub fn from_z_and_y(z: [f64; 3], y_hint: [f64; 3]) -> Result<Self> {
        let zv = Vector3::from(check_direction(z)?);
        let h = Vector3::from(y_hint);
        check_finite_vec("y hint component", &h)?;
        let (f, _) = Self::from_z_hint(&zv, &h, "y hint")?;
        // f has x along the hint; turn it by -90 degrees about z so that y is along it:
        // x' = cos(-90) x + sin(-90) y = -y, y' = sin(90) x + cos(-90) y = x.
        let (x, y, zz) = (f.x(), f.y(), f.z());
        Ok(Self {
            m: Matrix3::from_columns(&[-y, x, zz]),
        })
    }

    fn from_z_hint(z: &Vector3<f64>, h: &Vector3<f64>, name: &'static str) -> Result<(Self, f64)> {
        let zn = z.normalize();
        let p = h - zn * zn.dot(h);
        let (pn, hn) = (p.norm(), h.norm());
        if hn == 0.0 || pn <= 1e-12 * hn {
            return Err(Error::invalid(
                name,
                format!("{:?}", arr(h)),
                format!("parallel to (or zero against) z = {:?}", arr(z)),
            ));
        }
        Ok((Self::orthonormalized(&zn, &p), pn))
    }

    /// A deterministic frame with `z` the unit direction `z`: the orthonormal basis of
    /// Duff et al. 2017 ("Building an orthonormal basis, revisited", JCGT 6(1)), with
    /// `sigma = sign(z_z)` (`+1` at `z_z = 0`), `a = -1/(sigma + z_z)`, `b = z_x z_y a`,
    /// `x = (1 + sigma z_x^2 a, sigma b, -sigma z_x)`, `y = (b, sigma + z_y^2 a, -z_y)`.
    /// Mitsuba 3 builds its implicit Stokes basis of a ray travelling along `z` from this
    /// `x` (`mueller::stokes_basis`). Errors as for a bad direction.
    pub fn from_z(z: [f64; 3]) -> Result<Self> {
        let z = Vector3::from(check_direction(z)?).normalize();
        let sigma = if z[2] >= 0.0 { 1.0 } else { -1.0 };
        let a = -1.0 / (sigma + z[2]);
        let b = z[0] * z[1] * a;
        let x = Vector3::new(1.0 + sigma * z[0] * z[0] * a, sigma * b, -sigma * z[0]);
        Ok(Self::orthonormalized(&z, &x))
    }

    /// The `x` axis (world coordinates).
    pub fn x(&self) -> Vector3<f64> {
        self.m.column(0).into_owned()
    }

    /// The `y` axis.
    pub fn y(&self) -> Vector3<f64> {
        self.m.column(1).into_owned()
    }

    /// The `z` axis: for a Stokes frame, the ray direction `w`.
    pub fn z(&self) -> Vector3<f64> {
        self.m.column(2).into_owned()
    }

    /// The ray direction `z` as an array.
    pub fn direction(&self) -> [f64; 3] {
        arr(&self.z())
    }

    /// The matrix with columns `x, y, z`: it maps frame-local coordinates to world ones.
    pub fn matrix(&self) -> Matrix3<f64> {
        self.m
    }

    /// The rotation taking the world frame to this one (`F = R [e_x, e_y, e_z]`).
    pub fn rotation(&self) -> Rotation3<f64> {
        Rotation3::from_matrix_unchecked(self.m)
    }

    /// World coordinates of the local vector `v` (`F v`).
    pub fn to_world(&self, v: &Vector3<f64>) -> Vector3<f64> {
        self.m * v
    }

    /// Local coordinates of the world vector `v` (`F^T v`).
    pub fn to_local(&self, v: &Vector3<f64>) -> Vector3<f64> {
        self.m.transpose() * v
    }

    /// The frame `R_z(vartheta) F`: this frame turned by `vartheta` (radians,
    /// counterclockwise seen from `+z`, i.e. right-handed about `z`) about its own `z` axis
    /// (PSH (14)): `x' = cos(vartheta) x + sin(vartheta) y`,
    /// `y' = -sin(vartheta) x + cos(vartheta) y`, `z' = z`. Error: non-finite angle.
    pub fn rotated_about_z(&self, vartheta: f64) -> Result<Self> {
        finite("frame rotation angle", vartheta)?;
        let (s, c) = vartheta.sin_cos();
        let (x, y, z) = (self.x(), self.y(), self.z());
        Ok(Self {
            m: Matrix3::from_columns(&[x * c + y * s, y * c - x * s, z]),
        })
    }

    /// The frame `R F` (PSH Table 2): every axis rotated by `r`. Errors if `r` is not a
    /// rotation (non-finite, or built unchecked from a non-orthogonal matrix).
    pub fn rotated(&self, r: &Rotation3<f64>) -> Result<Self> {
        Self::from_matrix(&(r.matrix() * self.m))
    }

    /// Checks that `other` belongs to the same ray: `|z - z_other| <= RAY_TOLERANCE`,
    /// else [`Error::DifferentRays`] with `what` as its context.
    pub fn check_same_ray(&self, other: &Frame, what: &'static str) -> Result<()> {
        let d = (self.z() - other.z()).norm();
        if d <= RAY_TOLERANCE {
            Ok(())
        } else {
            Err(Error::DifferentRays {
                what,
                first: self.direction(),
                second: other.direction(),
                distance: d,
                tolerance: RAY_TOLERANCE,
            })
        }
    }

    /// Whether `other` belongs to the same ray (see [`Frame::check_same_ray`]).
    pub fn same_ray(&self, other: &Frame) -> bool {
        (self.z() - other.z()).norm() <= RAY_TOLERANCE
    }

    /// `(cos vartheta, sin vartheta)` of the angle of [`Frame::angle_to`], from dot
    /// products (no trigonometric round trip).
    pub fn cos_sin_to(&self, other: &Frame) -> Result<(f64, f64)> {
        self.check_same_ray(other, "angle between frames")?;
        let xo = other.x();
        let (c, s) = (xo.dot(&self.x()), xo.dot(&self.y()));
        let n = c.hypot(s);
        Ok((c / n, s / n))
    }

    /// The signed angle `vartheta` in `(-pi, pi]` with `other = R_z(vartheta) self`
    /// (PSH (14)): `atan2(x_other . y, x_other . x)`. Error: the frames belong to
    /// different rays ([`RAY_TOLERANCE`]).
    pub fn angle_to(&self, other: &Frame) -> Result<f64> {
        let (c, s) = self.cos_sin_to(other)?;
        Ok(s.atan2(c))
    }

    /// Whether all axes agree within `tol` (Euclidean distance per axis).
    pub fn approx_eq(&self, other: &Frame, tol: f64) -> bool {
        (0..3).all(|k| (self.m.column(k) - other.m.column(k)).norm() <= tol)
    }
}

/// A frame for every direction (PSH Sec. 5.1): `frame(w)` has `z = w` (normalized).
pub trait FrameField {
    /// The frame at the unit direction `w`. Errors: `w` non-finite or not unit within
    /// [`super::UNIT_TOLERANCE`].
    fn frame(&self, w: [f64; 3]) -> Result<Frame>;
}

/// The angle `vartheta` with `to.frame(w) = R_z(vartheta) from.frame(w)`: Stokes
/// components measured in `from` convert to `to` by the rotator `C(vartheta)` (PSH (14)).
pub fn field_angle<A, B>(w: [f64; 3], from: &A, to: &B) -> Result<f64>
where
    A: FrameField + ?Sized,
    B: FrameField + ?Sized,
{
    from.frame(w)?.angle_to(&to.frame(w)?)
}

/// The theta-phi frame field `F_theta_phi` of PSH Sec. 5.1 about a global frame `F_g`
/// (the world frame by default): with `theta` the polar angle from `z_g` and `phi` the
/// azimuth from `x_g` towards `y_g` (`docs/conventions.md` Sec. 1),
///
/// - `x = e_theta = (cos theta cos phi, cos theta sin phi, -sin theta)` (increasing theta),
/// - `y = e_phi = (-sin phi, cos phi, 0)` (increasing phi),
/// - `z = w = (sin theta cos phi, sin theta sin phi, cos theta)`,
///
/// in `F_g` coordinates; right-handed since `e_theta x e_phi = w`.
///
/// Poles (`theta = 0, pi`), where the field is singular: [`FrameField::frame`] returns the
/// limit along the meridian `phi = 0`, i.e. `[x_g, y_g, z_g]` at the north pole and
/// `[-x_g, y_g, -z_g]` at the south pole. This is also what the angle form
/// [`ThetaPhiFrameField::frame_at_angles`] gives at `(0, 0)` and `(pi, 0)`, and the
/// `phi = atan2(0, 0) = 0` of [`super::direction_angles`]. The angle form is
/// defined at the poles for every `phi` (PSH (61) uses `F_theta_phi(0, phi)`).
/// Near a pole, `cos phi, sin phi` are taken from `(w_x, w_y)/hypot(w_x, w_y)`, exact to
/// rounding however small `sin theta` is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThetaPhiFrameField {
    global: Frame,
}

impl Default for ThetaPhiFrameField {
    fn default() -> Self {
        Self::new()
    }
}

impl ThetaPhiFrameField {
    /// The field about the world frame.
    pub fn new() -> Self {
        Self {
            global: Frame::world(),
        }
    }

    /// The field about the global frame `global` (its `z` is the pole, its `x` is
    /// `phi = 0`).
    pub fn with_global(global: Frame) -> Self {
        Self { global }
    }

    /// The global frame `F_g`.
    pub fn global(&self) -> &Frame {
        &self.global
    }

    /// `F_theta_phi(theta, phi)`, defined for every `theta` in `[0, pi]` (at the poles
    /// too) and finite `phi`. Errors: `theta` outside `[0, pi]` or non-finite; `phi`
    /// non-finite.
    pub fn frame_at_angles(&self, theta: f64, phi: f64) -> Result<Frame> {
        crate::geometry::check_theta(theta)?;
        finite("phi", phi)?;
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        Ok(self.local_frame(st, ct, sp, cp))
    }

    fn local_frame(&self, st: f64, ct: f64, sp: f64, cp: f64) -> Frame {
        let x = Vector3::new(ct * cp, ct * sp, -st);
        let z = Vector3::new(st * cp, st * sp, ct);
        // y = z x x = e_phi = (-sin phi, cos phi, 0) follows from Gram-Schmidt.
        let g = &self.global.m;
        Frame::orthonormalized(&(g * z), &(g * x))
    }
}

impl FrameField for ThetaPhiFrameField {
    fn frame(&self, w: [f64; 3]) -> Result<Frame> {
        let wv = Vector3::from(check_direction(w)?).normalize();
        let l = self.global.to_local(&wv);
        let rho = l[0].hypot(l[1]);
        let (sp, cp) = if rho > 0.0 {
            (l[1] / rho, l[0] / rho)
        } else {
            (0.0, 1.0)
        };
        // sin theta = rho >= 0, cos theta = l_z (|l| = 1 to rounding).
        let f = self.local_frame(rho, l[2], sp, cp);
        // Keep z exactly the normalized input direction.
        Ok(Frame::orthonormalized(&wv, &f.x()))
    }
}

/// The frame field of a perspective camera, as Mitsuba 3's polarized sensors define it.
///
/// The camera frame `C = [x_c, y_c, z_c]` has `x_c` to the image's right, `z_c` forward
/// (into the scene) and `y_c = z_c x x_c` towards the image's *bottom* (the camera's up
/// vector is `u = -y_c`). For a pixel direction `w` (pointing into the scene):
///
/// - `x = normalize(w x u) = normalize(y_c x w)`: orthogonal to the camera's up vector
///   and to the ray (level, when the camera's up is the world's up), pointing to the
///   image's right, and equal to `x_c` at the image centre and along the image's vertical
///   centre line;
/// - `z = w`, `y = z x x` (towards the image's bottom).
///
/// Reason for the choice: Mitsuba 3's Stokes integrator turns the measured Stokes vector
/// into the basis `cross(ray.d, vertical)` with `vertical` the sensor's up vector
/// (`src/integrators/stokes.cpp`), i.e. this `x`. The alternatives (the camera frame
/// carried to `w` by the minimal rotation from `z_c`, or `x_c` projected on the plane
/// orthogonal to `w`) tilt `x` out of the plane orthogonal to `u` for pixels off both
/// image axes, and Mitsuba uses neither. Mitsuba's frame has the same `x` but `z` along
/// the light's direction of travel `-w` and `y = -w x x`, opposite to ours; so between
/// the two `s1` agrees and `s2` changes sign (see `proofs/stokes-frames.md`).
///
/// Singularity: at `w = +-u` (90 degrees off the optical axis, outside every perspective
/// image) `y_c x w` vanishes; where its norm is below `1e-12` the frame takes `x` from
/// `x_c` (orthogonalized against `w`) instead.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PerspectiveFrameField {
    camera: Frame,
}

impl PerspectiveFrameField {
    /// The field of a camera with frame `camera` (`x` image-right, `y` image-down, `z`
    /// forward).
    pub fn new(camera: Frame) -> Self {
        Self { camera }
    }

    /// The field of a camera looking along `forward` with image-up direction `up`
    /// (orthogonalized against `forward`): camera frame `x = forward x up`,
    /// `y = -up`, `z = forward`. Errors: `forward` not a unit direction; `up` non-finite
    /// or parallel to `forward`.
    pub fn look(forward: [f64; 3], up: [f64; 3]) -> Result<Self> {
        let u = Vector3::from(up);
        let camera = Frame::from_z_and_y(forward, arr(&-u))?;
        Ok(Self { camera })
    }

    /// The camera frame.
    pub fn camera(&self) -> &Frame {
        &self.camera
    }
}

impl FrameField for PerspectiveFrameField {
    fn frame(&self, w: [f64; 3]) -> Result<Frame> {
        let wv = Vector3::from(check_direction(w)?).normalize();
        let h = self.camera.y().cross(&wv);
        let hint = if h.norm() > PERSPECTIVE_SINGULAR {
            h
        } else {
            self.camera.x()
        };
        // The hint is orthogonal to w up to rounding; orthonormalize against w.
        Ok(Frame::orthonormalized(&wv, &hint))
    }
}

/// The frame field of the shared cube-map environment maps (`docs/conventions.md`, `image_grid`):
/// each face is a 90-degree perspective camera with camera frame `[r, -u, f]` (image-right
/// `r`, image-down `-u`, forward `f` from [`CubeFace::basis`]), and the frame at a
/// direction of that face is the [`PerspectiveFrameField`] frame of that camera:
/// `x = normalize(w x u)`, `z = w`, `y = z x x`. At the centre of a face the frame is
/// `[r, -u, f]`; on a face `w` is never parallel to `u` (`|w . u| <= |w . f|`).
///
/// The face of a direction is that of its largest absolute coordinate; ties (cube edges
/// and corners) go to Up/Down first, then Right/Left, then Front/Back. The field is
/// discontinuous across cube edges, like the stored images.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CubeMapFrameField;

impl CubeMapFrameField {
    /// The face containing the unit direction `w` (ties as documented on the type).
    pub fn face_of(w: [f64; 3]) -> Result<CubeFace> {
        let w = check_direction(w)?;
        let (ax, ay, az) = (w[0].abs(), w[1].abs(), w[2].abs());
        Ok(if az >= ax && az >= ay {
            if w[2] >= 0.0 {
                CubeFace::Up
            } else {
                CubeFace::Down
            }
        } else if ax >= ay {
            if w[0] >= 0.0 {
                CubeFace::Right
            } else {
                CubeFace::Left
            }
        } else if w[1] >= 0.0 {
            CubeFace::Front
        } else {
            CubeFace::Back
        })
    }

    /// The camera frame `[r, -u, f]` of a face.
    pub fn camera_frame(face: CubeFace) -> Frame {
        let (f, r, u) = face.basis();
        let (f, r, u) = (Vector3::from(f), Vector3::from(r), Vector3::from(u));
        Frame {
            m: Matrix3::from_columns(&[r, -u, f]),
        }
    }

    /// The frame at `w` measured by the camera of `face` (whether or not `w` lies on that
    /// face; off the face this is that camera's perspective field, with its singularity
    /// at `w = +-u`).
    pub fn face_frame(face: CubeFace, w: [f64; 3]) -> Result<Frame> {
        PerspectiveFrameField::new(Self::camera_frame(face)).frame(w)
    }

    /// The frame of texel `i` of a cube cross: its face's camera at its centre direction.
    /// Error: `i` off the cross (unused block or past the end).
    pub fn texel_frame(grid: &CubeCross, i: usize) -> Result<Frame> {
        use crate::geometry::image_grid::PixelGrid;
        match grid.texel(i) {
            Some((face, _)) if i < grid.len() => Self::face_frame(face, grid.direction(i)),
            _ => Err(Error::invalid(
                "cube cross texel",
                i.to_string(),
                "not on a face of the cross",
            )),
        }
    }
}

impl FrameField for CubeMapFrameField {
    fn frame(&self, w: [f64; 3]) -> Result<Frame> {
        Self::face_frame(Self::face_of(w)?, w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_1_SQRT_2, PI};

    fn close(a: &Vector3<f64>, b: [f64; 3], tol: f64) -> bool {
        (a - Vector3::from(b)).norm() <= tol
    }

    #[test]
    fn validation_rejects_bad_frames() {
        assert!(Frame::new([1., 0., 0.], [0., 1., 0.], [0., 0., 1.]).is_ok());
        // Left-handed.
        assert!(matches!(
            Frame::new([1., 0., 0.], [0., 1., 0.], [0., 0., -1.]),
            Err(Error::InvalidArgument { .. })
        ));
        // Non-unit.
        assert!(Frame::new([1.001, 0., 0.], [0., 1., 0.], [0., 0., 1.]).is_err());
        // Non-orthogonal.
        assert!(Frame::new([1., 0., 0.], [1e-6, 1., 0.], [0., 0., 1.]).is_err());
        // NaN.
        assert!(matches!(
            Frame::new([f64::NAN, 0., 0.], [0., 1., 0.], [0., 0., 1.]),
            Err(Error::NonFinite { .. })
        ));
        // Within tolerance: accepted and re-orthonormalized.
        let f = Frame::new([1. + 5e-11, 0., 0.], [0., 1., 0.], [0., 3e-11, 1.]).unwrap();
        let m = f.matrix();
        assert!((m.transpose() * m - Matrix3::identity()).norm() < 1e-15);
        assert!((m.determinant() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn from_z_and_hints() {
        let f = Frame::from_z_and_x([0., 0., 1.], [2., 0., 5.]).unwrap();
        assert!(f.approx_eq(&Frame::world(), 1e-15));
        let g = Frame::from_z_and_y([0., 0., 1.], [0., 3., -1.]).unwrap();
        assert!(g.approx_eq(&Frame::world(), 1e-15));
        assert!(Frame::from_z_and_x([0., 0., 1.], [0., 0., 2.]).is_err());
        assert!(Frame::from_z_and_x([0., 0., 1.], [0., 0., 0.]).is_err());
        assert!(Frame::from_z_and_x([0., 0., 2.], [1., 0., 0.]).is_err());
        assert!(Frame::from_z_and_x([0., 0., 1.], [f64::INFINITY, 0., 0.]).is_err());
    }

    #[test]
    fn duff_basis_is_right_handed_everywhere() {
        for w in [
            [0., 0., 1.],
            [0., 0., -1.],
            [1., 0., 0.],
            [0., -1., 0.],
            [0.6, 0., -0.8],
            [1e-9, -1e-9, -(1.0f64 - 2e-18).sqrt()],
        ] {
            let f = Frame::from_z(w).unwrap();
            let m = f.matrix();
            assert!(
                (m.transpose() * m - Matrix3::identity()).norm() < 1e-14,
                "{w:?}"
            );
            assert!((m.determinant() - 1.0).abs() < 1e-14);
            assert!(close(&f.z(), w, 1e-15));
        }
        // Duff et al.'s example values at z = +e_z: x = e_x, y = e_y.
        assert!(Frame::from_z([0., 0., 1.])
            .unwrap()
            .approx_eq(&Frame::world(), 0.0));
    }

    #[test]
    fn rotation_about_z_and_angle() {
        let f = Frame::world();
        let g = f.rotated_about_z(PI / 2.0).unwrap();
        assert!(close(&g.x(), [0., 1., 0.], 1e-15));
        assert!(close(&g.y(), [-1., 0., 0.], 1e-15));
        assert!((f.angle_to(&g).unwrap() - PI / 2.0).abs() < 1e-15);
        assert!((g.angle_to(&f).unwrap() + PI / 2.0).abs() < 1e-15);
        let h = f.rotated_about_z(-3.0).unwrap();
        assert!((f.angle_to(&h).unwrap() + 3.0).abs() < 1e-14);
        assert!(f.rotated_about_z(f64::NAN).is_err());
        // Different rays.
        let other = Frame::from_z([1., 0., 0.]).unwrap();
        assert!(matches!(
            f.angle_to(&other),
            Err(Error::DifferentRays { .. })
        ));
    }

    #[test]
    fn rotating_a_frame() {
        let r = Rotation3::from_axis_angle(&Vector3::x_axis(), PI / 2.0);
        let g = Frame::world().rotated(&r).unwrap();
        assert!(close(&g.x(), [1., 0., 0.], 1e-15));
        assert!(close(&g.y(), [0., 0., 1.], 1e-15));
        assert!(close(&g.z(), [0., -1., 0.], 1e-15));
        let bad =
            Rotation3::from_matrix_unchecked(Matrix3::new(2., 0., 0., 0., 1., 0., 0., 0., 1.));
        assert!(Frame::world().rotated(&bad).is_err());
    }

    /// `e_theta`, `e_phi` against central differences of `direction(theta, phi)`.
    #[test]
    fn theta_phi_frame_is_the_coordinate_frame() {
        let field = ThetaPhiFrameField::new();
        let h = 1e-6;
        for &(t, p) in &[(0.3, 0.2), (1.2, -2.5), (2.9, 3.0), (PI / 2.0, 1.0)] {
            let d = |t: f64, p: f64| Vector3::from(crate::geometry::direction(t, p));
            let dt = (d(t + h, p) - d(t - h, p)) / (2.0 * h);
            let dp = (d(t, p + h) - d(t, p - h)) / (2.0 * h) / t.sin();
            let f = field.frame(crate::geometry::direction(t, p)).unwrap();
            assert!((f.x() - dt).norm() < 1e-9, "{t} {p}");
            assert!((f.y() - dp).norm() < 1e-9, "{t} {p}");
            let g = field.frame_at_angles(t, p).unwrap();
            assert!(f.approx_eq(&g, 1e-14));
        }
    }

    #[test]
    fn theta_phi_poles() {
        let field = ThetaPhiFrameField::new();
        let n = field.frame([0., 0., 1.]).unwrap();
        assert!(n.approx_eq(&Frame::world(), 0.0));
        let n2 = field.frame([-0.0, -0.0, 1.]).unwrap();
        assert!(n2.approx_eq(&Frame::world(), 0.0));
        let s = field.frame([0., 0., -1.]).unwrap();
        assert!(close(&s.x(), [-1., 0., 0.], 0.0));
        assert!(close(&s.y(), [0., 1., 0.], 0.0));
        assert!(close(&s.z(), [0., 0., -1.], 0.0));
        // Angle form at the north pole: x = (cos phi, sin phi, 0).
        let a = field.frame_at_angles(0.0, 0.7).unwrap();
        assert!(close(&a.x(), [0.7f64.cos(), 0.7f64.sin(), 0.], 1e-15));
        // Very near the pole the azimuth is still resolved.
        let tiny = field.frame([1e-300, 1e-300, 1.0]).unwrap();
        assert!(close(&tiny.x(), [FRAC_1_SQRT_2, FRAC_1_SQRT_2, 0.], 1e-15));
        assert!(field.frame([0., 0., 1.1]).is_err());
        assert!(field.frame_at_angles(-0.1, 0.0).is_err());
        assert!(field.frame_at_angles(0.1, f64::NAN).is_err());
    }

    #[test]
    fn theta_phi_about_a_rotated_global_frame() {
        // Global frame with pole along world +x: the field at direction w equals the world
        // field at R^-1 w, rotated by R.
        let r = Rotation3::from_axis_angle(&Vector3::y_axis(), PI / 2.0);
        let g = Frame::from_rotation(&r).unwrap();
        let field = ThetaPhiFrameField::with_global(g);
        let w0 = Vector3::from(crate::geometry::direction(0.8, 2.0));
        let w = r * w0;
        let f = field.frame(arr(&w)).unwrap();
        let f0 = ThetaPhiFrameField::new()
            .frame(arr(&w0))
            .unwrap()
            .rotated(&r)
            .unwrap();
        assert!(f.approx_eq(&f0, 1e-14));
    }

    #[test]
    fn perspective_field_matches_mitsuba_rule() {
        // Camera looking along +y with up +z: x_c = +x, y_c = -z.
        let cam = PerspectiveFrameField::look([0., 1., 0.], [0., 0., 1.]).unwrap();
        assert!(close(&cam.camera().x(), [1., 0., 0.], 1e-15));
        assert!(close(&cam.camera().y(), [0., 0., -1.], 1e-15));
        // Centre pixel: the camera frame.
        let c = cam.frame([0., 1., 0.]).unwrap();
        assert!(c.approx_eq(cam.camera(), 1e-15));
        // Off-axis pixel up and right: x = normalize(d x up) by hand.
        let d = Vector3::new(0.3, 1.0, 0.4).normalize();
        let f = cam.frame(arr(&d)).unwrap();
        let want = Vector3::new(d[1], -d[0], 0.0).normalize(); // d x e_z
        assert!((f.x() - want).norm() < 1e-15);
        assert!(f.x()[2].abs() < 1e-16, "x is horizontal");
        assert!(f.y()[2] < 0.0, "y points to the image bottom");
        // Singular direction: falls back to x_c.
        let s = cam.frame([0., 0., 1.]).unwrap();
        assert!(close(&s.x(), [1., 0., 0.], 1e-15));
    }

    #[test]
    fn cube_faces_and_frames() {
        let field = CubeMapFrameField;
        for face in [
            CubeFace::Front,
            CubeFace::Right,
            CubeFace::Back,
            CubeFace::Left,
            CubeFace::Up,
            CubeFace::Down,
        ] {
            let (f, r, u) = face.basis();
            assert_eq!(CubeMapFrameField::face_of(f).unwrap(), face);
            let fr = field.frame(f).unwrap();
            assert!(close(&fr.x(), r, 1e-15), "{face:?}");
            assert!(close(&fr.y(), u.map(|c| -c), 1e-15), "{face:?}");
            assert!(close(&fr.z(), f, 1e-15), "{face:?}");
        }
        // Ties go to Up.
        let e = FRAC_1_SQRT_2;
        assert_eq!(
            CubeMapFrameField::face_of([e, 0., e]).unwrap(),
            CubeFace::Up
        );
        assert!(field.frame([0., 0., 0.]).is_err());
    }

    #[test]
    fn cube_texel_frames() {
        let g = CubeCross::new(4).unwrap();
        // First texel of the image is in an unused block.
        assert!(CubeMapFrameField::texel_frame(&g, 0).is_err());
        assert!(CubeMapFrameField::texel_frame(&g, g.len()).is_err());
        // A texel of the Front face (row block 1, column block 1), upper-left quadrant:
        // its x is horizontal (Front's up is +z) with positive x-component.
        let i = 4 * g.width() + 4;
        let f = CubeMapFrameField::texel_frame(&g, i).unwrap();
        assert!(f.x()[2].abs() < 1e-15 && f.x()[0] > 0.0);
        assert!(f.y()[2] < 0.0);
        use crate::geometry::image_grid::PixelGrid;
        assert!(close(&f.z(), g.direction(i), 1e-15));
    }

    #[test]
    fn field_angle_between_fields() {
        // At the equator looking along +y, the theta-phi frame is x = -z (e_theta),
        // y = -x (e_phi at phi = 90 deg); the Front-camera frame is x = +x, y = -z.
        // x_front = +x = -y_tp: vartheta = -90 deg.
        let a = field_angle([0., 1., 0.], &ThetaPhiFrameField::new(), &CubeMapFrameField).unwrap();
        assert!((a + PI / 2.0).abs() < 1e-15, "{a}");
    }
}
