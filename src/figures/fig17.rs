//! PSH Fig. 17: a polarized plastic pBRDF (PSH coefficient matrix, l <= 4) averaged over
//! rotations on Euler grids of resolution n = 1..7 (PSH (64)-(67)); the residual of its
//! projection onto the convolutions against n, as a table and a plot.

use super::{Comparison, FigureOptions, Outcome, Table};
use crate::apps::plot::{Axis, LinePlot, Series, Stroke};
use crate::error::Result;
use crate::optics::PolarizedPlastic;
use crate::polarized::{project_operator, project_to_convolution, rotation_average, SpinBlock22};
use std::path::Path;

/// Band limit of the pBRDF matrix.
const LMAX: usize = 4;

pub fn run(out: &Path, _options: &FigureOptions) -> Result<Outcome> {
    let brdf = PolarizedPlastic::new(0.3, 1.5, 0.5)?;
    let m = project_operator(&brdf, LMAX, 2 * LMAX, SpinBlock22::ComplexPair)?;
    let (_, raw) = project_to_convolution(&m)?;
    let mut table = Table::new(&["Euler grid n (2n x n x 2n rotations)", "residual"]);
    table.row(vec!["none (the pBRDF itself)".into(), format!("{raw:.3e}")]);
    let mut points = Vec::new();
    let mut exact = f64::NAN;
    for n in 1..=LMAX + 3 {
        let (_, residual) = project_to_convolution(&rotation_average(&m, n)?)?;
        table.row(vec![n.to_string(), format!("{residual:.3e}")]);
        points.push((n as f64, residual.max(1e-17)));
        if n == LMAX + 1 {
            exact = residual;
        }
    }
    let mut plot = LinePlot::new(
        "PSH Fig. 17: rotation average of a polarized plastic",
        Axis::integer(
            "Euler grid n (2n x n x 2n rotations)",
            (1.0, (LMAX + 3) as f64),
        ),
        Axis::log("residual from a convolution", (1e-17, 1.0)),
    )?;
    plot.add(Series {
        label: format!("plastic (alpha 0.3, n 1.5, albedo 0.5), l <= {LMAX}"),
        color: [200, 40, 40],
        stroke: Stroke::Solid,
        points,
    });
    let path = plot.write(out.join("fig17_residual.png"), 720, 480)?;
    Ok(Outcome {
        pictures: vec![path],
        table,
        comparison: Some(Comparison {
            measured: format!("residual at n = lmax + 1: {exact:.1e}, of the pBRDF {raw:.1e}"),
            expected: "<= 1e-12 at n = lmax + 1, the pBRDF's >= 1e-3".into(),
            holds: exact <= 1e-12 && raw >= 1e-3,
        }),
    })
}
