//! SHH Tables 1 and 2: the mean squared error of the SH Hessians against the 20-digit
//! oracle (SHH Table 1; psh's Hessian has no division by `sin theta`, so no error at the
//! poles), and many spherical lights on uniform grids against the Hessian-adaptive grid
//! ([`write_lights_demo`] into `shh/`, SHH Table 2).

use super::panels::pngs;
use super::{Comparison, FigureOptions, Outcome, Table};
use crate::apps::lights_demo::{write_lights_demo, LightsDemoRow};
use crate::error::Result;
use crate::verify::oracle::sh_hessian_table1;
use std::path::Path;

pub fn run(out: &Path, _options: &FigureOptions) -> Result<Outcome> {
    let bands = sh_hessian_table1()?;
    let mut table = Table::new(&["SH band l", "MSE of the Hessian against the oracle"]);
    for (l, mse) in &bands {
        table.row(vec![l.to_string(), format!("{mse:.2e}")]);
    }
    let worst = bands.iter().map(|b| b.1).fold(0.0f64, f64::max);
    let demo = write_lights_demo(&out.join("shh"))?;
    // SHH Table 2 compares at equal construction time; time is the machine's, so the
    // figure compares at equal cost in grid points: the uniform grids' MSE interpolated
    // (log-log) at the adaptive grid's number of points.
    let (adaptive, points) = demo
        .rows
        .iter()
        .find(|r| !r.grid.starts_with("uniform"))
        .map_or((f64::NAN, 0), |r| (r.mse, r.points));
    let uniform = uniform_mse_at(&demo.rows, points);
    let pictures = pngs(&demo.files);
    Ok(Outcome {
        pictures,
        table: Table {
            notes: demo.markdown_table(),
            ..table
        },
        comparison: Some(Comparison {
            measured: format!(
                "Hessian MSE at most {worst:.1e}; adaptive grid MSE {adaptive:.2e} against {uniform:.2e} of uniform grids at its {points} points"
            ),
            expected: "Hessian MSE <= 1e-20; the adaptive grid below the uniform ones".into(),
            holds: worst <= 1e-20 && adaptive < uniform,
        }),
    })
}

/// The MSE of the uniform rows interpolated log-log at `points` grid points (NaN outside
/// their range).
fn uniform_mse_at(rows: &[LightsDemoRow], points: usize) -> f64 {
    let mut uniform: Vec<&LightsDemoRow> = rows
        .iter()
        .filter(|r| r.grid.starts_with("uniform"))
        .collect();
    uniform.sort_by_key(|r| r.points);
    let x = (points as f64).ln();
    uniform
        .windows(2)
        .find(|w| w[0].points <= points && points <= w[1].points)
        .map_or(f64::NAN, |w| {
            let (x0, x1) = ((w[0].points as f64).ln(), (w[1].points as f64).ln());
            let t = (x - x0) / (x1 - x0);
            (w[0].mse.ln() * (1.0 - t) + w[1].mse.ln() * t).exp()
        })
}
