//! PSH Fig. 19: PPRT's error falling with the band limit, and run time against error
//! beside a reference ([`bench_error`]): on the built-in scene against a high-sample
//! ground truth of psh's reference renderer (into `fig19/`), and, given a Python with
//! Mitsuba 3 (`--mitsuba`), as the paper did, against Mitsuba 3's render of
//! `scenes/mitsuba_sky.toml` (unpolarized sky, two plastic spheres on a diffuse floor,
//! rolled camera; into `fig19_mitsuba/`) and, the paper's case, of
//! `scenes/mitsuba_polarized_sky.toml` (the polarized sky through a conductor, a
//! dielectric and a plastic sphere, Mitsuba emitting it through psh's plugin; into
//! `fig19_mitsuba_polarized/`).

use super::{Comparison, FigureOptions, Outcome, Table};
use crate::apps::bench_error::{bench_error, BenchErrorOptions, BenchErrorReport};
use crate::error::Result;
use crate::io::{load_scene, write_text};
use crate::pprt::builtin_scene;
use crate::progress::Silent;
use std::path::Path;

/// Image size, top band limit, rays per vertex, reference samples and ground-truth
/// samples; the second of each with `--quick`.
const SIZE: [(usize, usize); 2] = [(160, 120), (64, 48)];
const L_MAX: [usize; 2] = [9, 5];
const RAYS: [usize; 2] = [256, 64];
const SPP: [&[usize]; 2] = [&[1, 4, 16, 64, 256], &[1, 4, 16]];
const TRUTH_SPP: [usize; 2] = [2048, 256];
/// The scenes both renderers express identically: name (the output directory's suffix)
/// and file; and Mitsuba's samples per pixel.
const MITSUBA_SCENES: [(&str, &str); 2] = [
    ("", include_str!("../../scenes/mitsuba_sky.toml")),
    (
        "_polarized",
        include_str!("../../scenes/mitsuba_polarized_sky.toml"),
    ),
];
const MITSUBA_SPP: [usize; 2] = [1024, 256];

pub fn run(out: &Path, options: &FigureOptions) -> Result<Outcome> {
    let q = usize::from(options.quick);
    let scene = builtin_scene(L_MAX[q], SIZE[q].0, SIZE[q].1)?;
    let dir = out.join("fig19");
    let bench = |scene: &crate::pprt::Scene, rays, truth, dir: &Path| {
        bench_error(
            scene,
            &BenchErrorOptions {
                l_max: L_MAX[q],
                rays,
                spp: SPP[q].to_vec(),
                ground_truth_spp: TRUTH_SPP[q],
                ground_truth: truth,
            },
            dir,
            &Silent,
        )
    };
    let report = bench(&scene, RAYS[q], None, &dir)?;
    let mut table = Table::new(&[
        "ground truth",
        "method",
        "setting",
        "l_max",
        "spp",
        "frame (ms)",
        "RMSE s0",
        "s1",
        "s2",
        "s3",
    ]);
    let ext = crate::apps::plot::plot_format().extension();
    let mut pictures = vec![
        dir.join(format!("fig19.{ext}")),
        dir.join(format!("bench-error.{ext}")),
    ];
    let (mut measured, mut holds) = rows(&mut table, "psh reference, built-in scene", &report);
    for (suffix, text) in MITSUBA_SCENES.iter().filter(|_| options.mitsuba.is_some()) {
        let python = options.mitsuba.as_deref().expect("filtered");
        let dir = out.join(format!("fig19_mitsuba{suffix}"));
        let path = dir.join("scene.toml");
        std::fs::create_dir_all(&dir).map_err(|e| crate::Error::Io {
            path: dir.clone(),
            source: e,
        })?;
        write_text(&path, text)?;
        let (scene, settings) = load_scene(&path, L_MAX[q])?;
        let (truth, seconds) = super::mitsuba::render(python, &scene, MITSUBA_SPP[q], &dir)?;
        let report = bench(&scene, settings.rays, Some(truth), &dir.join("bench"))?;
        let name = format!("mitsuba{suffix}_sky");
        let (m, h) = rows(
            &mut table,
            &format!("Mitsuba 3, {} spp ({seconds:.1} s), {name}", MITSUBA_SPP[q]),
            &report,
        );
        measured += &format!("; against Mitsuba 3 on {name}: {m}");
        holds &= h;
        pictures.push(dir.join("bench").join(format!("fig19.{ext}")));
    }
    Ok(Outcome {
        pictures,
        table,
        comparison: Some(Comparison {
            measured,
            expected: "the error falls from l = 2 to the top band limit".into(),
            holds,
        }),
    })
}

/// `report`'s rows into `table` under `truth`; what PPRT `full`'s total RMSE does from
/// l = 2 to the top, and whether it falls.
fn rows(table: &mut Table, truth: &str, report: &BenchErrorReport) -> (String, bool) {
    for r in &report.rows {
        let opt = |x: Option<usize>| x.map_or("-".into(), |x| x.to_string());
        let mut row = vec![
            truth.to_string(),
            r.method.to_string(),
            r.setting.to_string(),
            opt(r.l_max),
            opt(r.spp),
            format!("{:.2}", r.frame_s * 1e3),
        ];
        row.extend(r.rmse.iter().map(|e| format!("{e:.4}")));
        table.row(row);
    }
    let full: Vec<(usize, f64)> = report
        .rows
        .iter()
        .filter(|r| r.method == "pprt" && r.setting == "full")
        .map(|r| (r.l_max.unwrap_or(0), r.total()))
        .collect();
    let ((l0, first), (l1, last)) = (full[0], full[full.len() - 1]);
    let speedup = report
        .speedup_at_equal_rmse
        .as_ref()
        .map_or("-".into(), |s| format!("{:.0}x", s.ratio));
    (
        format!(
            "PPRT full total RMSE {first:.4} at l = {l0}, {last:.4} at l = {l1}; speed-up at equal error {speedup}"
        ),
        last < first,
    )
}
