//! Fresnel reflection: amplitude coefficients `r_s`, `r_p`, reflectances, the phase
//! difference between `p` and `s`, and the Mueller matrix of a specular reflection.
//!
//! Conventions (derived in `proofs/optics.md`):
//! - complex amplitudes in the time convention `e^{-i omega t}`, `eta = n + i k`, `k >= 0`
//!   (Born & Wolf);
//! - `s` is the unit normal of the plane of incidence, and on every ray travelling along
//!   `d` the `p` axis is `d x s`: the *travel frames* `[s, d x s, d]` (z along travel) of
//!   the incident and the reflected ray. In them the Jones matrix is `diag(r_s, r_p)` with
//!   the Verdet (Born & Wolf) sign of `r_p`, so `r_p = -r_s` at normal incidence;
//! - Stokes components `s2 + i s3 = 2 E_x conj(E_y)` of these amplitudes, i.e.
//!   `2 conj(E_x) E_y` in the `e^{+i omega t}` convention of Mitsuba 3: `s3 > 0` when the
//!   field turns from `x` towards `-y` (clockwise about `z` seen from the tip of `z`).

use super::ior::ComplexIor;
use crate::error::{Error, Result};
use crate::stokes::MuellerMatrix;
use nalgebra::Matrix4;
use num_complex::Complex64;

/// The Fresnel amplitude reflection coefficients of a planar interface at one angle of
/// incidence (Fresnel equations, Born & Wolf §1.5.2 (21) in the form with
/// `u = eta cos(theta_t)`; §14.2 for a complex `eta`; §1.5.4 for total internal
/// reflection):
///
/// ```text
/// u   = sqrt(eta^2 - sin^2 theta_i),   Im u >= 0        (Snell: eta cos theta_t = u)
/// r_s = (cos theta_i - u) / (cos theta_i + u)
/// r_p = (eta^2 cos theta_i - u) / (eta^2 cos theta_i + u)
/// ```
///
/// `Im u >= 0` makes the transmitted wave decay away from the interface in the
/// `e^{-i omega t}` convention: for a conductor it is the principal root, under total
/// internal reflection (`eta` real, `sin theta_i > eta`) `u = i sqrt(sin^2 theta_i - eta^2)`
/// and `|r_s| = |r_p| = 1` with finite phases. At `eta = 1` both vanish (also at grazing
/// incidence, where the formulas are `0/0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FresnelCoefficients {
    r_s: Complex64,
    r_p: Complex64,
    total_internal: bool,
}

impl FresnelCoefficients {
    /// The coefficients at `cos_i = cos(theta_i)` in `[0, 1]` for the relative index
    /// `ior`. Error: `cos_i` NaN or outside `[0, 1]`.
    pub fn new(cos_i: f64, ior: &ComplexIor) -> Result<Self> {
        if !(0.0..=1.0).contains(&cos_i) {
            return Err(Error::invalid(
                "cos_theta_i",
                format!("{cos_i}"),
                "must be in [0, 1]".to_string(),
            ));
        }
        let eta = ior.eta();
        let eta2 = eta * eta;
        // sin^2 from cos: exact enough, 1 - c^2 loses nothing near grazing incidence
        // (where sin^2 is near 1) and its absolute error near normal incidence is an ulp.
        let sin2 = (1.0 - cos_i) * (1.0 + cos_i);
        let arg = eta2 - sin2;
        // `arg` has Im = 2 n k >= 0, exactly +0 for a dielectric (n > 0): the principal
        // square root then has Im >= 0, and gives +i sqrt(..) on the negative real axis.
        let arg = Complex64::new(arg.re, arg.im.abs());
        let u = arg.sqrt();
        let total_internal = ior.is_dielectric() && arg.re < 0.0;
        let c = Complex64::new(cos_i, 0.0);
        let ratio = |num: Complex64, den: Complex64| {
            if den == Complex64::new(0.0, 0.0) {
                // Only at eta = 1 and grazing incidence (u = cos_i = 0): the limit is 0.
                Complex64::new(0.0, 0.0)
            } else {
                num / den
            }
        };
        let r_s = ratio(c - u, c + u);
        let r_p = ratio(eta2 * c - u, eta2 * c + u);
        Ok(Self {
            r_s,
            r_p,
            total_internal,
        })
    }

    /// `r_s`, the amplitude ratio for the field along `s` (perpendicular, TE).
    pub fn r_s(&self) -> Complex64 {
        self.r_s
    }

    /// `r_p`, the amplitude ratio for the field along `p = d x s` (parallel, TM), Verdet
    /// (Born & Wolf) sign: `r_p = -r_s` at normal incidence.
    pub fn r_p(&self) -> Complex64 {
        self.r_p
    }

    /// `R_s = |r_s|^2` in `[0, 1]` (Born & Wolf §1.5.3).
    pub fn reflectance_s(&self) -> f64 {
        self.r_s.norm_sqr()
    }

    /// `R_p = |r_p|^2` in `[0, 1]`; zero at Brewster's angle of a dielectric.
    pub fn reflectance_p(&self) -> f64 {
        self.r_p.norm_sqr()
    }

    /// The reflectance of unpolarized light, `(R_s + R_p)/2` (PF (4), left side).
    pub fn reflectance(&self) -> f64 {
        0.5 * (self.reflectance_s() + self.reflectance_p())
    }

    /// The phase difference `delta = arg r_p - arg r_s` in `(-pi, pi]` (the retardance of
    /// the reflection; `0` when either coefficient vanishes). Born & Wolf §1.5.4 write the
    /// relative phase of total internal reflection as `arg r_s - arg r_p = -delta`, with
    /// `tan(-delta/2) = cos theta sqrt(sin^2 theta - eta^2) / sin^2 theta`.
    /// In the `e^{+i omega t}` convention of Mitsuba 3 the amplitudes are the complex
    /// conjugates, so Mitsuba's `arg(a_p) - arg(a_s)` is `-delta`.
    pub fn phase_difference(&self) -> f64 {
        let z = self.r_s.conj() * self.r_p;
        z.im.atan2(z.re)
    }

    /// Whether this is total internal reflection (real `eta`, `sin theta_i > eta`).
    pub fn is_total_internal_reflection(&self) -> bool {
        self.total_internal
    }

    /// The Mueller matrix of the reflection in the travel frames `[s, d x s, d]` of the
    /// incident and the reflected ray (both with `z` along the direction of travel `d`),
    /// with `A = (R_s + R_p)/2`, `B = (R_s - R_p)/2`, `C + i S = conj(r_s) r_p`
    /// (`C = sqrt(R_s R_p) cos delta`, `S = sqrt(R_s R_p) sin delta`):
    ///
    /// ```text
    /// [ A  B  0  0 ]
    /// [ B  A  0  0 ]
    /// [ 0  0  C  S ]
    /// [ 0  0 -S  C ]
    /// ```
    ///
    /// This is PF (7) (after Wilkie & Weidlich 2012) and, entry for entry, Mitsuba 3's
    /// `mueller::specular_reflection` (whose `delta` is `-delta` here, see
    /// [`FresnelCoefficients::phase_difference`]). Derivation: `proofs/optics.md` §2.
    pub fn mueller_travel(&self) -> MuellerMatrix {
        let (rs, rp) = (self.reflectance_s(), self.reflectance_p());
        let (a, b) = (0.5 * (rs + rp), 0.5 * (rs - rp));
        let cs = self.r_s.conj() * self.r_p;
        let (c, s) = (cs.re, cs.im);
        mueller_unchecked(Matrix4::new(
            a, b, 0.0, 0.0, //
            b, a, 0.0, 0.0, //
            0.0, 0.0, c, s, //
            0.0, 0.0, -s, c,
        ))
    }

    /// The Mueller matrix in psh's frames: the input frame `[s, w_i x s, w_i]` with `z`
    /// the direction `w_i = -d_i` towards the source, the output frame
    /// `[s, w_o x s, w_o]`, `w_o = d_o`. The input frame is `[x, -y, -z]` of the incident
    /// travel frame, in which Stokes components read `(s0, s1, -s2, -s3)`
    /// (`proofs/travel-convention.md` step 1), so this is
    /// `mueller_travel() diag(1, 1, -1, -1)`:
    ///
    /// ```text
    /// [ A  B  0  0 ]
    /// [ B  A  0  0 ]
    /// [ 0  0 -C -S ]
    /// [ 0  0  S -C ]
    /// ```
    ///
    /// At normal incidence (`C = -R`, `S = 0`) it is `R` times the identity: both frames
    /// are then the same frame, and the reflected field is `r` times the incident one.
    pub fn mueller(&self) -> MuellerMatrix {
        let m = self.mueller_travel().matrix();
        mueller_unchecked(m * Matrix4::from_diagonal(&nalgebra::Vector4::new(1.0, 1.0, -1.0, -1.0)))
    }
}

/// A Mueller matrix from entries that are finite by construction: products of the
/// coefficients, whose moduli are at most 1 for every passive medium (`k >= 0`).
fn mueller_unchecked(m: Matrix4<f64>) -> MuellerMatrix {
    MuellerMatrix::new(m).expect("Fresnel Mueller entries are bounded by 1")
}

/// [`FresnelCoefficients::new`]: the Fresnel coefficients at `cos_i`.
pub fn fresnel(cos_i: f64, ior: &ComplexIor) -> Result<FresnelCoefficients> {
    FresnelCoefficients::new(cos_i, ior)
}

/// The Mueller matrix of a specular reflection at `cos_i` in psh's frames
/// ([`FresnelCoefficients::mueller`]).
pub fn specular_reflection(cos_i: f64, ior: &ComplexIor) -> Result<MuellerMatrix> {
    Ok(FresnelCoefficients::new(cos_i, ior)?.mueller())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ior(n: f64, k: f64) -> ComplexIor {
        ComplexIor::new(n, k).unwrap()
    }

    #[test]
    fn extreme_indices_are_refused_or_finite() {
        // Up to MAX_IOR the Mueller matrix stays finite at every incidence (the `expect`
        // of `mueller_unchecked` relies on it); above, the index is refused.
        let m = crate::optics::ior::MAX_IOR;
        for (n, k) in [(m, 0.0), (m, m), (1e-300, m), (m, 1e-300), (1e-300, 0.0)] {
            for c in [0.0, 1e-300, 0.3, 1.0] {
                let f = fresnel(c, &ior(n, k)).unwrap().mueller().matrix();
                assert!(f.iter().all(|x| x.is_finite()), "n {n} k {k} cos {c}");
            }
        }
        for (n, k) in [(1e300, 0.0), (1.5, 1e300), (2.0 * m, 0.0)] {
            let e = ComplexIor::new(n, k).unwrap_err().to_string();
            assert!(e.contains("at most"), "{e}");
        }
        assert!(crate::optics::PolarizedPlastic::new(0.3, 1e300, 0.5).is_err());
    }

    #[test]
    fn normal_incidence_closed_form() {
        for n in [1.0, 1.33, 1.5, 2.4, 0.5] {
            let f = fresnel(1.0, &ior(n, 0.0)).unwrap();
            let r = (1.0 - n) / (1.0 + n);
            assert!((f.r_s() - Complex64::new(r, 0.0)).norm() < 1e-15);
            assert!((f.r_p() + Complex64::new(r, 0.0)).norm() < 1e-15);
            assert!((f.reflectance() - ior(n, 0.0).normal_reflectance()).abs() < 1e-15);
        }
    }

    #[test]
    fn brewster_angle_kills_p() {
        for n in [1.33, 1.5, 2.4] {
            let theta_b = f64::atan(n);
            let f = fresnel(theta_b.cos(), &ior(n, 0.0)).unwrap();
            assert!(f.reflectance_p() < 1e-28, "{}", f.reflectance_p());
            assert!(f.reflectance_s() > 0.0);
            // The Mueller matrix there is a polarizer along s (A = B).
            let m = f.mueller().matrix();
            assert!((m[(0, 0)] - m[(0, 1)]).abs() < 1e-15);
        }
    }

    #[test]
    fn total_internal_reflection_has_unit_modulus_and_finite_phase() {
        // Light inside glass (n = 1.51), the Fresnel rhomb angle 54.6 degrees: the relative
        // phase is 45 degrees (Born & Wolf §1.5.4).
        let eta = ior(1.0 / 1.51, 0.0);
        let theta = 54.6f64.to_radians();
        let f = fresnel(theta.cos(), &eta).unwrap();
        assert!(f.is_total_internal_reflection());
        assert!((f.r_s().norm() - 1.0).abs() < 1e-15);
        assert!((f.r_p().norm() - 1.0).abs() < 1e-15);
        let d = -f.phase_difference();
        assert!((d.to_degrees() - 45.0).abs() < 0.05, "{}", d.to_degrees());
        // Exactly at the critical angle and at grazing incidence.
        let crit = (1.0f64 / 1.51).asin();
        for c in [crit.cos(), 0.0, 1e-300] {
            let f = fresnel(c, &eta).unwrap();
            assert!((f.reflectance() - 1.0).abs() < 1e-12);
            assert!(f.phase_difference().is_finite());
        }
    }

    #[test]
    fn index_matched_and_grazing() {
        let f = fresnel(0.0, &ior(1.0, 0.0)).unwrap();
        assert_eq!(f.reflectance(), 0.0);
        let f = fresnel(0.0, &ior(1.5, 0.0)).unwrap();
        assert!((f.r_s() + Complex64::new(1.0, 0.0)).norm() < 1e-15);
        assert!((f.r_p() + Complex64::new(1.0, 0.0)).norm() < 1e-15);
        assert!(fresnel(-0.1, &ior(1.5, 0.0)).is_err());
        assert!(fresnel(f64::NAN, &ior(1.5, 0.0)).is_err());
        assert!(fresnel(1.0 + 1e-12, &ior(1.5, 0.0)).is_err());
    }

    #[test]
    fn psh_frames_flip_the_lower_block() {
        let f = fresnel(0.6, &ior(0.2, 3.4)).unwrap();
        let t = f.mueller_travel().matrix();
        let p = f.mueller().matrix();
        for i in 0..4 {
            for j in 0..4 {
                let sign = if j >= 2 { -1.0 } else { 1.0 };
                assert_eq!(p[(i, j)], sign * t[(i, j)]);
            }
        }
        // Normal incidence: R times the identity in psh's frames.
        let m = fresnel(1.0, &ior(0.2, 3.4)).unwrap().mueller().matrix();
        let r = ior(0.2, 3.4).normal_reflectance();
        assert!((m - Matrix4::identity() * r).amax() < 1e-15);
    }
}
