//! Zonal harmonics: coefficients of axisymmetric kernels, the Funk-Hecke convolution
//! theorem PSH (11), and rotated zonal functions by the addition theorem.
//!
//! A kernel `k: [0, pi] -> R` is the axisymmetric function `k(theta)` about +z. Its ZH
//! coefficients are `k_l = <Y_l0, k> = 2 pi int_0^pi k(theta) Pbar_l0(theta) sin(theta) dtheta`
//! (PSH (3) with the `phi` integral done). Spherical convolution PSH (10) then acts on
//! coefficients as `(k * f)_lm = sqrt(4 pi / (2l + 1)) k_l f_lm` (PSH (11)), and the
//! kernel turned to an axis `n`, `k(angle(n, w))`, has coefficients
//! `sqrt(4 pi / (2l + 1)) k_l conj(Y_lm(n))` (complex) or `... k_l Y^R_lm(n)` (real), by
//! the addition theorem `P_l(n . w) = 4 pi / (2l + 1) sum_m Y_lm(w) conj(Y_lm(n))`
//! (DLMF 14.30.9). Derivations in `proofs/zonal.md`.

use crate::error::{check_len, Error, Result};
use crate::geometry::{check_direction, direction_angles};
use crate::sh::evaluation::harmonics::{sh_complex, sh_real};
use crate::sh::index::{check_lmax, num_coeffs};
use crate::sh::recursion::legendre::zonal_legendre;
use num_complex::Complex64;
use std::f64::consts::PI;

/// ZH coefficients `k_l`, `l <= lmax`, of a kernel, with the quadrature's error estimate.
#[derive(Clone, Debug, PartialEq)]
pub struct ZonalCoefficients {
    /// `k_l = <Y_l0, k>`.
    pub coeffs: Vec<f64>,
    /// Sum over `l` of the absolute error estimates of the 1D quadratures.
    pub error_estimate: f64,
}

impl ZonalCoefficients {
    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.coeffs.len().saturating_sub(1)
    }

    /// The Funk-Hecke factors `sqrt(4 pi / (2l+1)) k_l` of PSH (11).
    pub fn funk_hecke_factors(&self) -> Vec<f64> {
        self.coeffs
            .iter()
            .enumerate()
            .map(|(l, k)| (4.0 * PI / (2 * l + 1) as f64).sqrt() * k)
            .collect()
    }
}

/// ZH coefficients of `kernel` for `l <= lmax` by adaptive Clenshaw-Curtis quadrature
/// (`quadrature` crate) over `1 + l/8` panels of `[0, pi]` (a few oscillations of `P_l`
/// each). `kernel` must be finite on `[0, pi]` (checked at the
/// quadrature nodes: a NaN or infinity is an error naming the angle).
pub fn zonal_coefficients(kernel: impl Fn(f64) -> f64, lmax: usize) -> Result<ZonalCoefficients> {
    check_lmax(lmax)?;
    let mut coeffs = vec![0.0; lmax + 1];
    let mut error_estimate = 0.0;
    let bad = std::cell::Cell::new(None);
    for l in 0..=lmax {
        let mut total = 0.0;
        let panels = 1 + l / 8;
        for p in 0..panels {
            let (a, b) = (
                PI * p as f64 / panels as f64,
                PI * (p + 1) as f64 / panels as f64,
            );
            let out = quadrature::clenshaw_curtis::integrate(
                |t| {
                    let k = kernel(t);
                    if !k.is_finite() && bad.get().is_none() {
                        bad.set(Some(t));
                    }
                    2.0 * PI * k * zonal_legendre(l, t)[l] * t.sin()
                },
                a,
                b,
                1e-15,
            );
            total += out.integral;
            error_estimate += out.error_estimate;
        }
        coeffs[l] = total;
    }
    if let Some(t) = bad.get() {
        return Err(Error::invalid(
            "kernel",
            format!("k({t}) non-finite"),
            "a zonal kernel must be finite on [0, pi]",
        ));
    }
    Ok(ZonalCoefficients {
        coeffs,
        error_estimate,
    })
}

/// Funk-Hecke convolution PSH (11) of coefficients `f` (real or complex, flat order) of
/// band limit `k.lmax()`: `f'_lm = sqrt(4 pi / (2l+1)) k_l f_lm`.
pub fn funk_hecke<T>(k: &ZonalCoefficients, f: &[T]) -> Result<Vec<T>>
where
    T: Copy + std::ops::Mul<f64, Output = T>,
{
    check_len("coefficients", num_coeffs(k.lmax()), f.len())?;
    Ok(scale_bands(&k.funk_hecke_factors(), f.iter().copied()))
}

/// `g_l x_lm` over the flat order.
fn scale_bands<T: std::ops::Mul<f64, Output = T>>(g: &[f64], x: impl Iterator<Item = T>) -> Vec<T> {
    x.enumerate()
        .map(|(i, v)| v * g[(i as f64).sqrt() as usize])
        .collect()
}

/// Real coefficients of the kernel turned to the unit axis `n`: `sqrt(4 pi/(2l+1)) k_l Y^R_lm(n)`.
pub fn rotated_zonal_real(k: &ZonalCoefficients, n: [f64; 3]) -> Result<Vec<f64>> {
    let (t, p) = direction_angles(check_direction(n)?)?;
    let y = sh_real(k.lmax(), t, p)?;
    Ok(scale_bands(&k.funk_hecke_factors(), y.into_iter()))
}

/// Complex coefficients of the kernel turned to the unit axis `n`:
/// `sqrt(4 pi/(2l+1)) k_l conj(Y_lm(n))`.
pub fn rotated_zonal_complex(k: &ZonalCoefficients, n: [f64; 3]) -> Result<Vec<Complex64>> {
    let (t, p) = direction_angles(check_direction(n)?)?;
    let y = sh_complex(k.lmax(), t, p)?;
    Ok(scale_bands(
        &k.funk_hecke_factors(),
        y.into_iter().map(|v| v.conj()),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A kernel that is a polynomial of degree 2 in cos(theta) has exactly three ZH
    /// coefficients, known in closed form: k = cos^2 = (1/3) + (2/3) P_2.
    #[test]
    fn polynomial_kernel_has_exact_coefficients() {
        let k = zonal_coefficients(|t: f64| t.cos().powi(2), 6).unwrap();
        let y0 = (1.0 / (4.0 * PI)).sqrt();
        let y2 = (5.0 / (4.0 * PI)).sqrt();
        // k_l = 4 pi / (2l+1) * c_l * sqrt((2l+1)/(4 pi)) for k = sum c_l P_l.
        let expect = [
            4.0 * PI / 3.0 * y0,
            0.0,
            4.0 * PI / 5.0 * (2.0 / 3.0) * y2,
            0.0,
            0.0,
            0.0,
            0.0,
        ];
        for (a, b) in k.coeffs.iter().zip(expect) {
            assert!((a - b).abs() < 1e-15, "{a} vs {b}");
        }
        let high = zonal_coefficients(|t: f64| t.cos().powi(2), 100).unwrap();
        let worst = high.coeffs[3..].iter().fold(0.0f64, |w, c| w.max(c.abs()));
        // Rounding floor: 1e-16 of the integrand scale 2 pi sqrt((2l+1)/(4 pi)) ~ 25.
        assert!(worst < 1e-14, "{worst}");
    }

    #[test]
    fn non_finite_kernels_are_errors() {
        assert!(zonal_coefficients(|_| f64::NAN, 2).is_err());
    }
}
