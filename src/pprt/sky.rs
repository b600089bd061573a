//! A built-in analytic polarized sky: single-scattering Rayleigh skylight plus a sun.
//!
//! Light reaching the observer from the sky direction `w` was scattered once by an angle
//! `g` with `cos g = w . s` (`s` towards the sun). Rayleigh scattering of unpolarized
//! sunlight gives radiance proportional to `1 + cos^2 g` with degree of linear polarization
//! `sin^2 g / (1 + cos^2 g)`, polarized perpendicular to the scattering plane: the electric
//! field along `e = normalize(w x s)` (Chandrasekhar, Radiative Transfer, §17). The sun is a
//! smooth unpolarized lobe `exp(k (w . s - 1))`; below the horizon an unpolarized ground
//! radiance takes over smoothly (`tanh` blend over about 6 degrees), so that the
//! band-limited projection does not ring at a step.
//!
//! The sun lobe is about 7 degrees wide and rings at the band limits PPRT uses; with
//! [`Sun::Directional`] it is taken out of the sky and carried by a
//! [`DirectionalLight`] of the same power, reflected exactly at every shading point
//! (`src/pprt/direct.rs`).

use super::light::DirectionalLight;
use crate::error::{Error, Result};
use crate::geometry::frame::{FrameField, ThetaPhiFrameField};
use crate::polarized::{Codomain, PshTransform, PshVector};
use nalgebra::{Rotation3, Vector3};
use std::f64::consts::PI;

/// How the sky carries its sun.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Sun {
    /// A smooth lobe `peak exp(k (w . s - 1))` in the sky's radiance.
    #[default]
    Lobe,
    /// A directional light of the lobe's power ([`RayleighSky::directional_light`]); the
    /// sky's radiance has no lobe.
    Directional,
}

crate::named_enum!(Sun, "sun", { Lobe => "lobe", Directional => "directional" });

/// The sky (module docs), RGB.
#[derive(Clone, Debug, PartialEq)]
pub struct RayleighSky {
    sun: Vector3<f64>,
    /// Sky radiance scale per channel (bluish).
    sky: [f64; 3],
    /// Sun lobe peak radiance and sharpness `k`.
    sun_peak: f64,
    sun_sharpness: f64,
    ground: [f64; 3],
    sun_model: Sun,
    /// `false`: the intensity alone (`s1 = s2 = 0`), as renderers with unpolarized
    /// environments (Mitsuba 3) see it.
    polarized: bool,
}

impl RayleighSky {
    /// A sky with the sun at elevation `elevation` and azimuth `azimuth` (radians, from
    /// `+x` towards `+y`). Error: non-finite angles or an elevation outside
    /// `[-pi/2, pi/2]`.
    pub fn new(elevation: f64, azimuth: f64) -> Result<Self> {
        if !(elevation.is_finite() && azimuth.is_finite())
            || elevation.abs() > std::f64::consts::FRAC_PI_2
        {
            return Err(Error::invalid(
                "sun direction",
                format!("elevation {elevation}, azimuth {azimuth}"),
                "finite angles, elevation in [-pi/2, pi/2]",
            ));
        }
        let (ce, se) = (elevation.cos(), elevation.sin());
        Ok(Self {
            sun: Vector3::new(ce * azimuth.cos(), ce * azimuth.sin(), se),
            sky: [0.35, 0.55, 0.9],
            sun_peak: 20.0,
            sun_sharpness: 60.0,
            ground: [0.12, 0.11, 0.1],
            sun_model: Sun::Lobe,
            polarized: true,
        })
    }

    /// The sky turned by `angle` (radians) about the world's vertical `+z`: the sun's
    /// azimuth plus `angle`, its elevation kept (the sky's field depends on the sun's
    /// direction and the vertical only, so this is the sky rotated, PSH (8)). Error: a
    /// non-finite angle.
    pub fn turned(mut self, angle: f64) -> Result<Self> {
        self.sun = vertical_turn(angle)? * self.sun;
        Ok(self)
    }

    /// The same sky without its polarization: the intensity `s0` alone, the sun as it was.
    pub fn unpolarized(mut self) -> Self {
        self.polarized = false;
        self
    }

    /// Whether the sky's light is polarized ([`Self::unpolarized`]).
    pub fn is_polarized(&self) -> bool {
        self.polarized
    }

    /// The same sky with its sun carried as `sun` says.
    pub fn with_sun(mut self, sun: Sun) -> Self {
        self.sun_model = sun;
        self
    }

    /// How the sky carries its sun.
    pub fn sun(&self) -> Sun {
        self.sun_model
    }

    /// With [`Sun::Directional`], the sun as a directional light: unpolarized, towards the
    /// sun, of the lobe's irradiance `E = peak int exp(k (cos g - 1)) dw = 2 pi peak
    /// (1 - exp(-2k)) / k` times the horizon blend at the sun (the blend varies over the
    /// lobe: the lobe's power in the sky differs by 2e-4 at 34 degrees of elevation, 1e-6
    /// at 69); `None` with [`Sun::Lobe`].
    pub fn directional_light(&self) -> Option<DirectionalLight> {
        (self.sun_model == Sun::Directional).then(|| {
            let k = self.sun_sharpness;
            let up = 0.5 * (1.0 + (self.sun.z / 0.1).tanh());
            let e = up * 2.0 * PI * self.sun_peak * (1.0 - (-2.0 * k).exp()) / k;
            DirectionalLight::new(self.sun.into(), [e; 3])
                .expect("a unit direction and a finite irradiance")
        })
    }

    /// The Stokes components of channel `c` arriving from the unit direction `w`, in the
    /// theta-phi frame at `w` (psh's convention: `w` towards the source).
    pub fn stokes(&self, c: usize, w: [f64; 3]) -> Result<[f64; 4]> {
        let frame = ThetaPhiFrameField::new().frame(w)?;
        let wv = Vector3::from(w);
        let cos_g = wv.dot(&self.sun).clamp(-1.0, 1.0);
        let sin2 = 1.0 - cos_g * cos_g;
        let intensity = self.sky[c] * 0.75 * (1.0 + cos_g * cos_g);
        let dop = sin2 / (1.0 + cos_g * cos_g);
        // The field direction e = w x s; its angle chi from the frame's x.
        let e = wv.cross(&self.sun);
        let chi = e.dot(&frame.y()).atan2(e.dot(&frame.x()));
        let (s1, s2) = if self.polarized && e.norm() > 1e-12 {
            (
                intensity * dop * (2.0 * chi).cos(),
                intensity * dop * (2.0 * chi).sin(),
            )
        } else {
            (0.0, 0.0)
        };
        let sun = match self.sun_model {
            Sun::Lobe => self.sun_peak * (self.sun_sharpness * (cos_g - 1.0)).exp(),
            Sun::Directional => 0.0,
        };
        let up = 0.5 * (1.0 + (w[2] / 0.1).tanh());
        Ok([
            up * (intensity + sun) + (1.0 - up) * self.ground[c],
            up * s1,
            up * s2,
            0.0,
        ])
    }

    /// PSH coefficients (RGB, `s0..s3`) of band limit `lmax`, projected on the exact grid.
    pub fn project(&self, lmax: usize) -> Result<PshVector> {
        let t = PshTransform::new(lmax.max(2))?;
        let g = t.grid();
        let dirs = (0..g.len())
            .map(|i| g.direction(i))
            .collect::<Result<Vec<_>>>()?;
        let channels = (0..3)
            .map(|c| {
                dirs.iter()
                    .map(|&w| self.stokes(c, w))
                    .collect::<Result<Vec<_>>>()
            })
            .collect::<Result<Vec<_>>>()?;
        let refs: Vec<&[[f64; 4]]> = channels.iter().map(Vec::as_slice).collect();
        t.project_channels(&refs, Codomain::Full)?.truncated(lmax)
    }
}

/// The rotation by `angle` (radians) about the world's vertical `+z`. Error: a non-finite
/// angle.
pub(crate) fn vertical_turn(angle: f64) -> Result<Rotation3<f64>> {
    if !angle.is_finite() {
        return Err(Error::invalid(
            "environment turn",
            format!("{angle} radians"),
            "a finite angle",
        ));
    }
    Ok(Rotation3::from_axis_angle(&Vector3::z_axis(), angle))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 90 degrees from the sun the skylight is fully polarized, perpendicular to the
    /// scattering plane; towards the sun it is unpolarized.
    #[test]
    fn rayleigh_polarization() {
        let sky = RayleighSky::new(0.0, 0.0).unwrap(); // sun along +x on the horizon
        let s = sky.stokes(2, [0.0, 0.0, 1.0 - 1e-16]).unwrap();
        let lin = s[1].hypot(s[2]);
        assert!((lin / (s[0] - sky.sun_peak * (-sky.sun_sharpness).exp()) - 1.0).abs() < 1e-9);
        // At the zenith the theta-phi frame has x = +x: the field along w x s = +y,
        // angle 90 degrees, so s1 < 0, s2 = 0.
        assert!(s[1] < 0.0 && s[2].abs() < 1e-9 * lin, "{s:?}");
        let toward = sky.stokes(0, [1.0, 0.0, 0.0]).unwrap();
        assert_eq!((toward[1], toward[2]), (0.0, 0.0));
        assert!(RayleighSky::new(2.0, 0.0).is_err());
    }

    /// The directional sun carries the lobe's power: `E` against the lobe integrated on
    /// a fine polar grid about the sun (midpoint rule), and the sky without its lobe is
    /// the sky minus the lobe.
    #[test]
    fn directional_sun_has_the_lobes_power() {
        // High enough that the horizon blend is 1 within 2e-6 over the lobe.
        let lobe = RayleighSky::new(1.2, 1.0).unwrap();
        let directional = lobe.clone().with_sun(Sun::Directional);
        assert!(lobe.directional_light().is_none());
        let light = directional.directional_light().unwrap();
        assert_eq!(light.direction(), <[f64; 3]>::from(lobe.sun));
        let (n_t, n_p) = (4000, 64);
        let frame = crate::geometry::frame::Frame::from_z(lobe.sun.into()).unwrap();
        let mut power = 0.0;
        for i in 0..n_t {
            let t = (i as f64 + 0.5) * 1.0 / n_t as f64;
            for j in 0..n_p {
                let p = 2.0 * PI * (j as f64 + 0.5) / n_p as f64;
                let (st, ct) = t.sin_cos();
                let w = frame.x() * st * p.cos() + frame.y() * st * p.sin() + frame.z() * ct;
                let w = [w.x, w.y, w.z];
                let d = lobe.stokes(1, w).unwrap()[0] - directional.stokes(1, w).unwrap()[0];
                power += d * st * (1.0 / n_t as f64) * (2.0 * PI / n_p as f64);
            }
        }
        let e = light.irradiance()[1];
        assert!((power / e - 1.0).abs() < 1e-5, "{power} vs {e}");
        assert_eq!(Sun::from_name("directional").unwrap(), Sun::Directional);
        assert!(Sun::from_name("disk").is_err());
    }
}
