//! The polarizing filter function of Enfeldt & Goswami (PF): how much of a specular
//! reflection of unpolarized light an ideal linear polarizer in front of the camera lets
//! through, as a factor `Omega in [0, 2]` on the unfiltered (Fresnel-weighted) specular
//! term, so that a non-polarizing renderer can apply it (PF Sec. 3).
//!
//! | item | formula | source |
//! |---|---|---|
//! | [`Incidence`] | the angle of incidence `theta in [0, 90)` degrees | PF Sec. 2.1 |
//! | [`ior_from_r0`] | `n = (1 + sqrt R_0)/(1 - sqrt R_0)` | PF (14) |
//! | [`schlick`] | `R_0 + (1 - R_0)(1 - cos theta)^5` | PF (4) |
//! | [`psi`] | degree of polarization `B/A` of the reflection, from `eta` | PF (10)-(11) |
//! | [`omega_ior`] | `Omega_IOR = psi cos 2 varphi + 1` | PF (12) |
//! | [`psi_dielectric`] | `psi_D` from `R_0` | PF (13)-(14), Listing 1 |
//! | [`beta_approx`], [`gamma_approx`] | `beta~`, `gamma~` from `R_0` | PF (15), (16) |
//! | [`psi_conductor_approx`] | `psi~_C` | PF Sec. 3.6, Listing 2 |
//! | [`psi_approx`] | `psi~`: the metalness switch | PF Sec. 3.6 |
//! | [`omega`] | `Omega = psi~ cos 2 varphi + 1` | PF (17), Listing 3 |
//! | [`filter_angle`] | `varphi = omega + alpha` from camera and surface | PF (18), Listing 4 |
//! | [`mueller_filtered_reflection`] | the same by Mueller calculus, for checks | PF Sec. 3.2-3.4 |
//!
//! The Fresnel terms `F_perp = R_s`, `F_par = R_p`, their phase difference and the Fresnel
//! Mueller matrix (PF (1)-(2), (7)) are [`super::FresnelCoefficients`]; `R_0` from the
//! IOR (PF (3)) is [`super::ComplexIor::normal_reflectance`]; the polarizer (PF (8)) and
//! Malus's law are [`super::LinearPolarizer`] and [`super::malus_law`].
//!
//! Derivations not printed in the paper (the bounds `0 <= psi <= 1`, the cancellation-free
//! `h + c`, the frame of `varphi`, the limits) are in `proofs/polarizing-filter.md`.

use super::fresnel::FresnelCoefficients;
use super::ior::ComplexIor;
use super::microfacet::{sp_frames_unit, unit_pair};
use super::polarizer::LinearPolarizer;
use crate::error::{finite, Error, Result};
use crate::geometry::check_direction;
use crate::geometry::frame::Frame;
use crate::stokes::{MuellerTransform, StokesComponents, StokesVector};
use nalgebra::Vector3;
use std::f64::consts::FRAC_PI_2;

/// An angle of incidence `theta in [0, 90)` degrees, kept as `cos theta` and
/// `sin^2 theta` (the quantities of PF's listings, `ct` and `st2`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Incidence {
    cos: f64,
    sin2: f64,
}

impl Incidence {
    /// `theta` in radians, `0 <= theta < pi/2`. Error ([`Error::InvalidArgument`] with the
    /// value in radians and degrees): NaN, infinite or outside `[0, pi/2)`.
    pub fn from_angle(theta: f64) -> Result<Self> {
        if !(0.0..FRAC_PI_2).contains(&theta) {
            return Err(Error::invalid(
                "angle of incidence theta",
                format!("{theta} rad ({} degrees)", theta.to_degrees()),
                "must be in [0, 90) degrees",
            ));
        }
        let (s, c) = theta.sin_cos();
        Ok(Self {
            cos: c,
            sin2: s * s,
        })
    }

    /// `theta` in degrees, `0 <= theta < 90`. Errors as [`Incidence::from_angle`].
    pub fn from_degrees(degrees: f64) -> Result<Self> {
        if !(0.0..90.0).contains(&degrees) {
            return Err(Error::invalid(
                "angle of incidence theta",
                format!("{degrees} degrees"),
                "must be in [0, 90) degrees",
            ));
        }
        Self::from_angle(degrees.to_radians().min(below_right_angle()))
    }

    /// From `cos theta` in `(0, 1]` (e.g. `dot(l, h)`). Error: NaN or outside `(0, 1]`
    /// (`cos theta = 0` is 90 degrees, excluded).
    pub fn from_cos(cos_theta: f64) -> Result<Self> {
        if !(cos_theta > 0.0 && cos_theta <= 1.0) {
            return Err(Error::invalid(
                "cos of the angle of incidence",
                format!("{cos_theta}"),
                "must be in (0, 1] (theta in [0, 90) degrees)",
            ));
        }
        Ok(Self {
            cos: cos_theta,
            sin2: (1.0 - cos_theta) * (1.0 + cos_theta),
        })
    }

    /// `cos theta`.
    pub fn cos(&self) -> f64 {
        self.cos
    }

    /// `sin^2 theta`.
    pub fn sin2(&self) -> f64 {
        self.sin2
    }

    /// `theta` in radians.
    pub fn angle(&self) -> f64 {
        self.sin2.sqrt().atan2(self.cos)
    }

    /// The common shape of PF (10), (13) and `psi~_C`:
    /// `p cos theta sin^2 theta / (q cos^2 theta + r sin^4 theta)` for `p, q, r >= 0`
    /// (`0` where the denominator vanishes, which needs `theta = 0`, where the numerator
    /// vanishes too).
    fn shape(&self, p: f64, q: f64, r: f64) -> f64 {
        let (ct, st2) = (self.cos, self.sin2);
        let den = q * ct * ct + r * st2 * st2;
        if den > 0.0 {
            p * ct * st2 / den
        } else {
            0.0
        }
    }
}

/// The largest `f64` below `pi/2`.
fn below_right_angle() -> f64 {
    f64::from_bits(FRAC_PI_2.to_bits() - 1)
}

/// A validated specular colour `R_0` in `[0, 1)` (one channel).
fn check_r0(r0: f64) -> Result<f64> {
    if !(0.0..1.0).contains(&r0) {
        return Err(Error::invalid(
            "specular colour R_0",
            format!("{r0}"),
            "must be in [0, 1)",
        ));
    }
    Ok(r0)
}

/// PF (14): the real index of a dielectric (in air) with normal reflectance `R_0`,
/// `n = (1 + sqrt R_0) / (1 - sqrt R_0)`, the root `n >= 1` of PF (3) with `k = 0`.
/// Error: `R_0` NaN or outside `[0, 1)`.
pub fn ior_from_r0(r0: f64) -> Result<ComplexIor> {
    let r = check_r0(r0)?.sqrt();
    ComplexIor::dielectric((1.0 + r) / (1.0 - r))
}

/// PF (4): Schlick's approximation `R_0 + (1 - R_0)(1 - cos theta)^5` of the reflectance
/// `(F_perp + F_par)/2` of unpolarized light. Error: `R_0` NaN or outside `[0, 1)`.
pub fn schlick(r0: f64, theta: Incidence) -> Result<f64> {
    let r0 = check_r0(r0)?;
    Ok(r0 + (1.0 - r0) * (1.0 - theta.cos).powi(5))
}

/// PF (10)-(11): the polarizing factor `psi = B/A = (F_perp - F_par)/(F_perp + F_par)`, the
/// degree of polarization of the reflection of unpolarized light, in `[0, 1]`:
///
/// ```text
/// psi = g cos theta sin^2 theta / (h cos^2 theta + sin^4 theta),
/// c = n^2 - k^2 - sin^2 theta,  h = a^2 + b^2 = sqrt(c^2 + 4 n^2 k^2),  g = 2a = sqrt(2 (h + c))
/// ```
///
/// (`a`, `b` of PF (2); the transcription's `g = sqrt(2) 2a` reads `g = sqrt 2 sqrt(h + c)`,
/// which is `2a`). For `c < 0`, `h + c` is computed as `4 n^2 k^2 / (h - c)` (no
/// cancellation; `proofs/polarizing-filter.md` §2). It is `1` exactly at Brewster's angle of
/// a dielectric and `0` under total internal reflection (`g = 0`).
pub fn psi(ior: &ComplexIor, theta: Incidence) -> f64 {
    let (n, k) = (ior.n(), ior.k());
    let c = (n - k) * (n + k) - theta.sin2;
    let two_nk = 2.0 * n * k;
    let h = c.hypot(two_nk);
    let h_plus_c = if c >= 0.0 {
        h + c
    } else {
        two_nk * two_nk / (h - c)
    };
    let g = (2.0 * h_plus_c).sqrt();
    theta.shape(g, h, 1.0)
}

/// PF (12): the exact filter factor `Omega_IOR(eta, theta, varphi) = psi cos 2 varphi + 1`
/// in `[0, 2]`: the intensity of the reflection of unpolarized light seen through an ideal
/// linear polarizer at `varphi` from the normal of the plane of incidence (the `s` axis),
/// doubled (Malus) and divided by the unfiltered reflectance `(F_perp + F_par)/2`.
/// Error: `varphi` non-finite.
pub fn omega_ior(ior: &ComplexIor, theta: Incidence, varphi: f64) -> Result<f64> {
    let c2 = (2.0 * finite("filter angle varphi", varphi)?).cos();
    Ok(psi(ior, theta) * c2 + 1.0)
}

/// PF (13) with `n` from PF (14): the polarizing factor of a dielectric from its specular
/// colour,
///
/// ```text
/// psi_D = 2 sqrt(n^2 - sin^2 theta) cos theta sin^2 theta
///         / ((n^2 - sin^2 theta) cos^2 theta + sin^4 theta),
/// ```
///
/// clamped to `[0, 1]` as in PF Listing 1 (`saturate`; the exact value is in `[0, 1]`,
/// the clamp only removes rounding). Exactly [`psi`] of `n + 0i`. Error: `R_0` NaN or
/// outside `[0, 1)`.
pub fn psi_dielectric(r0: f64, theta: Incidence) -> Result<f64> {
    let n = ior_from_r0(r0)?.n();
    let c = (n - theta.sin2.sqrt()) * (n + theta.sin2.sqrt());
    Ok(theta.shape(2.0 * c.sqrt(), c, 1.0).clamp(0.0, 1.0))
}

/// PF (15): `beta~(R_0) = 0.1 / (1.095 - R_0)^3 + 5.4 R_0^2 + 1`, the approximation of
/// `beta = h/g` of a conductor. Error: `R_0` NaN or outside `[0, 1)`.
pub fn beta_approx(r0: f64) -> Result<f64> {
    let r0 = check_r0(r0)?;
    let rb = 1.095 - r0;
    Ok(0.1 / (rb * rb * rb) + 5.4 * r0 * r0 + 1.0)
}

/// PF (16): `gamma~(R_0) = 0.16 R_0^2 / (1.18 - R_0)^2 + 0.35 (1.18 - R_0)`, the
/// approximation of `gamma = 1/g` of a conductor. Error: `R_0` NaN or outside `[0, 1)`.
pub fn gamma_approx(r0: f64) -> Result<f64> {
    let r0 = check_r0(r0)?;
    let rg = 1.18 - r0;
    Ok(0.16 * r0 * r0 / (rg * rg) + 0.35 * rg)
}

/// PF Sec. 3.6 (`psi~_C`, Listing 2): the approximate polarizing factor of a conductor
/// from its specular colour,
/// `psi~_C = cos theta sin^2 theta / (beta~ cos^2 theta + gamma~ sin^4 theta)`, clamped to
/// `[0, 1]` (`saturate`). Error: `R_0` NaN or outside `[0, 1)`.
pub fn psi_conductor_approx(r0: f64, theta: Incidence) -> Result<f64> {
    let (b, g) = (beta_approx(r0)?, gamma_approx(r0)?);
    Ok(theta.shape(1.0, b, g).clamp(0.0, 1.0))
}

/// PF Sec. 3.6: the approximate polarizing factor `psi~`, [`psi_conductor_approx`] if
/// `metalness > 0.5` and [`psi_dielectric`] otherwise (a step, not a blend, as in the
/// paper). Errors: `R_0` NaN or outside `[0, 1)`; `metalness` NaN or outside `[0, 1]`.
pub fn psi_approx(r0: f64, theta: Incidence, metalness: f64) -> Result<f64> {
    if !(0.0..=1.0).contains(&metalness) {
        return Err(Error::invalid(
            "metalness",
            format!("{metalness}"),
            "must be in [0, 1]",
        ));
    }
    if metalness > 0.5 {
        psi_conductor_approx(r0, theta)
    } else {
        psi_dielectric(r0, theta)
    }
}

/// PF (17) (Listing 3): the polarizing filter function
/// `Omega(R_0, theta, varphi) = psi~ cos 2 varphi + 1` in `[0, 2]`, a factor on the
/// unfiltered specular term. Equal to [`omega_ior`] for dielectrics with matching `R_0`.
/// Errors as [`psi_approx`], and `varphi` non-finite.
pub fn omega(r0: f64, theta: Incidence, varphi: f64, metalness: f64) -> Result<f64> {
    let c2 = (2.0 * finite("filter angle varphi", varphi)?).cos();
    Ok(psi_approx(r0, theta, metalness)? * c2 + 1.0)
}

/// PF (18) with the semantics of PF Listing 4: the filter angle `varphi = omega + alpha`
/// relative to the surface,
///
/// ```text
/// x' = normalize(h x v),   alpha = atan2(v . (x' x x_cam), x' . x_cam),
/// ```
///
/// where `v` is the unit direction from the surface to the viewer, `h` the unit (half)
/// vector of the reflecting facet, `x_cam` the viewer's reference axis (Listing 5:
/// `normalize(up x v)`, the camera's right) and `omega` the filter's counterclockwise
/// angle from `x_cam` (radians). `alpha` is the angle from the `s` axis `x'` to `x_cam`
/// about `v` (counterclockwise seen from the viewer), so `varphi` is the filter's angle
/// from `s` in PF (12) (`proofs/polarizing-filter.md` §4). Only the part of `x_cam`
/// orthogonal to `v` matters. At normal incidence (`h x v = 0`, where `psi = 0`) `alpha`
/// is taken as 0. Errors: non-unit or non-finite vectors, `x_cam` parallel to `v`,
/// `omega` non-finite.
pub fn filter_angle(camera_x: [f64; 3], h: [f64; 3], v: [f64; 3], omega: f64) -> Result<f64> {
    let omega = finite("filter angle omega", omega)?;
    let xc = Vector3::from(check_direction(camera_x)?);
    let h = Vector3::from(check_direction(h)?);
    let v = Vector3::from(check_direction(v)?);
    if xc.cross(&v).norm() <= 1e-12 {
        return Err(Error::invalid(
            "camera x axis",
            format!("{camera_x:?}"),
            format!("parallel to the view direction {:?}", [v[0], v[1], v[2]]),
        ));
    }
    // atan2 is invariant under a positive scale of x'; scaling by the largest component
    // instead of normalizing keeps tiny cross products (grazing) from underflowing.
    let sx = h.cross(&v);
    let big = sx.amax();
    if big == 0.0 {
        return Ok(omega);
    }
    let sx = sx / big;
    Ok(omega + v.dot(&sx.cross(&xc)).atan2(sx.dot(&xc)))
}

/// The reference of PF Sec. 3.2-3.4 by Mueller calculus in psh's frames: unpolarized
/// light of intensity `intensity` arriving from `w_i` (unit, towards the source) is
/// reflected specularly by a facet with normal `h = normalize(w_i + w_o)` into `w_o`
/// (unit, towards the viewer) with the Fresnel Mueller matrix
/// ([`FresnelCoefficients::mueller`] in the frames of [`super::sp_frames`]) and then
/// passes an ideal linear polarizer ([`LinearPolarizer`]) whose axis is at `omega` from
/// `camera_x` counterclockwise about `w_o`. Returns the Stokes vector behind the
/// polarizer in the camera frame `[x_cam, w_o x x_cam, w_o]` (`x_cam` made orthogonal
/// to `w_o`). Its `s0` doubled over `intensity (F_perp + F_par)/2` is `Omega_IOR` of
/// PF (12) at `varphi` = [`filter_angle`]`(camera_x, h, w_o, omega)`.
/// Errors: non-unit or non-finite directions, `w_i = -w_o` (no facet), `camera_x`
/// parallel to `w_o`, non-finite `omega` or `intensity`.
pub fn mueller_filtered_reflection(
    ior: &ComplexIor,
    wi: [f64; 3],
    wo: [f64; 3],
    camera_x: [f64; 3],
    omega: f64,
    intensity: f64,
) -> Result<StokesVector> {
    let (wi_v, wo_v) = unit_pair(wi, wo)?;
    let sum = wi_v + wo_v;
    let len = sum.norm();
    if len == 0.0 {
        return Err(Error::invalid(
            "directions w_i, w_o",
            format!("{wi:?}, {wo:?}"),
            "opposite: no facet reflects one into the other",
        ));
    }
    let theta = Incidence::from_cos((sum / len).dot(&wi_v).min(1.0))?;
    let fresnel = FresnelCoefficients::new(theta.cos, ior)?;
    let (fi, fo) = sp_frames_unit(&wi_v, &wo_v)?;
    let reflection = MuellerTransform::new(fresnel.mueller(), fi, fo);
    let camera = Frame::from_z_and_x(wo, camera_x)?;
    let polarizer = LinearPolarizer::new(omega)?.transform(camera);
    let light = StokesVector::new(StokesComponents::unpolarized(intensity)?, fi);
    polarizer.compose(&reflection)?.apply(&light)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::{Channel, Material};

    fn deg(d: f64) -> Incidence {
        Incidence::from_degrees(d).unwrap()
    }

    #[test]
    fn psi_is_b_over_a_of_the_fresnel_terms() {
        for m in Material::ALL {
            for ch in Channel::ALL {
                let ior = m.ior(ch);
                for d in [0.0, 1e-6, 10.0, 45.0, 60.0, 80.0, 89.0, 89.999_999] {
                    let f = FresnelCoefficients::new(deg(d).cos(), &ior).unwrap();
                    let (rs, rp) = (f.reflectance_s(), f.reflectance_p());
                    let want = (rs - rp) / (rs + rp);
                    let got = psi(&ior, deg(d));
                    assert!((got - want).abs() < 4e-15, "{m:?} {ch:?} {d}: {got} {want}");
                }
            }
        }
    }

    #[test]
    fn brewster_angle_and_total_internal_reflection() {
        for n in [1.1, 1.333, 1.5, 2.42] {
            let ior = ComplexIor::dielectric(n).unwrap();
            let tb = Incidence::from_angle(f64::atan(n)).unwrap();
            assert!((psi(&ior, tb) - 1.0).abs() < 1e-15);
            // Inside the medium beyond the critical angle: R_s = R_p = 1, psi = 0.
            let inside = ComplexIor::dielectric(1.0 / n).unwrap();
            let beyond = Incidence::from_angle((1.0 / n).asin() + 0.01).unwrap();
            assert_eq!(psi(&inside, beyond), 0.0);
        }
    }

    #[test]
    fn dielectric_from_r0_is_exact() {
        for n in [1.0, 1.2, 1.5, 2.4, 4.0] {
            let ior = ComplexIor::dielectric(n).unwrap();
            let r0 = ior.normal_reflectance();
            assert!((ior_from_r0(r0).unwrap().n() - n).abs() < 1e-14 * n);
            for d in [0.0, 20.0, 56.3, 70.0, 89.9] {
                let a = psi_dielectric(r0, deg(d)).unwrap();
                assert!((a - psi(&ior, deg(d))).abs() < 1e-14, "{n} {d}");
                let o = omega(r0, deg(d), 0.3, 0.0).unwrap();
                assert!((o - omega_ior(&ior, deg(d), 0.3).unwrap()).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn listing_values_and_schlick() {
        // Listing 2 at R_0 = 0.5, theta = 60 degrees, by hand: beta~ = 0.1/0.595^3 + 2.35,
        // gamma~ = 0.16*0.25/0.68^2 + 0.35*0.68.
        let (b, g) = (0.1 / 0.595f64.powi(3) + 2.35, 0.04 / 0.4624 + 0.238);
        let t = deg(60.0);
        let want = 0.5 * 0.75 / (b * 0.25 + g * 0.5625);
        let got = psi_conductor_approx(0.5, t).unwrap();
        assert!((got - want).abs() < 1e-15, "{got} {want}");
        assert!((schlick(0.04, deg(0.0)).unwrap() - 0.04).abs() < 1e-17);
        assert!((schlick(0.04, deg(60.0)).unwrap() - (0.04 + 0.96 / 32.0)).abs() < 1e-16);
        // The metalness switch is a step at 0.5.
        let d = psi_approx(0.5, t, 0.5).unwrap();
        assert_eq!(d, psi_dielectric(0.5, t).unwrap());
        assert_eq!(psi_approx(0.5, t, 0.51).unwrap(), got);
    }

    #[test]
    fn incidence_round_trips() {
        for d in [0.0, 1e-9, 30.0, 60.0, 89.999] {
            let t = deg(d);
            assert!((t.angle().to_degrees() - d).abs() < 1e-12, "{d}");
            let c = Incidence::from_cos(t.cos()).unwrap();
            assert!((c.sin2() - t.sin2()).abs() < 1e-15);
        }
        // Just below 90 degrees in either unit stays valid.
        assert!(Incidence::from_degrees(f64::from_bits(90f64.to_bits() - 1)).is_ok());
    }

    #[test]
    fn conductor_approximation_is_below_one() {
        // psi~_C <= 1/(2 sqrt(beta~ gamma~)) (proofs/polarizing-filter.md §3), and
        // beta~ gamma~ >= 0.435 on [0, 1) (minimum near R_0 = 0.063).
        let mut least = f64::INFINITY;
        for i in 0..100_000 {
            let r0 = i as f64 * 1e-5;
            least = least.min(beta_approx(r0).unwrap() * gamma_approx(r0).unwrap());
        }
        assert!((0.435..0.436).contains(&least), "{least}");
        let bound = 0.5 / least.sqrt();
        for i in 0..=900 {
            let t = deg(0.1 * i as f64 - if i == 900 { 1e-9 } else { 0.0 });
            for r0 in [0.0, 0.063, 0.5, 0.95] {
                assert!(psi_conductor_approx(r0, t).unwrap() <= bound);
            }
        }
    }

    #[test]
    fn grazing_and_normal_incidence_are_finite() {
        let gold = Material::Gold.ior(Channel::Blue);
        for t in [
            Incidence::from_angle(below_right_angle()).unwrap(),
            Incidence::from_cos(1e-300).unwrap(),
            Incidence::from_cos(f64::MIN_POSITIVE / 8.0).unwrap(),
            deg(0.0),
        ] {
            for r0 in [0.0, 0.04, 0.5, 0.999_999] {
                for m in [0.0, 1.0] {
                    let o = omega(r0, t, 0.2, m).unwrap();
                    assert!((0.0..=2.0).contains(&o), "{r0} {m} {o}");
                }
            }
            let o = omega_ior(&gold, t, 1.0).unwrap();
            assert!((0.0..=2.0).contains(&o));
        }
    }

    #[test]
    fn bad_input_names_the_value() {
        for (r, what) in [
            (Incidence::from_degrees(90.0), "90"),
            (Incidence::from_degrees(-1.0), "-1"),
            (Incidence::from_angle(f64::NAN), "NaN"),
            (Incidence::from_cos(0.0), "0"),
            (Incidence::from_cos(1.5), "1.5"),
        ] {
            let e = r.unwrap_err().to_string();
            assert!(e.contains(what) && e.contains("incidence"), "{e}");
        }
        let t = deg(30.0);
        for r0 in [1.0, -0.1, f64::NAN, f64::INFINITY] {
            let e = omega(r0, t, 0.0, 1.0).unwrap_err().to_string();
            assert!(e.contains("R_0") && e.contains(&format!("{r0}")), "{e}");
            assert!(ior_from_r0(r0).is_err() && schlick(r0, t).is_err());
        }
        let e = omega(0.5, t, 0.0, f64::NAN).unwrap_err().to_string();
        assert!(e.contains("metalness"), "{e}");
        let e = omega(0.5, t, f64::NAN, 0.0).unwrap_err().to_string();
        assert!(e.contains("varphi"), "{e}");
        let z = [0.0, 0.0, 1.0];
        assert!(filter_angle(z, z, z, 0.0).is_err());
        let gold = Material::Gold.ior(Channel::Red);
        let e = mueller_filtered_reflection(&gold, [0.0, 0.0, -1.0], z, [1.0, 0.0, 0.0], 0.0, 1.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("opposite"), "{e}");
        let e = mueller_filtered_reflection(&gold, [f64::NAN, 0.0, 0.0], z, z, 0.0, 1.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("NaN"), "{e}");
        // Nearly opposite directions (a facet at 89.99999 degrees) are fine and finite.
        let (s, c) = (1e-7f64).sin_cos();
        let out = mueller_filtered_reflection(&gold, [s, 0.0, -c], z, [1.0, 0.0, 0.0], 0.3, 1.0);
        assert!(out.unwrap().s0().is_finite());
        assert!(filter_angle([1.0, 0.0, 0.0], z, [0.0, 0.0, 2.0], 0.0).is_err());
    }

    #[test]
    fn filter_angle_of_a_simple_configuration() {
        // Viewer along +z, facet tilted towards +x: the plane of incidence is x-z, the s
        // axis h x v is along -y... x' = (sin, 0, cos) x (0, 0, 1) = (0, -sin, 0).
        let (s, c) = 0.3f64.sin_cos();
        let (h, v) = ([s, 0.0, c], [0.0, 0.0, 1.0]);
        // camera right +x: from x' = -y to +x counterclockwise about +z is +90 degrees.
        let a = filter_angle([1.0, 0.0, 0.0], h, v, 0.25).unwrap();
        assert!((a - (0.25 + FRAC_PI_2)).abs() < 1e-15, "{a}");
        // Normal incidence: alpha = 0.
        assert_eq!(filter_angle([1.0, 0.0, 0.0], v, v, 0.25).unwrap(), 0.25);
    }

    #[test]
    fn mueller_reference_matches_omega_ior() {
        let ior = Material::Iron.ior(Channel::Green);
        let wo = [0.0, 0.0, 1.0];
        let (s, c) = 1.1f64.sin_cos();
        let wi = [s * 0.6, s * 0.8, c];
        let cam = [0.6, -0.8, 0.0];
        let h = (Vector3::from(wi) + Vector3::from(wo)).normalize();
        let t = Incidence::from_cos(h.dot(&Vector3::from(wo))).unwrap();
        let a = FresnelCoefficients::new(t.cos(), &ior)
            .unwrap()
            .reflectance();
        for om in [0.0, 0.4, 1.3, -2.0] {
            let out = mueller_filtered_reflection(&ior, wi, wo, cam, om, 1.0).unwrap();
            let varphi = filter_angle(cam, [h[0], h[1], h[2]], wo, om).unwrap();
            let want = omega_ior(&ior, t, varphi).unwrap();
            assert!((2.0 * out.s0() / a - want).abs() < 1e-14, "{om}");
        }
    }
}
