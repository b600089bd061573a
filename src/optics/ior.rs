//! The relative complex index of refraction `eta = n + i k` of an interface.

use crate::error::{Error, Result};
use num_complex::Complex64;

/// The relative index of refraction `eta = n + i k = eta_t / eta_i` of an interface: the
/// medium the light would enter over the medium it comes from (Born & Wolf §1.5.2 for a
/// real `eta`, §14.2 for an absorbing medium).
///
/// `k >= 0` is the extinction coefficient in the physics time convention `e^{-i omega t}`
/// (fields `e^{i (k.r - omega t)}`), the convention of Born & Wolf, of refractiveindex.info
/// and of the PF paper's Table 1. A dielectric seen from inside (light inside glass of
/// index `n`, outside air) has `eta = 1/n < 1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ComplexIor {
    n: f64,
    k: f64,
}

/// Largest `n` and `k` accepted: far above every optical material (`n` below 5 and `k`
/// below 15 across PF Table 1 and the metals of refractiveindex.info in the visible) and
/// above the indices PF's filter derives from reflectances up to `1 - 1e-11`
/// (`n = (1 + sqrt r) / (1 - sqrt r)`), low enough that the Fresnel coefficients'
/// intermediate powers stay finite (checked at the bound in `fresnel`'s tests).
pub const MAX_IOR: f64 = 1e12;

impl ComplexIor {
    /// `eta = n + i k`. Errors ([`Error::InvalidArgument`] naming the value): `n` or `k`
    /// NaN or infinite, `n < 0`, `k < 0` (a gain medium), `n` or `k` above
    /// [`MAX_IOR`](crate::optics::MAX_IOR),
    /// or `n = k = 0`.
    pub fn new(n: f64, k: f64) -> Result<Self> {
        let bad = |name: &'static str, value: f64, reason: &str| {
            // Exponent form for huge values (1e300 has 301 digits in full).
            let text = if value.abs() >= 1e6 {
                format!("{value:e}")
            } else {
                format!("{value}")
            };
            Error::invalid(name, text, reason)
        };
        if !n.is_finite() || n < 0.0 {
            return Err(bad(
                "refractive index n",
                n,
                "must be finite and non-negative",
            ));
        }
        if !k.is_finite() || k < 0.0 {
            return Err(bad(
                "extinction coefficient k",
                k,
                "must be finite and non-negative (k < 0 is a gain medium)",
            ));
        }
        for (name, x) in [("refractive index n", n), ("extinction coefficient k", k)] {
            if x > MAX_IOR {
                return Err(bad(
                    name,
                    x,
                    &format!("must be at most {MAX_IOR:e} (no optical medium is near it)"),
                ));
            }
        }
        if n == 0.0 && k == 0.0 {
            return Err(bad("refractive index n", n, "n = k = 0 is not a medium"));
        }
        Ok(Self { n, k })
    }

    /// A dielectric, `eta = n` (`k = 0`). Errors as [`ComplexIor::new`], and `n = 0`.
    pub fn dielectric(n: f64) -> Result<Self> {
        Self::new(n, 0.0)
    }

    /// The real part `n`.
    pub fn n(&self) -> f64 {
        self.n
    }

    /// The extinction coefficient `k >= 0`.
    pub fn k(&self) -> f64 {
        self.k
    }

    /// `eta = n + i k`.
    pub fn eta(&self) -> Complex64 {
        Complex64::new(self.n, self.k)
    }

    /// Whether `k = 0`.
    pub fn is_dielectric(&self) -> bool {
        self.k == 0.0
    }

    /// The reflectance at normal incidence, `R_0 = ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2)`
    /// (PF (3); the `cos_i = 1` value of [`crate::optics::FresnelCoefficients`]).
    pub fn normal_reflectance(&self) -> f64 {
        let (n, k2) = (self.n, self.k * self.k);
        ((n - 1.0) * (n - 1.0) + k2) / ((n + 1.0) * (n + 1.0) + k2)
    }
}
