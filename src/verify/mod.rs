//! `psh verify`: the checks a user can run on their own machine.
//!
//! Each check computes a maximum error against an independent reference (an exact
//! identity, a high-precision oracle, or the angular-domain equivalent on an exact
//! quadrature grid) and compares it with a stated tolerance. The JSON form is the
//! contract of `psh verify --json` (README): `{"id", "source", "description", "max_error", "tolerance",
//! "passed"}` (plus `"proof"`, the derivation's page in `proofs/`, when there is one).

mod convolution;
mod filter;
pub mod isd;
mod lights;
mod matrix;
mod optics;
pub(crate) mod oracle;
mod pbrdf;
pub use pbrdf::{energy_below_horizon, isobi2_index, HORIZON_BOUND};
mod plan;
mod polarized;
pub mod polygon;
mod pprt;
pub use plan::{convex_scene as plan_convex_scene, tangent_plane_vs_rays, unpolarized_vs_full};
pub use pprt::reference_discrepancy as pprt_reference_discrepancy;
mod sh;
mod solid;
mod stokes;
mod swsh;
mod triple;

use crate::error::Result;
use crate::polarized::{Codomain, PshVector};
use serde::Serialize;

/// One check: what it verifies, against what, and how.
pub struct Check {
    /// Stable identifier, e.g. `sh.orthonormality`.
    pub id: &'static str,
    /// Paper tag and equation or figure, e.g. `PSH (9)`.
    pub source: &'static str,
    /// What is compared with what.
    pub description: &'static str,
    /// Largest acceptable error.
    pub tolerance: f64,
    /// Derivation page in `proofs/`, if the formula is not printed in the papers.
    pub proof: Option<&'static str>,
    /// Computes the maximum error.
    pub run: fn() -> Result<f64>,
}

/// The outcome of a check (the JSON record of `psh verify --json`).
#[derive(Clone, Debug, Serialize)]
pub struct CheckResult {
    pub id: String,
    pub source: String,
    pub description: String,
    pub max_error: f64,
    pub tolerance: f64,
    pub passed: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub proof: Option<String>,
    /// Set when the check could not run (its error message); the check then fails.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// Set when the check needs shared data that is absent (the message); the check is
    /// then not run and does not fail.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub skipped: Option<String>,
}

/// Every check, in a stable order.
pub fn checks() -> Vec<Check> {
    let mut all = sh::checks();
    all.extend(swsh::checks());
    all.extend(stokes::checks());
    all.extend(polarized::checks());
    all.extend(matrix::checks());
    all.extend(pbrdf::checks());
    all.extend(optics::checks());
    all.extend(filter::checks());
    all.extend(triple::checks());
    all.extend(convolution::checks());
    all.extend(pprt::checks());
    all.extend(plan::checks());
    all.extend(solid::checks());
    all.extend(lights::checks());
    all.extend(isd::checks());
    all.extend(polygon::checks());
    all
}

impl Check {
    /// Runs the check. An error, a NaN or an error above tolerance all fail; missing
    /// shared data ([`crate::Error::DataMissing`]) skips it.
    pub fn evaluate(&self) -> CheckResult {
        let (max_error, error, skipped) = match (self.run)() {
            Ok(e) => (e, None, None),
            Err(e @ crate::Error::DataMissing { .. }) => (f64::NAN, None, Some(e.to_string())),
            Err(e) => (f64::NAN, Some(e.to_string()), None),
        };
        CheckResult {
            id: self.id.into(),
            source: self.source.into(),
            description: self.description.into(),
            max_error,
            tolerance: self.tolerance,
            passed: skipped.is_some() || (error.is_none() && max_error <= self.tolerance),
            proof: self.proof.map(Into::into),
            error,
            skipped,
        }
    }
}

/// Runs the checks whose id contains `filter` (all when `None`).
pub fn run(filter: Option<&str>) -> Vec<CheckResult> {
    checks()
        .iter()
        .filter(|c| filter.is_none_or(|f| c.id.contains(f)))
        .map(Check::evaluate)
        .collect()
}

/// Deterministic pseudo-random numbers in `[-1, 1)` (a 64-bit LCG), for reproducible
/// test inputs without a dependency.
pub fn pseudo_random(n: usize, seed: u64) -> Vec<f64> {
    let mut x = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15).wrapping_add(1);
    (0..n)
        .map(|_| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((x >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        })
        .collect()
}

/// `n` deterministic pseudo-random unit directions (polar angle uniform in `[0, pi]`,
/// azimuth in `[-3.2, 3.2)`), from [`pseudo_random`] with `seed`.
pub fn random_directions(n: usize, seed: u64) -> Vec<[f64; 3]> {
    let r = pseudo_random(2 * n, seed);
    (0..n)
        .map(|k| {
            crate::sh::harmonics::direction(
                (r[2 * k] + 1.0) * 0.5 * std::f64::consts::PI,
                r[2 * k + 1] * 3.2,
            )
        })
        .collect()
}

/// Random coefficients on the index set PSH (31).
pub fn random_psh(
    lmax: usize,
    codomain: Codomain,
    channels: usize,
    seed: u64,
) -> Result<PshVector> {
    let p = codomain.components().len();
    let mut data = pseudo_random(channels * crate::sh::num_coeffs(lmax) * p, seed);
    for (i, x) in data.iter_mut().enumerate() {
        let lm = (i / p) % crate::sh::num_coeffs(lmax);
        let comp = codomain.components()[i % p];
        if lm < 4 && (comp == 1 || comp == 2) {
            *x = 0.0;
        }
    }
    PshVector::from_data(lmax, codomain, channels, data)
}

/// Convolution coefficients with random real forms `g_l` (all 16 entries), `l <= lmax`.
pub fn random_kernel(lmax: usize, seed: u64) -> Result<crate::polarized::KernelCoefficients> {
    let r = pseudo_random((lmax + 1) * 16, seed);
    let forms: Vec<crate::polarized::KernelValue> = (0..=lmax)
        .map(|l| std::array::from_fn(|q| std::array::from_fn(|p| r[l * 16 + q * 4 + p])))
        .collect();
    crate::polarized::KernelCoefficients::from_real_form(&forms)
}

/// A random coefficient matrix (full Stokes) on the index set PSH (31).
pub fn random_psh_matrix(lmax: usize, seed: u64) -> Result<crate::polarized::PshMatrix> {
    let n = crate::sh::num_coeffs(lmax);
    let mut data = pseudo_random(n * n * 16, seed);
    for (k, x) in data.iter_mut().enumerate() {
        let (jo, ji, po, pi) = (k / (16 * n), (k / 16) % n, (k / 4) % 4, k % 4);
        if (jo < 4 && (po == 1 || po == 2)) || (ji < 4 && (pi == 1 || pi == 2)) {
            *x = 0.0;
        }
    }
    crate::polarized::PshMatrix::from_data(lmax, data)
}
