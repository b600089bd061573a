//! Filtering with ISD: pre-convolved signals (ISD (13), (14)), the filtered signal for
//! any rotation as a weighted sum of their values (ISD (6)), and spherical lights
//! (ISD (33), (34)).
//!
//! The filtered signal is `fhat(R) = int k(R^-1 w) f(w) dw` (ISD (1)). For a signal of
//! band limit `L` only the bands `l' <= L` of each mother function matter, so the
//! pre-convolution `fhat_l = f (x) phi_l` has the SH coefficients
//! `beta_ll' pi_l' f_l'm'` (Funk-Hecke; ISD (13) is the case `beta = I`,
//! `proofs/isd.md` §2), and ISD (6) equals the SH result `<R_F[k], f>` exactly.

use super::decomposition::Isd;
use super::pi_l;
use super::profiles::Profile;
use crate::error::{check_len, Error, Result};
use crate::geometry::check_direction;
use crate::lights::spherical::{cap_of, SphericalLight};
use crate::sh::evaluation::harmonics::ShEvaluator;
use crate::sh::num_coeffs;
use crate::sh::recursion::legendre::legendre_polynomials;
use crate::sh::rotation::wigner_d::RealWignerD;
use nalgebra::{DMatrix, Rotation3, Vector3};

/// A signal pre-convolved with the mother functions of an ISD basis.
#[derive(Clone, Debug)]
pub struct PreConvolved {
    profile: Profile,
    beta: DMatrix<f64>,
    /// `pi_l f_lm` (ISD (13)), flat order.
    scaled: Vec<f64>,
    ev: ShEvaluator,
}

impl PreConvolved {
    /// Pre-convolves the real SH coefficients `f` (flat order, `(L + 1)^2` for the basis'
    /// `L`). Errors: wrong length, a non-finite coefficient (named).
    pub fn new(isd: &Isd, f: &[f64]) -> Result<Self> {
        let lmax = isd.lmax();
        check_len("signal SH coefficients", num_coeffs(lmax), f.len())?;
        if let Some((i, v)) = f.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(Error::invalid(
                "signal SH coefficient",
                format!("f[{i}] = {v}"),
                "signal coefficients must be finite",
            ));
        }
        Ok(Self {
            profile: isd.profile(),
            beta: isd.beta().clone(),
            scaled: (0..f.len())
                .map(|i| pi_l(crate::sh::lm_of_index(i).0) * f[i])
                .collect(),
            ev: ShEvaluator::new(lmax)?,
        })
    }

    /// The pre-convolved signals at the unit direction `w`, `fhat_l(w)` for `l <= L`:
    /// `sum_l' beta_ll' pi_l' sum_m' f_l'm' y_l'^m'(w)` (ISD (14); `proofs/isd.md` §2).
    pub fn lookup(&self, w: [f64; 3]) -> Result<Vec<f64>> {
        let w = check_direction(w)?;
        let mut y = vec![0.0; self.ev.len()];
        self.ev.real_batch(&[w], &mut y)?;
        let lmax = self.ev.lmax();
        let band: Vec<f64> = (0..=lmax)
            .map(|l| {
                (l * l..(l + 1) * (l + 1))
                    .map(|i| self.scaled[i] * y[i])
                    .sum()
            })
            .collect();
        Ok((0..=lmax)
            .map(|l| (0..=lmax).map(|lp| self.beta[(l, lp)] * band[lp]).sum())
            .collect())
    }

    /// Checks that `isd` is the basis this signal was pre-convolved for.
    fn check_basis(&self, isd: &Isd) -> Result<()> {
        if isd.profile() != self.profile || isd.lmax() != self.ev.lmax() {
            return Err(Error::invalid(
                "ISD basis",
                format!("{} at L = {}", isd.profile().name(), isd.lmax()),
                format!(
                    "the signal was pre-convolved for {} at L = {}",
                    self.profile.name(),
                    self.ev.lmax()
                ),
            ));
        }
        Ok(())
    }

    /// The filtered signal `fhat(R)` (ISD (1)) for each rotation, by ISD (6):
    /// `sum_lm lambda_l^m fhat_l(R z_l^m)`, with the weights `lambda` of a kernel in the
    /// basis `isd` ([`Isd::weights`]). The SH of all distinct `R z_l^m` are evaluated once
    /// per rotation (`2L + 1` directions when shared, `(L + 1)^2` per band).
    pub fn filter(
        &self,
        isd: &Isd,
        lambda: &[f64],
        rotations: &[Rotation3<f64>],
    ) -> Result<Vec<f64>> {
        self.check_basis(isd)?;
        let lmax = isd.lmax();
        let n = num_coeffs(lmax);
        let folded = isd.fold(lambda)?;
        let dirs = isd.directions().distinct();
        // W[k][l'm'] = w_kl' pi_l' f_l'm': the weight of y_l'^m'(R z_k).
        let weights: Vec<f64> = (0..dirs.len() * n)
            .map(|t| {
                let (k, i) = (t / n, t % n);
                folded[k * (lmax + 1) + crate::sh::lm_of_index(i).0] * self.scaled[i]
            })
            .collect();
        let mut rotated = vec![[0.0; 3]; dirs.len()];
        let mut y = vec![0.0; dirs.len() * n];
        let mut out = Vec::with_capacity(rotations.len());
        for r in rotations {
            for (d, z) in rotated.iter_mut().zip(dirs) {
                *d = (r * Vector3::from(*z)).into();
            }
            self.ev.real_batch(&rotated, &mut y)?;
            out.push(weights.iter().zip(&y).map(|(a, b)| a * b).sum());
        }
        Ok(out)
    }
}

/// The light of a sphere seen from `x` filtered by the kernel of weights `lambda` turned
/// by each rotation (ISD (33), (34)): the light is zonal about its axis `zeta`,
/// `E(w) = sum_l e_l y_l^0(R_zeta^-1 w)`, so its pre-convolved signals are
/// `fhat_l(n) = sum_l' beta_ll' e_l' P_l'(zeta . n)` and each value costs `O(L)`
/// (`proofs/isd.md` §3). Errors: `x` not finite or not outside the light, bad weights.
pub fn spherical_light(
    isd: &Isd,
    lambda: &[f64],
    light: &SphericalLight,
    x: [f64; 3],
    rotations: &[Rotation3<f64>],
) -> Result<Vec<f64>> {
    let lmax = isd.lmax();
    let mut e = vec![0.0; lmax + 1];
    let zeta = Vector3::from(cap_of(light, x, &mut e)?);
    let mut folded = isd.fold(lambda)?;
    for row in folded.chunks_exact_mut(lmax + 1) {
        for (w, el) in row.iter_mut().zip(&e) {
            *w *= el;
        }
    }
    let dirs = isd.directions().distinct();
    let mut p = vec![0.0; lmax + 1];
    Ok(rotations
        .iter()
        .map(|r| {
            // zeta . (R z) = (R^T zeta) . z
            let zr = r.inverse() * zeta;
            dirs.iter()
                .zip(folded.chunks_exact(lmax + 1))
                .map(|(z, row)| {
                    let t = (zr[0] * z[0] + zr[1] * z[1] + zr[2] * z[2]).clamp(-1.0, 1.0);
                    legendre_polynomials(t, &mut p, None);
                    row.iter().zip(&p).map(|(a, b)| a * b).sum::<f64>()
                })
                .sum()
        })
        .collect())
}

/// The reference ISD replaces: `<R_F[k], f>` for each rotation by rotating the kernel's
/// real SH coefficients `c` with the real Wigner D (PSH (8), (13); `O(L^3)` per
/// rotation) and taking the dot product with the signal's `f` (Parseval).
pub fn sh_rotate_dot(c: &[f64], f: &[f64], rotations: &[Rotation3<f64>]) -> Result<Vec<f64>> {
    check_len("signal SH coefficients", c.len(), f.len())?;
    let lmax = crate::sh::lm_of_index(c.len().saturating_sub(1)).0;
    check_len("kernel SH coefficients", num_coeffs(lmax), c.len())?;
    rotations
        .iter()
        .map(|r| {
            let rc = RealWignerD::new(r, lmax)?.rotate(c)?;
            Ok(rc.iter().zip(f).map(|(a, b)| a * b).sum())
        })
        .collect()
}
