//! Jobs on a scene besides rendering it: run time against error (`bench-error`) and the
//! export to Mitsuba 3 (`export-mitsuba`).

use crate::args::{parse_spp, to_json, SceneArgs};
use crate::terminal::TerminalProgress;
use clap::Args;
use psh::apps::bench_error::{
    bench_error as run_bench_error, ground_truth_image, BenchErrorOptions,
};
use psh::apps::{ImageSize, RenderJob};
use serde_json::json;
use std::path::PathBuf;

#[derive(Args)]
pub struct BenchErrorArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Output directory.
    #[arg(long)]
    out: PathBuf,
    /// Image size WxH (replaces the scene camera's).
    #[arg(long, default_value = "160x120")]
    size: ImageSize,
    /// Largest band limit of the PPRT rows.
    #[arg(long, default_value_t = BenchErrorOptions::L_MAX)]
    lmax: usize,
    /// Visibility rays per vertex of the PPRT rows.
    #[arg(long, default_value_t = BenchErrorOptions::RAYS)]
    rays: usize,
    /// Samples per pixel of the reference rows, comma-separated.
    #[arg(long, default_values_t = BenchErrorOptions::SPP, value_delimiter = ',', value_parser = parse_spp)]
    spp: Vec<usize>,
    /// Samples per pixel of the ground truth.
    #[arg(long, default_value_t = BenchErrorOptions::GROUND_TRUTH_SPP, value_parser = parse_spp)]
    ground_truth_spp: usize,
    /// An outside ground truth: a Stokes image EXR with layers S0..S3 (R, G, B), as
    /// Mitsuba 3's stokes integrator writes it, of the scene's camera (docs/mitsuba.md);
    /// psh's reference still renders the band-limit floor at --ground-truth-spp.
    #[arg(long)]
    ground_truth: Option<PathBuf>,
}

#[derive(Args)]
pub struct ExportMitsubaArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Output directory (created if missing).
    #[arg(long, default_value = "psh-mitsuba")]
    out: PathBuf,
    /// Image size WxH of the built-in scene.
    #[arg(long, default_value_t = ImageSize::RENDER)]
    size: ImageSize,
    /// Mitsuba's samples per pixel.
    #[arg(long, default_value_t = 256)]
    spp: usize,
    /// Rows of the environment's lat-long map (columns: twice as many).
    #[arg(long, default_value_t = psh::io::ENVMAP_ROWS)]
    env_rows: usize,
}

pub fn bench_error(a: &BenchErrorArgs) -> psh::Result<serde_json::Value> {
    let (w, h) = (a.size.width, a.size.height);
    let (mut scene, name) = a.scene.setup(a.size).load(a.lmax)?;
    let cam = scene.camera().clone();
    scene.set_camera(psh::pprt::Camera {
        width: w,
        height: h,
        ..cam
    });
    eprintln!(
        "bench-error on {} ({} triangles, {w} x {h}): ground truth at {} spp, then PPRT l = 2..{} \
         and the reference at {:?} spp, into {}",
        name,
        scene.triangle_count(),
        a.ground_truth_spp,
        a.lmax,
        a.spp,
        a.out.display()
    );
    let mut options = BenchErrorOptions::default();
    options.l_max = a.lmax;
    options.rays = a.rays;
    options.spp = a.spp.clone();
    options.ground_truth_spp = a.ground_truth_spp;
    options.ground_truth = a
        .ground_truth
        .as_ref()
        .map(|p| psh::io::read_stokes_image(p).and_then(|image| ground_truth_image(&scene, image)))
        .transpose()?;
    to_json(&run_bench_error(
        &scene,
        &options,
        &a.out,
        &TerminalProgress::new(),
    )?)
}

pub fn export_mitsuba(a: &ExportMitsubaArgs) -> psh::Result<serde_json::Value> {
    // The scene as `psh render` would render it: its settings checked, its environment
    // at their band limit.
    let mut job = RenderJob::default();
    job.scene = a.scene.setup(a.size);
    let loaded = job.load()?;
    let export = psh::io::export_mitsuba(&loaded.scene, &a.out, a.spp, a.env_rows)?;
    Ok(json!({
        "scene": loaded.name,
        "files": export.files,
        "differences": export.differences,
    }))
}
