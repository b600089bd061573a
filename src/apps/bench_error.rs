//! Run time against error (`psh bench-error`): PPRT at a ladder of band limits and
//! settings, and the reference renderer at a ladder of sample counts, each timed and
//! measured against a high-sample ground truth ([`crate::pprt::Reference`], exact fidelity);
//! PSH Fig. 19 (RMSE per Stokes component falling with the band limit) is the `full`
//! series of it.
//!
//! RMSE per Stokes component is over the pixels that see a surface and the three
//! channels, in the camera's frames; the total is the root of their sum of squares.

use crate::apps::plot::{Axis, LinePlot, Series, Stroke};
use crate::error::{Error, Result};
use crate::io::tick_label;
use crate::io::write_text;
use crate::pprt::plan::Plan;
use crate::pprt::reference::{Fidelity, Reference, ReferenceSettings};
use crate::pprt::render::{direct_light, primary_hits, render_frame, StokesImage};
use crate::pprt::scene::{Hit, Scene};
use crate::pprt::settings::{Planning, TransferSettings, Visibility};
use crate::pprt::transfer::precompute_planned;
use crate::progress::Progress;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// What to run.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct BenchErrorOptions {
    /// PPRT at band limits `2..=l_max`.
    pub l_max: usize,
    /// Visibility rays per vertex of the PPRT rows.
    pub rays: usize,
    /// Sample counts of the reference rows.
    pub spp: Vec<usize>,
    /// Samples per pixel of the ground truth (and of the band-limit floor's reference).
    pub ground_truth_spp: usize,
    /// An outside ground truth instead of psh's reference (Mitsuba 3's render read by
    /// [`crate::io::read_stokes_image`], made an image by [`ground_truth_image`]).
    pub ground_truth: Option<StokesImage>,
}

impl BenchErrorOptions {
    /// The default largest band limit of the PPRT rows.
    pub const L_MAX: usize = 9;
    /// The default visibility rays per vertex.
    pub const RAYS: usize = 256;
    /// The default sample counts of the reference rows.
    pub const SPP: [usize; 5] = [1, 4, 16, 64, 256];
    /// The default samples per pixel of the ground truth.
    pub const GROUND_TRUTH_SPP: usize = 2048;
}

impl Default for BenchErrorOptions {
    /// [`Self::L_MAX`], [`Self::RAYS`], [`Self::SPP`], [`Self::GROUND_TRUTH_SPP`], psh's
    /// reference as the ground truth.
    fn default() -> Self {
        BenchErrorOptions {
            l_max: Self::L_MAX,
            rays: Self::RAYS,
            spp: Self::SPP.to_vec(),
            ground_truth_spp: Self::GROUND_TRUTH_SPP,
            ground_truth: None,
        }
    }
}

/// An outside render of `scene` (`(width, height, [channel][pixel] components)` in the
/// camera's frames) as the ground truth of [`bench_error`], with psh's object mask (the
/// camera's primary hits). Error: a size other than the camera's, or not 3 channels.
pub fn ground_truth_image(
    scene: &Scene,
    (width, height, channels): crate::io::StokesPixels,
) -> Result<StokesImage> {
    let cam = scene.camera();
    if (width, height) != (cam.width, cam.height) || channels.len() != 3 {
        return Err(Error::invalid(
            "ground truth image",
            format!("{width} x {height}, {} channels", channels.len()),
            format!("the scene's camera is {} x {}, RGB", cam.width, cam.height),
        ));
    }
    let pixels: Vec<[[f64; 4]; 3]> = (0..width * height)
        .map(|k| [channels[0][k], channels[1][k], channels[2][k]])
        .collect();
    Ok(StokesImage::from_pixels(cam, &pixels, &primary_hits(scene)))
}

/// One row of `bench-error.json` (the contract).
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// `"pprt"` or `"reference"`.
    pub method: &'static str,
    /// PPRT's `"full"`, `"no_shadow"` or `"low_only"` ([`bench_error`]'s settings); the
    /// reference's `"exact"` or `"band_limited_env"` (the environment cut at `l_max`: the
    /// band-limit floor).
    pub setting: &'static str,
    /// Band limit of a PPRT row and of the band-limit floor; `None` for an `exact` row.
    pub l_max: Option<usize>,
    /// Samples per pixel of a reference row; `None` for PPRT.
    pub spp: Option<usize>,
    /// Seconds of PPRT's plan and transfer precomputation; 0 for the reference.
    pub precompute_s: f64,
    /// Seconds per frame: PPRT's the median of [`PPRT_FRAMES`], the reference's one run.
    pub frame_s: f64,
    /// RMSE of `s0..s3` against the ground truth (the module's convention).
    pub rmse: [f64; 4],
}

/// `bench-error.json`: the ground truth, every row, and the speed-up at equal error.
#[derive(Clone, Debug, Serialize)]
pub struct BenchErrorReport {
    /// "psh reference" at `ground_truth_spp`, or "outside image" ([`BenchErrorOptions::ground_truth`]).
    pub ground_truth: &'static str,
    /// Samples per pixel of psh's ground truth and of the `band_limited_env` row.
    pub ground_truth_spp: usize,
    /// Seconds of rendering the ground truth; 0 for an outside image.
    pub ground_truth_s: f64,
    /// Width and height in pixels.
    pub image: [usize; 2],
    /// PPRT at `l = 2..=l_max` (each setting), the reference's sample ladder, then the
    /// band-limit floor.
    pub rows: Vec<Row>,
    /// `None` (JSON `null`) without a PPRT `full` row at `l_max` or two reference rows.
    pub speedup_at_equal_rmse: Option<Speedup>,
}

/// The reference's frame time at PPRT `full`'s total RMSE at `l_max` over PPRT's.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Speedup {
    /// PPRT's band limit (`l_max`).
    pub pprt_l_max: usize,
    /// PPRT `full`'s total RMSE at it ([`Row::total`]).
    pub pprt_rmse: f64,
    /// PPRT's seconds per frame.
    pub pprt_frame_s: f64,
    /// The reference's seconds per frame at that RMSE, by log-log interpolation along its
    /// sample ladder.
    pub reference_frame_s: f64,
    /// `reference_frame_s / pprt_frame_s`.
    pub ratio: f64,
    /// Whether the reference's time was extrapolated beyond its sample ladder.
    pub extrapolated: bool,
}

impl Row {
    /// The total RMSE: the root of the sum of the four components' squares.
    pub fn total(&self) -> f64 {
        self.rmse.iter().map(|x| x * x).sum::<f64>().sqrt()
    }
}

/// The PPRT settings of a row: `full` (`l_low = min(l, 4)`, high orders to `l`,
/// shadows), `no_shadow` (the same without shadows), `low_only` (`l_low = l`, no high
/// orders, shadows).
fn pprt_settings(setting: &str, l: usize, rays: usize) -> TransferSettings {
    let l_low = l.min(4);
    let high = (l > l_low).then_some(l);
    match setting {
        "no_shadow" => TransferSettings {
            l_low,
            l_high: high,
            rays,
            visibility: Visibility::Off,
        },
        "low_only" => TransferSettings {
            l_low: l,
            l_high: None,
            rays,
            visibility: Visibility::Rays,
        },
        _ => TransferSettings {
            l_low,
            l_high: high,
            rays,
            visibility: Visibility::Rays,
        },
    }
}

/// RMSE per Stokes component of `a` against `truth` over the surface pixels. Errors:
/// other sizes; an error beyond the range of `f64` (a ground truth of values near
/// `1e154` or larger), named rather than reported as infinity.
pub fn rmse(a: &StokesImage, truth: &StokesImage) -> Result<[f64; 4]> {
    if (a.width, a.height) != (truth.width, truth.height) {
        return Err(Error::invalid(
            "image size",
            format!("{} x {}", a.width, a.height),
            format!("the ground truth is {} x {}", truth.width, truth.height),
        ));
    }
    let mut sq = [0.0; 4];
    let mut count = 0usize;
    for (c, t) in a.channels.iter().zip(&truth.channels) {
        for ((x, y), object) in c.iter().zip(t).zip(&truth.object) {
            if object.is_some() {
                count += 1;
                for q in 0..4 {
                    sq[q] += (x[q] - y[q]).powi(2);
                }
            }
        }
    }
    let n = count.max(1) as f64;
    let e = sq.map(|s| (s / n).sqrt());
    crate::error::finite_all("RMSE against the ground truth", &e)?;
    Ok(e)
}

/// Runs the benchmark on `scene` and writes `bench-error.json`, `bench-error.csv`,
/// `bench-error.png` (log10 total RMSE against log10 seconds per frame: PPRT `full` red,
/// `no_shadow` orange, `low_only` purple, the reference blue; grid lines every decade)
/// and `fig19.png` (log10 RMSE of `s0..s3`, black, red, green, blue, against `l` for
/// PPRT `full`; grid every band and every decade) into `out`, the four together at the
/// end ([`crate::io::all_or_nothing`]: a failing run leaves an earlier run's as they
/// were). Returns the JSON. `progress` counts the ground truth and the rows.
pub fn bench_error(
    scene: &Scene,
    options: &BenchErrorOptions,
    out: &Path,
    progress: &dyn Progress,
) -> Result<BenchErrorReport> {
    options.check(scene)?;
    std::fs::create_dir_all(out).map_err(|e| Error::Io {
        path: out.to_path_buf(),
        source: e,
    })?;
    crate::io::check_output(out.join("bench-error.json"))?;
    let rows_total = 3 * (options.l_max - 1) + options.spp.len() + 1;
    progress.start(
        "bench-error: ground truth, then rows",
        1 + rows_total as u64,
    );
    let hits = primary_hits(scene);
    let direct = direct_light(scene, &hits)?;
    let reference = |samples, fidelity, seed| -> Result<(StokesImage, f64)> {
        let r = Reference::new(
            scene,
            ReferenceSettings {
                samples,
                fidelity,
                seed,
            },
        )?;
        let t = Instant::now();
        let image = r.render(&hits)?;
        Ok((image, t.elapsed().as_secs_f64()))
    };
    let (truth, truth_s) = match &options.ground_truth {
        Some(t) => (
            ground_truth_image(scene, (t.width, t.height, t.channels.clone()))?,
            0.0,
        ),
        None => reference(options.ground_truth_spp, Fidelity::Exact, 1)?,
    };
    progress.advance(1);
    let mut rows = Vec::new();
    let mut push = |row: Row| -> Result<()> {
        rows.push(row);
        progress.advance(1);
        Ok(())
    };
    for l in 2..=options.l_max {
        for setting in ["full", "no_shadow", "low_only"] {
            push(pprt_row(
                scene,
                (&hits, &direct),
                setting,
                l,
                options.rays,
                &truth,
            )?)?;
        }
    }
    for &spp in &options.spp {
        let (image, frame_s) = reference(spp, Fidelity::Exact, 2)?;
        push(Row {
            method: "reference",
            setting: "exact",
            l_max: None,
            spp: Some(spp),
            precompute_s: 0.0,
            frame_s,
            rmse: rmse(&image, &truth)?,
        })?;
    }
    // The band-limit floor: the reference with the environment cut at l_max.
    let (image, frame_s) = reference(
        options.ground_truth_spp,
        Fidelity::BandLimitedEnvironment(options.l_max),
        2,
    )?;
    push(Row {
        method: "reference",
        setting: "band_limited_env",
        l_max: Some(options.l_max),
        spp: Some(options.ground_truth_spp),
        precompute_s: 0.0,
        frame_s,
        rmse: rmse(&image, &truth)?,
    })?;
    progress.finish();
    let speedup = speedup_at_equal_error(&rows, options.l_max);
    let report = BenchErrorReport {
        ground_truth: if options.ground_truth.is_some() {
            "outside image"
        } else {
            "psh reference"
        },
        ground_truth_spp: options.ground_truth_spp,
        ground_truth_s: truth_s,
        image: [truth.width, truth.height],
        rows,
        speedup_at_equal_rmse: speedup,
    };
    crate::io::all_or_nothing(&[], || write_report(&report, out, options.l_max))?;
    Ok(report)
}

impl BenchErrorOptions {
    /// Errors: `l_max` below 2 or above the environment's band limit, no sample count.
    fn check(&self, scene: &Scene) -> Result<()> {
        if self.l_max < 2 || self.l_max > scene.environment().lmax() || self.spp.is_empty() {
            return Err(Error::invalid(
                "bench-error options",
                format!("l_max {}, spp {:?}", self.l_max, self.spp),
                format!(
                    "2 <= l_max <= the environment's band limit {}, and at least one sample count",
                    scene.environment().lmax()
                ),
            ));
        }
        // Every count before any work: the ground truth renders first.
        for &spp in self.spp.iter().chain([&self.ground_truth_spp]) {
            crate::pprt::check_samples(spp)?;
        }
        Ok(())
    }
}

/// One PPRT row: the precomputation at band limit `l` with `setting`'s settings, timed,
/// and the median frame's RMSE against `truth`; `(hits, direct)` of the camera.
fn pprt_row(
    scene: &Scene,
    (hits, direct): (&[Option<Hit>], &[[[f64; 4]; 3]]),
    setting: &'static str,
    l: usize,
    rays: usize,
    truth: &StokesImage,
) -> Result<Row> {
    let settings = pprt_settings(setting, l, rays);
    let t = Instant::now();
    let plan = Plan::new(scene, settings, Planning::Full)?;
    let transfer = precompute_planned(scene, &plan, &crate::progress::Silent)?;
    let high = plan.high_fields();
    let precompute_s = t.elapsed().as_secs_f64();
    let (image, frame_s) = median_frame(|| render_frame(scene, &transfer, &high, hits, direct))?;
    Ok(Row {
        method: "pprt",
        setting,
        l_max: Some(l),
        spp: None,
        precompute_s,
        frame_s,
        rmse: rmse(&image, truth)?,
    })
}

/// `bench-error.json`, `bench-error.csv` and the plots `bench-error.png` and `fig19.png`
/// (`.svg` with [`super::plot::PlotFormat::Svg`]) into `out`.
fn write_report(report: &BenchErrorReport, out: &Path, l_max: usize) -> Result<()> {
    write_text(
        out.join("bench-error.json"),
        &serde_json::to_value(report)
            .and_then(|v| serde_json::to_string_pretty(&v))
            .map_err(|e| Error::invalid("report", "bench-error.json", e.to_string()))?,
    )?;
    write_text(out.join("bench-error.csv"), &csv_text(&report.rows))?;
    plot_error_time(&report.rows, &out.join("bench-error.png"))?;
    plot_fig19(&report.rows, l_max, &out.join("fig19.png"))
}

/// Frames PPRT renders per row; its frame time is their median (the first frame also
/// pays for warming the caches and the thread pool, which a renderer pays once).
pub const PPRT_FRAMES: usize = 25;

/// The image of `frame` and the median of [`PPRT_FRAMES`] run times, in seconds.
fn median_frame(frame: impl Fn() -> Result<StokesImage>) -> Result<(StokesImage, f64)> {
    let mut times = Vec::with_capacity(PPRT_FRAMES);
    let mut image = None;
    for _ in 0..PPRT_FRAMES {
        let t = Instant::now();
        image = Some(frame()?);
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    Ok((image.expect("PPRT_FRAMES > 0"), times[PPRT_FRAMES / 2]))
}

/// The rows as `bench-error.csv`.
fn csv_text(rows: &[Row]) -> String {
    use std::fmt::Write;
    let opt = |x: Option<usize>| x.map_or(String::new(), |v| v.to_string());
    let mut text = String::from(
        "method,setting,l_max,spp,precompute_s,frame_s,rmse_s0,rmse_s1,rmse_s2,rmse_s3\n",
    );
    for r in rows {
        let _ = writeln!(
            text,
            "{},{},{},{},{:.6},{:.6},{:.6e},{:.6e},{:.6e},{:.6e}",
            r.method,
            r.setting,
            opt(r.l_max),
            opt(r.spp),
            r.precompute_s,
            r.frame_s,
            r.rmse[0],
            r.rmse[1],
            r.rmse[2],
            r.rmse[3]
        );
    }
    text
}

/// The reference's frame time at PPRT `full`'s total RMSE at `l_max`, by log-log
/// interpolation along the sample ladder (extrapolated from the last two counts when the
/// ladder does not reach that error), over PPRT's frame time.
fn speedup_at_equal_error(rows: &[Row], l_max: usize) -> Option<Speedup> {
    let p = rows
        .iter()
        .find(|r| r.method == "pprt" && r.setting == "full" && r.l_max == Some(l_max))?;
    let refs: Vec<&Row> = rows.iter().filter(|r| r.setting == "exact").collect();
    if refs.len() < 2 {
        return None;
    }
    let target = p.total();
    let first_below = refs.iter().position(|r| r.total() <= target);
    let k = match first_below {
        Some(0) => 0,
        Some(i) => i - 1,
        None => refs.len() - 2,
    };
    let (a, b) = (refs[k], refs[k + 1]);
    let slope = (b.frame_s.ln() - a.frame_s.ln()) / (b.total().ln() - a.total().ln());
    let t = (a.frame_s.ln() + slope * (target.ln() - a.total().ln())).exp();
    Some(Speedup {
        pprt_l_max: l_max,
        pprt_rmse: target,
        pprt_frame_s: p.frame_s,
        reference_frame_s: t,
        ratio: t / p.frame_s,
        extrapolated: matches!(first_below, None | Some(0)),
    })
}

/// Decades containing the positive values `xs` (log10, widened to whole decades).
fn decades(xs: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = xs
        .filter(|x| *x > 0.0 && x.is_finite())
        .map(f64::log10)
        .fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x), b.max(x)));
    if lo > hi {
        (-1.0, 0.0)
    } else {
        (lo.floor(), hi.ceil().max(lo.floor() + 1.0))
    }
}

fn plot_error_time(rows: &[Row], path: &Path) -> Result<()> {
    let (x0, x1) = decades(rows.iter().map(|r| r.frame_s));
    let (y0, y1) = decades(rows.iter().map(Row::total));
    let mut plot = LinePlot::new(
        "Run time against error (psh bench-error)",
        Axis::log("frame time (s)", (10f64.powf(x0), 10f64.powf(x1))),
        Axis::log(
            "RMSE, all Stokes components",
            (10f64.powf(y0), 10f64.powf(y1)),
        ),
    )?;
    for (method, setting, label, color) in [
        ("pprt", "full", "PPRT full (l = 2..)", [200, 30, 30]),
        ("pprt", "no_shadow", "PPRT without shadows", [240, 150, 20]),
        ("pprt", "low_only", "PPRT low orders only", [130, 50, 170]),
        (
            "reference",
            "exact",
            "reference (samples per pixel)",
            [30, 80, 200],
        ),
    ] {
        plot.add(Series {
            label: label.into(),
            color,
            stroke: Stroke::Solid,
            points: rows
                .iter()
                .filter(|r| r.method == method && r.setting == setting)
                .map(|r| (r.frame_s, r.total()))
                .collect(),
        });
    }
    plot.write(path, 800, 600).map(drop)
}

fn plot_fig19(rows: &[Row], l_max: usize, path: &Path) -> Result<()> {
    let full: Vec<&Row> = rows
        .iter()
        .filter(|r| r.method == "pprt" && r.setting == "full")
        .collect();
    // Six decades under the largest error: below them a component is zero to rounding
    // (`s3` of an unpolarized scene) and would flatten the others.
    let top = full.iter().flat_map(|r| r.rmse).fold(0.0f64, f64::max);
    let floor = top * 1e-6;
    let (y0, y1) = decades(full.iter().flat_map(|r| r.rmse).filter(|&e| e >= floor));
    let hidden: Vec<String> = (0..4)
        .filter(|&q| full.iter().all(|r| r.rmse[q] < floor))
        .map(|q| format!("s{q}"))
        .collect();
    let title = if hidden.is_empty() {
        "PPRT full against the ground truth (PSH Fig. 19)".to_string()
    } else {
        format!(
            "PPRT full against the ground truth (PSH Fig. 19; {} below {}, not drawn)",
            hidden.join(", "),
            tick_label(floor)
        )
    };
    let mut plot = LinePlot::new(
        &title,
        Axis::integer("band limit l_max", (2.0, l_max.max(3) as f64)),
        Axis::log("RMSE", (10f64.powf(y0), 10f64.powf(y1))),
    )?;
    for (q, color) in [[0, 0, 0], [200, 30, 30], [30, 150, 30], [30, 80, 200]]
        .into_iter()
        .enumerate()
    {
        plot.add(Series {
            label: format!("s{q}"),
            color,
            stroke: Stroke::Solid,
            points: full
                .iter()
                .filter(|r| r.rmse[q] >= floor)
                .map(|r| (r.l_max.unwrap_or(0) as f64, r.rmse[q]))
                .collect(),
        });
    }
    plot.write(path, 800, 600).map(drop)
}
