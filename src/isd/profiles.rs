//! Isotropic mother functions `phi_l(w) = g_l(w . z)` (ISD Sec. 5, 7.2) and their ZH
//! coefficients `beta_ll' = <phi_l, y_l'^0>` (ISD (16)).

use super::pi_l;
use crate::error::Result;
use crate::sh::evaluation::zonal::zonal_coefficients;
use crate::sh::recursion::legendre::legendre_polynomials;
use nalgebra::DMatrix;

/// The profile `g_l(t)`, `t = w . z`, of the band-`l` mother function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Profile {
    /// Rotated zonal harmonics: `phi_l = y_l^0` (ISD Sec. 5.1), `beta_ll' = delta_ll'`
    /// (ISD (18)); `M` is block diagonal with the blocks `M_l` of ISD (10).
    Zonal,
    /// `P_l(t)` (ISD Sec. 7.2, "Legendre"; RZH up to the factor `pi_l`).
    Legendre,
    /// `exp(-(1 - t) l^2)` (ISD (19)).
    Gaussian,
    /// `max(t, 0)^(4l)` (ISD Sec. 7.2; clamped to the upper hemisphere: the printed
    /// `t^(4l)` is even in `t`, so its `beta_ll'` vanish for odd `l'` and `M` is
    /// singular, `proofs/isd.md` §4). `g_0 = 1`.
    Phong,
    /// `P_l(t) exp(-(1 - t) l^2)` (ISD Sec. 7.2, "Gauss-Legendre").
    GaussLegendre,
}

crate::named_enum!(Profile, "profile", {
    Phong => "phong",
    Gaussian => "gaussian",
    Legendre => "legendre",
    GaussLegendre => "gauss-legendre",
    Zonal => "zonal",
});

impl Profile {
    /// `g_l(t)` for all `l <= lmax` into `out` (length `lmax + 1`), `t` in `[-1, 1]`.
    pub fn values(self, t: f64, out: &mut [f64]) {
        if matches!(
            self,
            Profile::Zonal | Profile::Legendre | Profile::GaussLegendre
        ) {
            legendre_polynomials(t, out, None);
        }
        for (l, g) in out.iter_mut().enumerate() {
            let l2 = (l * l) as f64;
            *g = match self {
                Profile::Zonal => *g / pi_l(l),
                Profile::Legendre => *g,
                Profile::Gaussian => (-(1.0 - t) * l2).exp(),
                Profile::Phong => t.max(0.0).powi(4 * l as i32),
                Profile::GaussLegendre => *g * (-(1.0 - t) * l2).exp(),
            };
        }
    }

    /// `beta_ll'` (ISD (16)), rows `l`, columns `l'`, `l, l' <= lmax`: the identity for
    /// [`Profile::Zonal`] (ISD (18)), otherwise by 1D quadrature of `g_l(cos theta)`
    /// ([`zonal_coefficients`]). Errors: `lmax` beyond [`super::MAX_LMAX`].
    pub fn beta(self, lmax: usize) -> Result<DMatrix<f64>> {
        super::check_isd_lmax(lmax)?;
        if self == Profile::Zonal {
            return Ok(DMatrix::identity(lmax + 1, lmax + 1));
        }
        let mut beta = DMatrix::zeros(lmax + 1, lmax + 1);
        for l in 0..=lmax {
            let k = zonal_coefficients(
                |theta: f64| {
                    let mut gl = vec![0.0; l + 1];
                    self.values(theta.cos(), &mut gl);
                    gl[l]
                },
                lmax,
            )?;
            for (lp, b) in k.coeffs.iter().enumerate() {
                beta[(l, lp)] = *b;
            }
        }
        Ok(beta)
    }
}
