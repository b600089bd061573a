//! PF Figs. 3 and 5, Table 1: the polarizing factor `psi` of PF Table 1's materials
//! (PF (10), Fig. 3), its specular-colour approximation and the approximation's error
//! (PF (16), Fig. 5), written by [`write_filter_report`] into `pf/`.

use super::panels::pngs;
use super::{Comparison, FigureOptions, Outcome, Table};
use crate::apps::filter_report::write_filter_report;
use crate::error::Result;
use crate::optics::Material;
use std::path::Path;

pub fn run(out: &Path, _options: &FigureOptions) -> Result<Outcome> {
    let report = write_filter_report(&out.join("pf"))?;
    let pictures = pngs(&report.files);
    // PF Sec. 5: for dielectrics the approximation is exact (no approximation made).
    let dielectric = report
        .errors
        .iter()
        .filter(|e| !e.material.is_conductor())
        .map(|e| e.from_ior[1].abs)
        .fold(0.0f64, f64::max);
    Ok(Outcome {
        pictures,
        table: Table::notes(report.markdown_table()),
        comparison: Some(Comparison {
            measured: format!(
                "largest |psi~ - psi| of the {} dielectrics up to 89 deg: {dielectric:.1e}",
                Material::ALL.iter().filter(|m| !m.is_conductor()).count()
            ),
            expected: "<= 1e-12 (PF: exact for dielectrics)".into(),
            holds: dielectric <= 1e-12,
        }),
    })
}
