//! PSH Fig. 19: PPRT's error against a high-sample ground truth of psh's reference
//! renderer falling with the band limit, and run time against error beside the reference
//! ([`bench_error`] on the built-in scene, into `fig19/`). Mitsuba 3's side of the figure
//! is `validation/test_mitsuba_render.py` (`docs/mitsuba.md`).

use super::{Comparison, FigureOptions, Outcome, Table};
use crate::apps::bench_error::{bench_error, BenchErrorOptions};
use crate::error::Result;
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

pub fn run(out: &Path, options: &FigureOptions) -> Result<Outcome> {
    let q = usize::from(options.quick);
    let scene = builtin_scene(L_MAX[q], SIZE[q].0, SIZE[q].1)?;
    let dir = out.join("fig19");
    let report = bench_error(
        &scene,
        &BenchErrorOptions {
            l_max: L_MAX[q],
            rays: RAYS[q],
            spp: SPP[q].to_vec(),
            ground_truth_spp: TRUTH_SPP[q],
            ground_truth: None,
        },
        &dir,
        &Silent,
    )?;
    let mut table = Table::new(&[
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
    for r in &report.rows {
        let opt = |x: Option<usize>| x.map_or("-".into(), |x| x.to_string());
        let mut row = vec![
            r.method.to_string(),
            r.setting.to_string(),
            opt(r.l_max),
            opt(r.spp),
            format!("{:.2}", r.frame_s * 1e3),
        ];
        row.extend(r.rmse.iter().map(|e| format!("{e:.4}")));
        table.row(row);
    }
    let full: Vec<f64> = report
        .rows
        .iter()
        .filter(|r| r.method == "pprt" && r.setting == "full")
        .map(|r| r.total())
        .collect();
    let (first, last) = (full[0], full[full.len() - 1]);
    let speedup = report
        .speedup_at_equal_rmse
        .as_ref()
        .map_or("-".into(), |s| format!("{:.0}x", s.ratio));
    Ok(Outcome {
        pictures: vec![dir.join("fig19.png"), dir.join("bench-error.png")],
        table,
        comparison: Some(Comparison {
            measured: format!(
                "PPRT full total RMSE {first:.4} at l = 2, {last:.4} at l = {}; speed-up at equal error {speedup}",
                L_MAX[q]
            ),
            expected: "the error falls from l = 2 to the top band limit".into(),
            holds: last < first,
        }),
    })
}
