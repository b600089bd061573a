//! ISD Fig. 13: the condition number of ISD's matrix `M` against the band limit `L` for
//! the mother-function profiles, directions per band or shared across bands
//! ([`write_isd_report`] into `isd/`, up to `L = 31`, 12 with `--quick`).

use super::panels::pngs;
use super::{Comparison, FigureOptions, Outcome, Table};
use crate::apps::isd_report::{write_isd_report, PAPER_TOP};
use crate::error::Result;
use crate::isd::{Pattern, Profile, Sharing};
use crate::progress::Silent;
use std::path::Path;

/// The largest `L` with `--quick`.
const QUICK_TOP: usize = 12;

pub fn run(out: &Path, options: &FigureOptions) -> Result<Outcome> {
    let top = if options.quick { QUICK_TOP } else { PAPER_TOP };
    let report = write_isd_report(&out.join("isd"), top, &Silent)?;
    let pictures = pngs(&report.files);
    // ISD Sec. 6: sharing directions across bands barely changes the conditioning of the
    // Legendre (RZH) profile, and worsens that of the Phong profile much more.
    let growth = |profile: Profile| {
        let at = |sharing| report.condition(profile, Pattern::Fibonacci, sharing, top);
        at(Sharing::Shared) / at(Sharing::PerBand)
    };
    let (phong, legendre) = (growth(Profile::Phong), growth(Profile::Legendre));
    Ok(Outcome {
        pictures,
        table: Table::notes(report.markdown_table()),
        comparison: Some(Comparison {
            measured: format!(
                "at L = {top}, sharing multiplies the condition number by {phong:.1e} (Phong), {legendre:.1e} (Legendre)"
            ),
            expected: "Phong's factor above Legendre's (ISD Sec. 6)".into(),
            holds: phong > legendre,
        }),
    })
}
