//! SHG Sec. 7's table: many triangular lights, per-point exact SH coefficients (SHG
//! (4)-(5)) against grids of coefficients and gradients (SHG (6)) interpolated
//! trilinearly and by cubic Hermite ([`write_polygon_lights_demo`] into `shg/`, finest
//! level 5, 4 with `--quick`).

use super::panels::pngs;
use super::{Comparison, FigureOptions, Outcome, Table};
use crate::apps::polygon_lights_demo::{write_polygon_lights_demo, PAPER_FINEST};
use crate::error::Result;
use crate::lights::grid::Interpolation;
use crate::progress::Silent;
use std::path::Path;

/// The finest level with `--quick`.
const QUICK_FINEST: u32 = 4;

pub fn run(out: &Path, options: &FigureOptions) -> Result<Outcome> {
    let finest = if options.quick {
        QUICK_FINEST
    } else {
        PAPER_FINEST
    };
    let demo = write_polygon_lights_demo(&out.join("shg"), finest, &Silent)?;
    let error = |scheme: Interpolation| {
        demo.rows
            .iter()
            .find(|r| r.interpolation == scheme && r.level == finest)
            .map_or(f64::NAN, |r| r.mean_relative)
    };
    let (trilinear, hermite) = (
        error(Interpolation::Trilinear),
        error(Interpolation::Serendipity),
    );
    let pictures = pngs(&demo.files);
    Ok(Outcome {
        pictures,
        table: Table::notes(demo.markdown_table()),
        comparison: Some(Comparison {
            measured: format!(
                "mean relative error at level {finest}: trilinear {trilinear:.2e}, cubic Hermite {hermite:.2e}"
            ),
            expected: "the gradients' cubic Hermite below trilinear (SHG Sec. 7)".into(),
            holds: hermite < trilinear,
        }),
    })
}
