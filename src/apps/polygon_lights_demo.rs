//! `psh polygon-lights-demo`: many triangular lights over a floor
//! ([`crate::lights::polygon_scene`]); per-vertex exact coefficients (SHG (4)-(5)) against
//! uniform grids of coefficients and gradients (SHG (6)) interpolated trilinearly, by the
//! zero-cross-derivative Hermite and by the cubic Hermite serendipity interpolant:
//! errors and times (a table like SHG Sec. 7), with false-colour error images.

use crate::apps::lights_demo::{error_image, write_table};
use crate::error::Result;
use crate::io::io_error;
use crate::lights::grid::{Interpolation, Lattice, LightGrid, Refinement};
use crate::lights::polygon::PolygonalLights;
use crate::lights::polygon_scene;
use crate::lights::{exact_coefficients, grid_errors_with};
use crate::progress::Progress;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The finest grid level of the full demo (`2^5` cells per axis).
pub const PAPER_FINEST: u32 = 5;

/// SH band limit of the demo (`l <= 8`, as in SHG Sec. 3.1).
pub const DEMO_LMAX: usize = 8;

/// One row of the table.
#[derive(Clone, Debug)]
pub struct PolygonLightsDemoRow {
    /// The interpolant of the grid's coefficients and gradients.
    pub interpolation: Interpolation,
    /// Finest level `N` (`2^N` cells per axis).
    pub level: u32,
    /// Evaluated grid points.
    pub points: usize,
    /// Grid construction time (ms), coefficients and gradients at every grid point.
    pub build_ms: f64,
    /// Interpolation time at all shading points (ms).
    pub interpolate_ms: f64,
    /// Mean over shading points of `|L - L_exact|_2 / |L_exact|_2`.
    pub mean_relative: f64,
    /// Largest such relative error.
    pub max_relative: f64,
}

/// The demo's results.
#[derive(Clone, Debug)]
pub struct PolygonLightsDemoReport {
    /// Polygonal lights in the scene (near triangles and walls).
    pub lights: usize,
    /// Shading points on the floor.
    pub shading_points: usize,
    /// Time of the per-point exact coefficients (ms).
    pub reference_ms: f64,
    /// By level, then by interpolation (trilinear, Hermite, serendipity).
    pub rows: Vec<PolygonLightsDemoRow>,
    /// Every file written: the error images of the finest level, then `table.md`.
    pub files: Vec<PathBuf>,
}

impl PolygonLightsDemoReport {
    /// The table as Markdown.
    pub fn markdown_table(&self) -> String {
        let mut s = format!(
            "{} polygonal lights (clipped to the floor's horizon), {} shading points, l <= {DEMO_LMAX}; per-point exact coefficients {:.1} ms\n\n",
            self.lights, self.shading_points, self.reference_ms
        );
        s.push_str("| interpolation | N | grid points | build (ms) | interpolate (ms) | mean rel. error | max rel. error |\n");
        s.push_str("|---|---|---|---|---|---|---|\n");
        for r in &self.rows {
            s.push_str(&format!(
                "| {:?} | {} | {} | {:.1} | {:.1} | {:.3e} | {:.3e} |\n",
                r.interpolation,
                r.level,
                r.points,
                r.build_ms,
                r.interpolate_ms,
                r.mean_relative,
                r.max_relative
            ));
        }
        s
    }
}

/// Runs the demo with grids of levels `2..=finest` ([`PAPER_FINEST`] is the full demo's)
/// and writes `table.md` and `error_<scheme>_N<finest>.png` into `out` (created if
/// missing), counting the exact coefficients and each grid level on `progress`.
pub fn write_polygon_lights_demo(
    out: &Path,
    finest: u32,
    progress: &dyn Progress,
) -> Result<PolygonLightsDemoReport> {
    std::fs::create_dir_all(out).map_err(|e| io_error(out, e))?;
    let scene = polygon_scene(64, 48, 7)?;
    let lights =
        PolygonalLights::new(scene.lights.clone(), DEMO_LMAX)?.with_horizon(scene.normal)?;
    let levels = 2..=finest.max(2);
    progress.start(
        "polygon-lights-demo: exact coefficients, then grid levels",
        1 + levels.clone().count() as u64,
    );
    let t0 = Instant::now();
    let exact = exact_coefficients(&lights, &scene.points)?;
    progress.advance(1);
    let reference_ms = t0.elapsed().as_secs_f64() * 1e3;
    let norms: Vec<f64> = exact
        .iter()
        .map(|e| e.iter().map(|x| x * x).sum::<f64>().sqrt())
        .collect();
    let mut rows = Vec::new();
    let mut files = Vec::new();
    for level in levels.clone() {
        let lattice = Lattice::new(scene.bounds.0, scene.bounds.1, level)?;
        let t0 = Instant::now();
        let grid = LightGrid::build(&lights, lattice, &scene.points, Refinement::Uniform)?;
        let build_ms = t0.elapsed().as_secs_f64() * 1e3;
        for scheme in [
            Interpolation::Trilinear,
            Interpolation::Hermite,
            Interpolation::Serendipity,
        ] {
            let t0 = Instant::now();
            let (_, _, per_point) = grid_errors_with(&grid, &scene.points, &exact, scheme)?;
            let interpolate_ms = t0.elapsed().as_secs_f64() * 1e3;
            let rel: Vec<f64> = per_point.iter().zip(&norms).map(|(e, n)| e / n).collect();
            rows.push(PolygonLightsDemoRow {
                interpolation: scheme,
                level,
                points: grid.num_points(),
                build_ms,
                interpolate_ms,
                mean_relative: rel.iter().sum::<f64>() / rel.len() as f64,
                max_relative: rel.iter().fold(0.0, |a, b| a.max(*b)),
            });
            if Some(level) == levels.clone().last() {
                let path = out.join(format!("error_{scheme:?}_N{level}.png").to_lowercase());
                error_image(&path, scene.floor_side, &per_point, &exact)?;
                files.push(path);
            }
        }
        progress.advance(1);
    }
    progress.finish();
    let mut report = PolygonLightsDemoReport {
        lights: scene.lights.len(),
        shading_points: scene.points.len(),
        reference_ms,
        rows,
        files,
    };
    report
        .files
        .push(write_table(out, &report.markdown_table())?);
    Ok(report)
}
