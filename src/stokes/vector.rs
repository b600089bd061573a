//! Geometric Stokes vectors `[s]_F` (PSH (15)-(20)) and spin-2 Stokes vectors.
//!
//! A [`StokesVector`] holds components together with the frame they are measured in; it
//! is built with [`StokesVector::new`] (`[s]_F`, PSH (15)) and read with
//! [`StokesVector::components_in`] (`[s]^F`, PSH (16)). Operations between two Stokes
//! vectors (PSH (17), (18)) first convert to a common frame and fail for different rays.

use super::components::StokesComponents;
use super::frame_change::FrameChange;
use crate::error::relabel;
use crate::error::{finite, Result};
use crate::geometry::frame::{Frame, FrameField};
use nalgebra::{Rotation3, Vector2, Vector3, Vector4};
use num_complex::Complex64;

/// A Stokes vector `[s]_F` (PSH (15)): the polarization state of a ray along the frame's
/// `z` axis, stored as components `s` measured in the frame `F`. Two `StokesVector`s that
/// are equal as geometric objects may store different components in different frames;
/// compare them with [`StokesVector::approx_eq`] (there is deliberately no `PartialEq`,
/// which could only compare the stored representations).
///
/// # Example
///
/// Light fully polarized along `x` of `F`, read in `F' = R_z(pi/4) F` (PSH (14)):
/// `s1' + i s2' = e^{-i pi/2} (s1 + i s2) = -i`.
///
/// ```
/// use psh::geometry::Frame;
/// use psh::stokes::{StokesComponents, StokesVector};
/// use std::f64::consts::FRAC_PI_4;
///
/// let f = Frame::from_z([0.0, 0.6, 0.8])?;
/// let s = StokesVector::new(StokesComponents::new([1.0, 1.0, 0.0, 0.0])?, f);
/// let f2 = f.rotated_about_z(FRAC_PI_4)?;
/// let c = s.components_in(&f2)?;
/// assert!(c.s1().abs() < 1e-15 && (c.s2() + 1.0).abs() < 1e-15);
/// assert_eq!((c.s0(), c.s3()), (1.0, 0.0));
/// // The same geometric vector stored in `F'`; a frame of another ray is refused.
/// assert!(s.in_frame(&f2)?.approx_eq(&s, 1e-15)?);
/// assert!(s.components_in(&Frame::from_z([1.0, 0.0, 0.0])?).is_err());
/// # Ok::<(), psh::Error>(())
/// ```
#[derive(Clone, Copy, Debug)]
pub struct StokesVector {
    s: StokesComponents,
    frame: Frame,
}

impl StokesVector {
    /// `[s]_F` (PSH (15)): the Stokes vector whose components in `frame` are `s`.
    pub fn new(s: StokesComponents, frame: Frame) -> Self {
        Self { s, frame }
    }

    /// `[s_k]_F` for each of the components `s` (channels measured in one frame). Error: a
    /// non-finite component.
    pub fn all_in_frame(s: &[[f64; 4]], frame: Frame) -> Result<Vec<Self>> {
        s.iter()
            .map(|&x| Ok(Self::new(StokesComponents::new(x)?, frame)))
            .collect()
    }

    /// `[s]_F` from the frame field `field` at the direction `w` (the frame
    /// `field.frame(w)`). Errors: those of the field (bad direction).
    pub fn from_field<F: FrameField + ?Sized>(
        s: StokesComponents,
        w: [f64; 3],
        field: &F,
    ) -> Result<Self> {
        Ok(Self::new(s, field.frame(w)?))
    }

    /// The full vector as the direct sum `s0 (+) [[s1, s2]]_F (+) s3` (PSH Sec. 4.2.1).
    /// Error: non-finite `s0` or `s3`.
    pub fn from_direct_sum(s0: f64, linear: &Spin2StokesVector, s3: f64) -> Result<Self> {
        finite("s0", s0)?;
        finite("s3", s3)?;
        let z = linear.z;
        Ok(Self::new(
            StokesComponents::from_vector_unchecked(Vector4::new(s0, z.re, z.im, s3)),
            linear.frame,
        ))
    }

    /// The parts `(s0, [[s1, s2]]_F, s3)` of the direct sum (PSH Sec. 4.2.1).
    pub fn to_direct_sum(&self) -> (f64, Spin2StokesVector, f64) {
        (self.s.s0(), self.spin2(), self.s.s3())
    }

    /// The spin-2 part `[[s1, s2]]_F`.
    pub fn spin2(&self) -> Spin2StokesVector {
        Spin2StokesVector {
            z: Complex64::new(self.s.s1(), self.s.s2()),
            frame: self.frame,
        }
    }

    /// `s0`: a scalar, the same in every frame of the ray (PSH (14)).
    pub fn s0(&self) -> f64 {
        self.s.s0()
    }

    /// `s3`: a scalar, the same in every frame of the ray (PSH (14)).
    pub fn s3(&self) -> f64 {
        self.s.s3()
    }

    /// The frame the components are stored in.
    pub fn frame(&self) -> &Frame {
        &self.frame
    }

    /// The ray direction `w = F[:, 3]`.
    pub fn direction(&self) -> [f64; 3] {
        self.frame.direction()
    }

    /// The components in the stored frame, `[s]^F` with `F = self.frame()`.
    pub fn components(&self) -> StokesComponents {
        self.s
    }

    /// `[s]^{F'}` (PSH (16)): the components in another frame `F'` of the same ray, by
    /// PSH (14): `s' = C(vartheta) s` with `F' = R_z(vartheta) F`. Error: `F'` belongs to
    /// another ray ([`crate::Error::DifferentRays`], tolerance
    /// [`crate::geometry::frame::RAY_TOLERANCE`]).
    pub fn components_in(&self, frame: &Frame) -> Result<StokesComponents> {
        let change = FrameChange::between(&self.frame, frame)
            .map_err(|e| relabel(e, "Stokes vector read in a frame"))?;
        Ok(StokesComponents::from_vector_unchecked(Vector4::from(
            change.components(self.s.to_array()),
        )))
    }

    /// `[s]^{field(w)}`: the components in the frame that `field` assigns to this ray.
    pub fn components_in_field<F: FrameField + ?Sized>(
        &self,
        field: &F,
    ) -> Result<StokesComponents> {
        self.components_in(&field.frame(self.direction())?)
    }

    /// The same Stokes vector stored in another frame of its ray.
    pub fn in_frame(&self, frame: &Frame) -> Result<StokesVector> {
        Ok(Self::new(self.components_in(frame)?, *frame))
    }

    /// `s + t` (PSH (17)): `[s + [t]^F]_F` in this vector's frame `F`. Error: different
    /// rays.
    pub fn try_add(&self, other: &StokesVector) -> Result<StokesVector> {
        let t = other
            .components_in(&self.frame)
            .map_err(|e| relabel(e, "sum of Stokes vectors"))?;
        Ok(Self::new(self.s + t, self.frame))
    }

    /// `a s` (scaling commutes with PSH (14)). Error: non-finite `a`.
    pub fn scaled(&self, a: f64) -> Result<StokesVector> {
        finite("scale factor", a)?;
        Ok(Self::new(self.s * a, self.frame))
    }

    /// `<s, t>_S = s . [t]^F` (PSH (18)). Error: different rays.
    pub fn inner(&self, other: &StokesVector) -> Result<f64> {
        let t = other
            .components_in(&self.frame)
            .map_err(|e| relabel(e, "inner product of Stokes vectors"))?;
        Ok(self.s.dot(&t))
    }

    /// `R_S s = [[s]^F]_{R F}` (PSH (19)): the polarized ray itself rotated by `r`, now a
    /// Stokes vector of the ray `R w`. Reading it in `R F` gives the original components.
    /// Error: `r` not a rotation.
    pub fn rotate(&self, r: &Rotation3<f64>) -> Result<StokesVector> {
        Ok(Self::new(self.s, self.frame.rotated(r)?))
    }

    /// The direction of linear polarization, a unit vector orthogonal to the ray (defined
    /// up to sign; the representative `cos(chi) x + sin(chi) y` of the stored frame, with
    /// `chi` of [`StokesComponents::angle_of_linear_polarization`]). A geometric
    /// quantity: the same line in every frame. `None` when `s1 = s2 = 0`.
    pub fn linear_polarization_direction(&self) -> Option<Vector3<f64>> {
        let chi = self.s.angle_of_linear_polarization()?;
        let (s, c) = chi.sin_cos();
        Some(self.frame.x() * c + self.frame.y() * s)
    }

    /// Whether `other` is the same Stokes vector within `tol` (componentwise, both read in
    /// this vector's frame). Error: different rays.
    pub fn approx_eq(&self, other: &StokesVector, tol: f64) -> Result<bool> {
        Ok(self.s.approx_eq(&other.components_in(&self.frame)?, tol))
    }
}

/// A spin-2 Stokes vector `[[s1, s2]]_F = [s1 + i s2]_F` (PSH Sec. 4.2.1): the linear
/// polarization of a ray, stored as the complex number `s1 + i s2` measured in `F`. In
/// another frame `F' = R_z(vartheta) F` it reads `e^{-2 i vartheta} (s1 + i s2)` (PSH (14)).
#[derive(Clone, Copy, Debug)]
pub struct Spin2StokesVector {
    z: Complex64,
    frame: Frame,
}

impl Spin2StokesVector {
    /// `[[s1, s2]]_F`. Error: a non-finite component.
    pub fn new(s: Vector2<f64>, frame: Frame) -> Result<Self> {
        Self::from_complex(Complex64::new(s[0], s[1]), frame)
    }

    /// `[s1 + i s2]_F`. Error: a non-finite part.
    pub fn from_complex(z: Complex64, frame: Frame) -> Result<Self> {
        finite("s1", z.re)?;
        finite("s2", z.im)?;
        Ok(Self { z, frame })
    }

    /// The frame the components are stored in.
    pub fn frame(&self) -> &Frame {
        &self.frame
    }

    /// The ray direction.
    pub fn direction(&self) -> [f64; 3] {
        self.frame.direction()
    }

    /// `s1 + i s2` in the stored frame.
    pub fn complex(&self) -> Complex64 {
        self.z
    }

    /// `s1 + i s2` in another frame of the ray (PSH (14)). Error: different rays.
    pub fn complex_in(&self, frame: &Frame) -> Result<Complex64> {
        let change = FrameChange::between(&self.frame, frame)
            .map_err(|e| relabel(e, "spin-2 Stokes vector read in a frame"))?;
        Ok(change.spin2(self.z))
    }

    /// `[s1, s2]` in another frame of the ray (PSH (14), (16)). Error: different rays.
    pub fn components_in(&self, frame: &Frame) -> Result<Vector2<f64>> {
        let z = self.complex_in(frame)?;
        Ok(Vector2::new(z.re, z.im))
    }

    /// The complex multiple `z [s1 + i s2]_F = [z (s1 + i s2)]_F` (PSH (20)): scales by
    /// `|z|` and turns the polarization by `arg(z)/2` about the ray (from `x` towards `y`).
    /// Frame-independent, since the conversion is itself a complex factor. Error:
    /// non-finite `z`.
    pub fn mul_complex(&self, z: Complex64) -> Result<Spin2StokesVector> {
        finite("complex factor (re)", z.re)?;
        finite("complex factor (im)", z.im)?;
        Ok(Self {
            z: z * self.z,
            frame: self.frame,
        })
    }

    /// The sum (PSH (17)) in this vector's frame. Error: different rays.
    pub fn try_add(&self, other: &Spin2StokesVector) -> Result<Spin2StokesVector> {
        let t = other
            .complex_in(&self.frame)
            .map_err(|e| relabel(e, "sum of spin-2 Stokes vectors"))?;
        Ok(Self {
            z: self.z + t,
            frame: self.frame,
        })
    }

    /// The inner product `s1 t1 + s2 t2 = Re(conj(s) t)` (PSH (18)). Error: different
    /// rays.
    pub fn inner(&self, other: &Spin2StokesVector) -> Result<f64> {
        let t = other
            .complex_in(&self.frame)
            .map_err(|e| relabel(e, "inner product of spin-2 Stokes vectors"))?;
        Ok(self.z.re * t.re + self.z.im * t.im)
    }

    /// `R_S` (PSH (19)): `[[s1, s2]]_{R F}`. Error: `r` not a rotation.
    pub fn rotate(&self, r: &Rotation3<f64>) -> Result<Spin2StokesVector> {
        Ok(Self {
            z: self.z,
            frame: self.frame.rotated(r)?,
        })
    }

    /// Whether `other` is the same within `tol` (both read in this frame).
    pub fn approx_eq(&self, other: &Spin2StokesVector, tol: f64) -> Result<bool> {
        let t = other.complex_in(&self.frame)?;
        Ok((self.z.re - t.re).abs() <= tol && (self.z.im - t.im).abs() <= tol)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Error;
    use std::f64::consts::PI;

    fn comps(s: [f64; 4]) -> StokesComponents {
        StokesComponents::new(s).unwrap()
    }

    /// PSH (14) sign, by hand: light polarized along x is `[1, 1, 0, 0]` in `F`. In
    /// `F' = R_z(45 deg) F`, `x = (x' - y')/sqrt 2` is the `-45` degree direction, so the
    /// components are `[1, 0, -1, 0]` (derivation in `proofs/stokes-frames.md`).
    #[test]
    fn horizontal_beam_read_in_a_frame_turned_by_45_degrees() {
        let f = Frame::world();
        let g = f.rotated_about_z(PI / 4.0).unwrap();
        let s = StokesVector::new(comps([1., 1., 0., 0.]), f);
        let t = s.components_in(&g).unwrap();
        assert!(t.approx_eq(&comps([1., 0., -1., 0.]), 1e-15), "{t:?}");
        // And by 90 degrees: along y', s1 = -1.
        let h = f.rotated_about_z(PI / 2.0).unwrap();
        assert!(s
            .components_in(&h)
            .unwrap()
            .approx_eq(&comps([1., -1., 0., 0.]), 1e-15));
        // The polarization direction is still x.
        let d = s
            .in_frame(&g)
            .unwrap()
            .linear_polarization_direction()
            .unwrap();
        assert!((d.cross(&Vector3::x())).norm() < 1e-15);
    }

    #[test]
    fn different_rays_and_nan_are_errors() {
        let a = StokesVector::new(comps([1., 0.2, 0., 0.]), Frame::world());
        let b = StokesVector::new(
            comps([1., 0., 0., 0.]),
            Frame::from_z([0., 1., 0.]).unwrap(),
        );
        assert!(matches!(a.try_add(&b), Err(Error::DifferentRays { .. })));
        assert!(matches!(a.inner(&b), Err(Error::DifferentRays { .. })));
        assert!(matches!(
            a.components_in(b.frame()),
            Err(Error::DifferentRays { .. })
        ));
        assert!(a.scaled(f64::NAN).is_err());
        let lin = a.spin2();
        assert!(StokesVector::from_direct_sum(f64::NAN, &lin, 0.0).is_err());
        assert!(lin.mul_complex(Complex64::new(f64::INFINITY, 0.0)).is_err());
        assert!(Spin2StokesVector::new(Vector2::new(0.0, f64::NAN), Frame::world()).is_err());
    }

    /// Fig. 4(b): rotating the Stokes vector itself by `vartheta` about its ray turns its
    /// components in a fixed frame by `+2 vartheta`.
    #[test]
    fn rotating_about_the_ray_turns_components_by_twice_the_angle() {
        let f = Frame::world();
        let a = 0.3;
        let r = Rotation3::from_axis_angle(&Vector3::z_axis(), a);
        let s = StokesVector::new(comps([1., 0.6, 0., 0.1]), f);
        let t = s.rotate(&r).unwrap().components_in(&f).unwrap();
        let want = comps([1., 0.6 * (2. * a).cos(), 0.6 * (2. * a).sin(), 0.1]);
        assert!(t.approx_eq(&want, 1e-15), "{t:?}");
    }

    /// PSH (20): multiplying by `e^{i alpha}` turns the polarization direction by
    /// `alpha / 2` about the ray, whatever the frame used.
    #[test]
    fn complex_multiple_turns_by_half_the_argument() {
        let f = Frame::from_z(Vector3::new(0.3, -0.5, 0.8).normalize().into()).unwrap();
        let g = f.rotated_about_z(1.1).unwrap();
        let lin = Spin2StokesVector::new(Vector2::new(0.5, 0.0), f).unwrap();
        let alpha = 0.8;
        let z = Complex64::from_polar(2.0, alpha);
        let out_f = lin.mul_complex(z).unwrap();
        // The same operation done in g.
        let lin_g = Spin2StokesVector::from_complex(lin.complex_in(&g).unwrap(), g).unwrap();
        let out_g = lin_g.mul_complex(z).unwrap();
        assert!(out_f.approx_eq(&out_g, 1e-15).unwrap());
        // Direction: x of f turned by alpha/2 towards y; magnitude 1.
        let full = StokesVector::from_direct_sum(1.0, &out_f, 0.0).unwrap();
        let d = full.linear_polarization_direction().unwrap();
        let want = f.x() * (alpha / 2.0).cos() + f.y() * (alpha / 2.0).sin();
        assert!(d.cross(&want).norm() < 1e-15);
        assert!((out_f.complex().norm() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn direct_sum_round_trip() {
        let f = Frame::world().rotated_about_z(0.2).unwrap();
        let s = StokesVector::new(comps([2., 0.3, -0.4, 0.5]), f);
        let (s0, lin, s3) = s.to_direct_sum();
        assert_eq!((s0, s3), (2., 0.5));
        assert_eq!(lin.complex(), Complex64::new(0.3, -0.4));
        let back = StokesVector::from_direct_sum(s0, &lin, s3).unwrap();
        assert_eq!(back.components(), s.components());
        assert_eq!(back.frame(), s.frame());
    }
}
