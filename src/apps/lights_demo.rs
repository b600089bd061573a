//! `psh lights-demo`: the procedural many-light scene of [`crate::lights::light_scene`] with
//! uniform grids and a Hessian-adaptive grid (SHH Sec. 5, 6.2), compared by construction
//! time and by the interpolation error against the per-point exact coefficients (a table
//! like SHH Table 2), with false-colour error images of the floor.

use crate::error::Result;
use crate::io::io_error;
use crate::io::png::{diverging, write_png_with_legend};
use crate::io::Legend;
use crate::lights::grid::{Lattice, LightGrid, Metric, Refinement};
use crate::lights::spherical::SphericalLights;
use crate::lights::{exact_coefficients, grid_errors, light_scene, LightScene};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// SH band limit of the demo (fourth-order SH as in SHH Sec. 6.2).
pub const DEMO_LMAX: usize = 4;
/// Finest level of every grid of the demo.
pub const DEMO_MAX_LEVEL: u32 = 7;
/// Absolute error threshold of the adaptive grid.
pub const DEMO_THRESHOLD: f64 = 0.3;

/// One row of the table.
#[derive(Clone, Debug)]
pub struct LightsDemoRow {
    /// The grid: `uniform <2^N>^3` or `adaptive (E_abs <= <threshold>)`.
    pub grid: String,
    /// Finest level `N` (`2^N` cells per axis).
    pub level: u32,
    /// Evaluated grid points.
    pub points: usize,
    /// Construction time (ms).
    pub time_ms: f64,
    /// Mean squared error per coefficient.
    pub mse: f64,
    /// `10 log10(peak^2 / MSE)`, `peak` the largest exact coefficient magnitude.
    pub psnr: f64,
    /// Mean over shading points of `|L - L_exact|_2`.
    pub mean_error: f64,
}

/// The demo's results.
#[derive(Clone, Debug)]
pub struct LightsDemoReport {
    /// Spherical lights in the scene (near and far).
    pub lights: usize,
    /// Shading points on the floor.
    pub shading_points: usize,
    /// Time of the per-point exact coefficients (ms).
    pub reference_ms: f64,
    /// The uniform grids by level, then the adaptive grid.
    pub rows: Vec<LightsDemoRow>,
    /// Index of the uniform row closest in construction time to the adaptive grid.
    pub equal_time: usize,
    /// Every file written: the error images, then `table.md`.
    pub files: Vec<PathBuf>,
}

impl LightsDemoReport {
    /// The table as Markdown.
    pub fn markdown_table(&self) -> String {
        let mut s = format!(
            "{} spherical lights, {} shading points, l <= {DEMO_LMAX}; reference (per-point exact) {:.1} ms\n\n",
            self.lights, self.shading_points, self.reference_ms
        );
        s.push_str("| grid | N | N_p | T_g (ms) | MSE | PSNR (dB) | mean abs error |\n");
        s.push_str("|---|---|---|---|---|---|---|\n");
        for (i, r) in self.rows.iter().enumerate() {
            let mark = if i == self.equal_time {
                " (equal time)"
            } else {
                ""
            };
            s.push_str(&format!(
                "| {}{mark} | {} | {} | {:.1} | {:.3e} | {:.1} | {:.3e} |\n",
                r.grid, r.level, r.points, r.time_ms, r.mse, r.psnr, r.mean_error
            ));
        }
        s
    }
}

fn row(
    name: String,
    level: u32,
    grid: &LightGrid,
    time_ms: f64,
    scene: &LightScene,
    exact: &[Vec<f64>],
    peak: f64,
) -> Result<(LightsDemoRow, Vec<f64>)> {
    let (mse, mean_error, per_point) = grid_errors(grid, &scene.points, exact)?;
    Ok((
        LightsDemoRow {
            grid: name,
            level,
            points: grid.num_points(),
            time_ms,
            mse,
            psnr: 10.0 * (peak * peak / mse).log10(),
            mean_error,
        },
        per_point,
    ))
}

/// Relative error per floor point as a false-colour image: `log10` of
/// `|L - L_exact| / |L_exact|` from `1e-6` (blue) to `1` (red), for an `n x n` floor.
pub(crate) fn error_image(
    path: &Path,
    n: usize,
    per_point: &[f64],
    exact: &[Vec<f64>],
) -> Result<()> {
    let rgb: Vec<[u8; 3]> = (0..n * n)
        .map(|i| {
            // Row 0 of the image at the largest y.
            let (r, c) = (i / n, i % n);
            let k = (n - 1 - r) * n + c;
            let norm = exact[k].iter().map(|x| x * x).sum::<f64>().sqrt();
            let e = (per_point[k] / norm).max(1e-300).log10();
            diverging((e + 3.0) / 3.0)
        })
        .collect();
    let bar = |t: f64| diverging(2.0 * t - 1.0);
    let ticks = (0..=6)
        .map(|k| (f64::from(k) / 6.0, format!("1e{}", k - 6)))
        .collect();
    let legend = Legend::bar(
        "relative error |L - L_exact| / |L_exact| per floor point (log scale)",
        &bar,
        ticks,
    );
    write_png_with_legend(path, &legend, n, n, &rgb)
}

/// Runs the demo and writes `table.md`, `error_adaptive.png` and
/// `error_uniform_N<level>.png` into `out` (created if missing).
pub fn write_lights_demo(out: &Path) -> Result<LightsDemoReport> {
    std::fs::create_dir_all(out).map_err(|e| io_error(out, e))?;
    let scene = light_scene(96, 24, 40, 3)?;
    let lights = SphericalLights::new(scene.lights.clone(), DEMO_LMAX)?;
    let t0 = Instant::now();
    let exact = exact_coefficients(&lights, &scene.points)?;
    let reference_ms = t0.elapsed().as_secs_f64() * 1e3;
    let peak = exact.iter().flatten().fold(0.0f64, |a, b| a.max(b.abs()));
    let build =
        |name: String, level: u32, refinement: Refinement| -> Result<(LightsDemoRow, Vec<f64>)> {
            let lattice = Lattice::new(scene.bounds.0, scene.bounds.1, level)?;
            let t0 = Instant::now();
            let grid = LightGrid::build(&lights, lattice, &scene.points, refinement)?;
            let ms = t0.elapsed().as_secs_f64() * 1e3;
            row(name, level, &grid, ms, &scene, &exact, peak)
        };
    let mut rows = Vec::new();
    let mut images = Vec::new();
    for level in 3..=DEMO_MAX_LEVEL - 1 {
        let (r, e) = build(
            format!("uniform {0}^3", 1u32 << level),
            level,
            Refinement::Uniform,
        )?;
        rows.push(r);
        images.push((format!("error_uniform_N{level}.png"), e));
    }
    let refinement = Refinement::Adaptive {
        metric: Metric::Absolute,
        threshold: DEMO_THRESHOLD,
    };
    let (r, e) = build(
        format!("adaptive (E_abs <= {DEMO_THRESHOLD})"),
        DEMO_MAX_LEVEL,
        refinement,
    )?;
    let ms = r.time_ms;
    let equal_time = rows
        .iter()
        .enumerate()
        .min_by(|a, b| {
            (a.1.time_ms - ms)
                .abs()
                .total_cmp(&(b.1.time_ms - ms).abs())
        })
        .map_or(0, |(i, _)| i);
    rows.push(r);
    images.push(("error_adaptive.png".into(), e));
    let mut files = Vec::new();
    for (name, e) in &images {
        let path = out.join(name);
        error_image(&path, scene.floor_side, e, &exact)?;
        files.push(path);
    }
    let mut report = LightsDemoReport {
        lights: scene.lights.len(),
        shading_points: scene.points.len(),
        reference_ms,
        rows,
        equal_time,
        files,
    };
    report
        .files
        .push(write_table(out, &report.markdown_table())?);
    Ok(report)
}

/// Writes `markdown` to `out/table.md` and returns the path.
pub(crate) fn write_table(out: &Path, markdown: &str) -> Result<PathBuf> {
    crate::io::write_text(out.join("table.md"), markdown)
}
