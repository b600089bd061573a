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
#[cfg(test)]
pub(crate) use pbrdf::isobi2_index;
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
    /// [`Check::id`].
    pub id: String,
    /// [`Check::source`].
    pub source: String,
    /// [`Check::description`].
    pub description: String,
    /// The maximum error computed; NaN when the check errored or was skipped.
    pub max_error: f64,
    /// [`Check::tolerance`].
    pub tolerance: f64,
    /// `max_error <= tolerance` without an error, or skipped.
    pub passed: bool,
    /// [`Check::proof`].
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
    run_with(filter, &crate::progress::Silent).expect("Silent never cancels")
}

/// [`run`], reporting each check done to `progress` and stopping between checks when it
/// is cancelled ([`crate::Error::Interrupted`]).
pub fn run_with(
    filter: Option<&str>,
    progress: &dyn crate::progress::Progress,
) -> Result<Vec<CheckResult>> {
    let selected: Vec<Check> = checks()
        .into_iter()
        .filter(|c| filter.is_none_or(|f| c.id.contains(f)))
        .collect();
    progress.start("psh verify", selected.len() as u64);
    let mut results = Vec::with_capacity(selected.len());
    for c in &selected {
        progress.check_cancelled("psh verify")?;
        results.push(c.evaluate());
        progress.advance(1);
    }
    progress.finish();
    Ok(results)
}
