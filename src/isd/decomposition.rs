//! The ISD of a kernel: the transfer matrix `M` (ISD (10), (17)), its conditioning
//! (ISD Sec. 7.2) and the weights `Lambda = M^-1 c` (ISD (11)).

use super::directions::DirectionSet;
use super::pi_l;
use super::profiles::Profile;
use crate::error::{check_len, Error, Result};
use crate::geometry::check_direction;
use crate::sh::evaluation::harmonics::ShEvaluator;
use crate::sh::{lm_of_index, num_coeffs};
use nalgebra::{DMatrix, DVector, Dyn, LU};

/// Largest accepted 2-norm condition number of `M`: weights then carry at most about
/// `MAX_CONDITION * 1e-16 = 1e-8` relative error. Larger (or singular) sets are refused.
pub const MAX_CONDITION: f64 = 1e8;

/// `M` of ISD (17): `M_ij = beta_ll' pi_l' y_l'^m'(z_l^m)`, rows `i = (l', m')`, columns
/// `j = (l, m)` in flat order; with `beta = I` it is block diagonal with the `M_l` of
/// ISD (10).
pub fn transfer_matrix(beta: &DMatrix<f64>, dirs: &DirectionSet) -> Result<DMatrix<f64>> {
    let lmax = dirs.lmax();
    check_len("beta rows", lmax + 1, beta.nrows())?;
    let n = num_coeffs(lmax);
    let ev = ShEvaluator::accurate(lmax)?;
    let mut y = vec![0.0; dirs.distinct().len() * n];
    ev.real_batch(dirs.distinct(), &mut y)?;
    Ok(DMatrix::from_fn(n, n, |i, j| {
        let (lp, _) = lm_of_index(i);
        let (l, m) = lm_of_index(j);
        beta[(l, lp)] * pi_l(lp) * y[dirs.index(l, m) * n + i]
    }))
}

/// The 2-norm condition number `sigma_max / sigma_min` (infinite when singular).
pub fn condition_number(m: &DMatrix<f64>) -> f64 {
    let s = m.clone().singular_values();
    let (lo, hi) = (s.min(), s.max());
    if lo > 0.0 && hi.is_finite() {
        hi / lo
    } else {
        f64::INFINITY
    }
}

/// An ISD basis: mother functions, directions, `M` and its LU factors.
#[derive(Clone, Debug)]
pub struct Isd {
    profile: Profile,
    directions: DirectionSet,
    beta: DMatrix<f64>,
    m: DMatrix<f64>,
    lu: LU<f64, Dyn, Dyn>,
    condition: f64,
}

impl Isd {
    /// The basis of `profile` on `directions`. Errors: `M` singular or with condition
    /// number above [`MAX_CONDITION`] (the error names it), quadrature failures.
    pub fn new(profile: Profile, directions: DirectionSet) -> Result<Self> {
        let beta = profile.beta(directions.lmax())?;
        let m = transfer_matrix(&beta, &directions)?;
        let condition = condition_number(&m);
        if condition.is_nan() || condition > MAX_CONDITION {
            return Err(Error::invalid("ISD direction set", format!(
                    "{:?} {} directions at L = {} (condition number of M {condition:e})",
                    directions.sharing(),
                    profile.name(),
                    directions.lmax()
                ), format!(
                    "M is singular or too ill-conditioned (bound {MAX_CONDITION:e}); use per-band or better spread directions"
                )));
        }
        let lu = m.clone().lu();
        Ok(Self {
            profile,
            directions,
            beta,
            m,
            lu,
            condition,
        })
    }

    /// The band limit `L`.
    pub fn lmax(&self) -> usize {
        self.directions.lmax()
    }

    /// The mother functions.
    pub fn profile(&self) -> Profile {
        self.profile
    }

    /// The axes `z_l^m`.
    pub fn directions(&self) -> &DirectionSet {
        &self.directions
    }

    /// `beta_ll'` (ISD (16)).
    pub fn beta(&self) -> &DMatrix<f64> {
        &self.beta
    }

    /// `M` (ISD (17)).
    pub fn matrix(&self) -> &DMatrix<f64> {
        &self.m
    }

    /// The 2-norm condition number of `M`.
    pub fn condition(&self) -> f64 {
        self.condition
    }

    /// The weights `Lambda = M^-1 c` (ISD (11)) of a kernel with real SH coefficients `c`
    /// (flat order, `(L + 1)^2`). Errors: wrong length, a non-finite coefficient (named).
    pub fn weights(&self, c: &[f64]) -> Result<Vec<f64>> {
        check_len("kernel SH coefficients", num_coeffs(self.lmax()), c.len())?;
        if let Some((i, v)) = c.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(Error::invalid(
                "kernel SH coefficient",
                format!("c[{i}] = {v}"),
                "kernel coefficients must be finite",
            ));
        }
        let x = self
            .lu
            .solve(&DVector::from_column_slice(c))
            .ok_or_else(|| {
                Error::invalid(
                    "ISD direction set",
                    format!("condition number {:e}", self.condition),
                    "the LU factors of M are singular",
                )
            })?;
        Ok(x.iter().copied().collect())
    }

    /// The decomposed kernel at the unit direction `w`, in the angular domain (ISD (12)):
    /// `sum_lm lambda_l^m g_l(w . z_l^m)`, with `g_l(w . z_l^m) = phi_l((R_l^m)^-1 w)` the
    /// rotated mother function of ISD (8) (any rotation with `R_l^m z = z_l^m`).
    pub fn evaluate(&self, lambda: &[f64], w: [f64; 3]) -> Result<f64> {
        check_len("ISD weights", num_coeffs(self.lmax()), lambda.len())?;
        let w = check_direction(w)?;
        let mut g = vec![0.0; self.lmax() + 1];
        let mut sum = 0.0;
        for (k, z) in self.directions.distinct().iter().enumerate() {
            let t = (w[0] * z[0] + w[1] * z[1] + w[2] * z[2]).clamp(-1.0, 1.0);
            self.profile.values(t, &mut g);
            for (l, m) in self.directions.users(k) {
                sum += lambda[crate::sh::lm_index(l, m)] * g[l];
            }
        }
        Ok(sum)
    }

    /// The weights folded per distinct direction `k`: `w_kl' = sum over the (l, m) using
    /// `k` of lambda_l^m beta_ll'` (row-major, `L + 1` per direction), so that ISD (6)
    /// reads `sum_k sum_l' w_kl' (band l' of the pre-convolution at R z_k)`.
    pub(crate) fn fold(&self, lambda: &[f64]) -> Result<Vec<f64>> {
        let lmax = self.lmax();
        check_len("ISD weights", num_coeffs(lmax), lambda.len())?;
        let mut w = vec![0.0; self.directions.distinct().len() * (lmax + 1)];
        for (k, row) in w.chunks_exact_mut(lmax + 1).enumerate() {
            for (l, m) in self.directions.users(k) {
                let lam = lambda[crate::sh::lm_index(l, m)];
                for (lp, x) in row.iter_mut().enumerate() {
                    *x += lam * self.beta[(l, lp)];
                }
            }
        }
        Ok(w)
    }
}
