//! Spherical lights: SH coefficients of the light seen from a shading point (SHH (2)-(5)),
//! their spatial gradients (SHH (6)-(8)) and Hessians (SHH (15), (20) and the Hessian of
//! `a(x)`), accumulated over many lights.
//!
//! A light of center `y`, radius `r` and uniform radiance `E` seen from a shading point
//! `x` (`|y - x| > r`) covers the spherical cap of axis `w = (y - x)/|y - x|` and half
//! angle `a = asin(r / |y - x|)` (SHH (5)). Its real SH coefficients (PSH (12)) are
//! `L_lm(x) = E int_cap Y_lm = E Lambda_l Y_lm(w) Ltilde_l` (SHH (2)), with
//! `Lambda_l = sqrt(4 pi/(2l+1))` and the zonal coefficient
//! `Ltilde_l = sqrt(pi/(2l+1)) (P_{l-1}(alpha) - P_{l+1}(alpha))`, `alpha = cos a`
//! (SHH (3), (4)). To avoid the cancellation of that difference for small lights
//! (`alpha -> 1`) it is evaluated as
//! `Ltilde_l = sqrt(pi/(2l+1)) (2l+1)/(l(l+1)) sin^2(a) P_l'(alpha)` for `l >= 1` and
//! `Ltilde_0 = sqrt(pi) sin^2(a)/(1 + alpha)` (`proofs/spherical-lights.md`).
//!
//! Gradients and Hessians are with respect to the shading point `x`. Written in
//! `d = y - x`, `L_lm = E Lambda_l Y_lm(d) Ltilde_l(|d|)` with `Y_lm(d) = Y_lm(d/|d|)`
//! differentiated by [`crate::sh::evaluation::solid`]; `grad_x = -grad_d` (the minus sign of
//! SHH (6)) and `H_x = H_d`.

use super::source::{LightField, Order};
use crate::error::{finite, Error, Result};
use crate::sh::evaluation::solid::{SolidHarmonics, HESSIAN_ENTRIES};
use crate::sh::num_coeffs;
use crate::sh::recursion::legendre::legendre_polynomials;
use std::f64::consts::PI;

/// A sphere of uniform radiance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphericalLight {
    center: [f64; 3],
    radius: f64,
    radiance: f64,
}

impl SphericalLight {
    /// A light of finite `center`, finite `radius > 0` and finite `radiance`.
    pub fn new(center: [f64; 3], radius: f64, radiance: f64) -> Result<Self> {
        for &c in &center {
            finite("light center", c)?;
        }
        finite("light radius", radius)?;
        finite("light radiance", radiance)?;
        if radius <= 0.0 {
            return Err(Error::invalid(
                "light radius",
                radius.to_string(),
                "a spherical light needs a positive radius",
            ));
        }
        Ok(Self {
            center,
            radius,
            radiance,
        })
    }

    /// The center `y`.
    pub fn center(&self) -> [f64; 3] {
        self.center
    }

    /// The radius `r`.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The radiance `E`.
    pub fn radiance(&self) -> f64 {
        self.radiance
    }

    /// The cap seen from `x`: `(d = y - x, |d|)`, or an error when `x` is not finite or
    /// not outside the light (`|d| <= r`).
    fn offset(&self, x: [f64; 3]) -> Result<([f64; 3], f64)> {
        for &c in &x {
            finite("shading point", c)?;
        }
        let d = [
            self.center[0] - x[0],
            self.center[1] - x[1],
            self.center[2] - x[2],
        ];
        let dist = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if dist <= self.radius {
            return Err(Error::invalid(
                "shading point",
                format!("{x:?}"),
                format!(
                    "inside the spherical light of center {:?} and radius {} (distance {dist})",
                    self.center, self.radius
                ),
            ));
        }
        Ok((d, dist))
    }
}

/// The half angle `a(x) = asin(r / |y - x|)` (SHH (5)) with its gradient (SHH (8), with
/// respect to `x`) and packed Hessian (SHH Sec. 4.4), for a light of radius `r` at
/// offset `d = y - x`, `|d| = dist > r`.
pub fn half_angle(d: [f64; 3], dist: f64, r: f64) -> (f64, [f64; 3], [f64; 6]) {
    let s = ((dist - r) * (dist + r)).sqrt();
    let w = d.map(|c| c / dist);
    // With respect to d: grad a = -r w / (dist s) (SHH (8)); with respect to x: opposite.
    let g1 = r / (dist * s);
    let a = (r / dist).asin();
    let grad = w.map(|c| g1 * c);
    // H a = r (w w^T / s^3 - (I - 2 w w^T) / (s dist^2)) (SHH Sec. 4.4), even in d.
    let (p, q) = (r / (s * s * s), r / (s * dist * dist));
    let hess = HESSIAN_ENTRIES.map(|(i, j)| {
        let ww = w[i] * w[j];
        p * ww - q * (if i == j { 1.0 } else { 0.0 } - 2.0 * ww)
    });
    (a, grad, hess)
}

/// SH coefficients (and optionally gradients and Hessians) of many spherical lights,
/// summed, for all `l <= lmax`.
#[derive(Clone, Debug)]
pub struct SphericalLights {
    lights: Vec<SphericalLight>,
    sh: SolidHarmonics,
}

/// Work space of one shading point: SH derivatives at the light direction and the
/// Legendre values `P_l(alpha)`, `P_l'(alpha)`.
struct Work {
    y: Vec<f64>,
    gy: Vec<[f64; 3]>,
    hy: Vec<[f64; 6]>,
    p: Vec<f64>,
    dp: Vec<f64>,
}

impl SphericalLights {
    /// The lights, with SH up to `lmax` (at most [`crate::sh::evaluation::solid::SOLID_MAX_DEGREE`]).
    pub fn new(lights: Vec<SphericalLight>, lmax: usize) -> Result<Self> {
        Ok(Self {
            lights,
            sh: SolidHarmonics::new(lmax)?,
        })
    }

    /// The lights.
    pub fn lights(&self) -> &[SphericalLight] {
        &self.lights
    }

    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.sh.lmax()
    }

    fn work(&self) -> Work {
        let n = self.sh.len();
        let l = self.lmax();
        Work {
            y: vec![0.0; n],
            gy: vec![[0.0; 3]; n],
            hy: vec![[0.0; 6]; n],
            p: vec![0.0; l + 1],
            dp: vec![0.0; l + 1],
        }
    }

    /// The summed light field at the shading point `x`; an error if `x` is not finite or
    /// lies inside (or on) a light.
    pub fn field(&self, x: [f64; 3], order: Order) -> Result<LightField> {
        let n = num_coeffs(self.lmax());
        let mut out = LightField {
            coefficients: vec![0.0; n],
            gradients: vec![[0.0; 3]; if order == Order::Values { 0 } else { n }],
            hessians: vec![[0.0; 6]; if order == Order::Hessians { n } else { 0 }],
        };
        let mut work = self.work();
        for light in &self.lights {
            self.accumulate(light, x, order, &mut work, &mut out)?;
        }
        Ok(out)
    }

    /// Adds one light's field at `x` to `out`.
    fn accumulate(
        &self,
        light: &SphericalLight,
        x: [f64; 3],
        order: Order,
        work: &mut Work,
        out: &mut LightField,
    ) -> Result<()> {
        let (d, dist) = light.offset(x)?;
        let w = d.map(|c| c / dist);
        self.sh.eval(w, &mut work.y, &mut work.gy, &mut work.hy)?;
        let r = light.radius;
        let (_, ga, ha) = half_angle(d, dist, r);
        let sin_a = r / dist;
        let sin2 = sin_a * sin_a;
        let alpha = ((dist - r) * (dist + r)).sqrt() / dist;
        legendre_polynomials(alpha, &mut work.p, Some(&mut work.dp));
        let e = light.radiance;
        let inv = 1.0 / dist;
        for l in 0..=self.lmax() {
            let lf = l as f64;
            let two_l1 = 2.0 * lf + 1.0;
            let zonal = cap_zonal(l, sin2, alpha, work.dp[l]);
            let lambda = (4.0 * PI / two_l1).sqrt();
            let z0 = e * lambda * zonal;
            // grad_d Ltilde_l = sqrt((2l+1) pi) sin(a) P_l(alpha) grad_d a (SHH (7)), and
            // H Ltilde_l (SHH (20)), both times E Lambda_l; grad_d a = -ga.
            let c = e * lambda * (two_l1 * PI).sqrt();
            let z1 = c * sin_a * work.p[l];
            let z2 = c * (alpha * work.p[l] - sin2 * work.dp[l]);
            let gz = ga.map(|g| -z1 * g);
            for k in l * l..(l + 1) * (l + 1) {
                let yv = work.y[k];
                out.coefficients[k] += z0 * yv;
                if order == Order::Values {
                    continue;
                }
                // grad_d Y(d) = grad Y(w) / |d|; SHH (6): grad_x L = -grad_d L.
                let gy = work.gy[k].map(|g| g * inv);
                for i in 0..3 {
                    out.gradients[k][i] -= z0 * gy[i] + yv * gz[i];
                }
                if order == Order::Hessians {
                    // SHH (15), H_x = H_d; H_d Y(d) = H Y(w) / |d|^2.
                    for (idx, &(i, j)) in HESSIAN_ENTRIES.iter().enumerate() {
                        let hz = z2 * ga[i] * ga[j] + z1 * ha[idx];
                        out.hessians[k][idx] += z0 * work.hy[k][idx] * inv * inv
                            + gy[i] * gz[j]
                            + gz[i] * gy[j]
                            + yv * hz;
                    }
                }
            }
        }
        Ok(())
    }
}

/// The zonal coefficient `Ltilde_l` of a unit cap (SHH (3), (4)) in the
/// cancellation-free form, from `sin^2 a`, `alpha = cos a` and `P_l'(alpha)`.
pub fn cap_zonal(l: usize, sin2: f64, alpha: f64, dp_l: f64) -> f64 {
    if l == 0 {
        PI.sqrt() * sin2 / (1.0 + alpha)
    } else {
        let lf = l as f64;
        let two_l1 = 2.0 * lf + 1.0;
        (PI / two_l1).sqrt() * two_l1 / (lf * (lf + 1.0)) * sin2 * dp_l
    }
}

/// The cap a light covers seen from `x`: its axis `w = (y - x)/|y - x|` and the zonal
/// coefficients `E Ltilde_l`, `l < zonal.len()` (SHH (2)-(5)); an error when `x` is not
/// finite or not outside the light.
pub fn cap_of(light: &SphericalLight, x: [f64; 3], zonal: &mut [f64]) -> Result<[f64; 3]> {
    let (d, dist) = light.offset(x)?;
    let r = light.radius;
    let sin2 = (r / dist) * (r / dist);
    let alpha = ((dist - r) * (dist + r)).sqrt() / dist;
    let n = zonal.len();
    let (mut p, mut dp) = (vec![0.0; n], vec![0.0; n]);
    legendre_polynomials(alpha, &mut p, Some(&mut dp));
    for (l, z) in zonal.iter_mut().enumerate() {
        *z = light.radiance * cap_zonal(l, sin2, alpha, dp[l]);
    }
    Ok(d.map(|c| c / dist))
}

impl super::source::LightSource for SphericalLights {
    fn lmax(&self) -> usize {
        SphericalLights::lmax(self)
    }

    fn field(&self, x: [f64; 3], order: Order) -> Result<LightField> {
        SphericalLights::field(self, x, order)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_input_is_an_error() {
        assert!(SphericalLight::new([0.0; 3], 0.0, 1.0).is_err());
        assert!(SphericalLight::new([0.0; 3], -1.0, 1.0).is_err());
        assert!(SphericalLight::new([f64::NAN, 0.0, 0.0], 1.0, 1.0).is_err());
        assert!(SphericalLight::new([0.0; 3], f64::INFINITY, 1.0).is_err());
        assert!(SphericalLight::new([0.0; 3], 1.0, f64::NAN).is_err());
        let light = SphericalLight::new([0.0, 0.0, 2.0], 1.0, 1.0).unwrap();
        let lights = SphericalLights::new(vec![light], 4).unwrap();
        // Inside, on the surface, NaN: errors; just outside: finite.
        assert!(lights.field([0.0, 0.0, 2.5], Order::Hessians).is_err());
        assert!(lights.field([0.0, 0.0, 1.0], Order::Hessians).is_err());
        assert!(lights.field([f64::NAN, 0.0, 0.0], Order::Values).is_err());
        let f = lights
            .field([0.0, 0.0, 1.0 - 1e-9], Order::Hessians)
            .unwrap();
        assert!(f.coefficients.iter().all(|x| x.is_finite()));
    }

    /// A light seen from far away: `L_00 = E sqrt(pi) (1 - cos a)` (the cap's solid angle
    /// times `Y_00`), accurate even when `1 - cos a` is far below the f64 epsilon.
    #[test]
    fn tiny_and_distant_lights_keep_relative_accuracy() {
        for (dist, r) in [(3.0, 1.0), (1e3, 1e-3), (1.0, 1e-9)] {
            let light = SphericalLight::new([dist, 0.0, 0.0], r, 2.0).unwrap();
            let f = SphericalLights::new(vec![light], 2)
                .unwrap()
                .field([0.0; 3], Order::Values)
                .unwrap();
            let s: f64 = r / dist;
            // 1 - cos a = s^2 / (1 + sqrt(1 - s^2)).
            let want = 2.0 * PI.sqrt() * s * s / (1.0 + (1.0 - s * s).sqrt());
            assert!((f.coefficients[0] / want - 1.0).abs() < 1e-14, "{dist} {r}");
        }
    }
}
