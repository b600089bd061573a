//! PSH Figs. 20 and 21: the ablation of PPRT's terms on the built-in scene: the transfer
//! matrices `l <= l_low` alone, with triple-product shadows, and with the high orders by
//! convolution ([`ablation_job`], into `fig20/`); the panels side by side, one exposure.

use super::{FigureOptions, Outcome, Table};
use crate::apps::render_job::ablation_job;
use crate::error::Result;
use crate::pprt::builtin_scene;
use crate::pprt::settings::TransferSettings;
use crate::progress::Silent;
use std::path::Path;

/// Image size (the second with `--quick`).
const SIZE: [(usize, usize); 2] = [(480, 360), (160, 120)];

pub fn run(out: &Path, options: &FigureOptions) -> Result<Outcome> {
    let (w, h) = SIZE[usize::from(options.quick)];
    let settings = TransferSettings::default();
    let scene = builtin_scene(settings.environment_lmax(), w, h)?;
    let dir = out.join("fig20");
    let report = ablation_job(&scene, settings, &[], &dir, &Silent)?;
    let mut table = Table::new(&[
        "variant",
        "l_low",
        "l_high",
        "shadows",
        "precompute (s)",
        "frame (ms)",
    ]);
    for v in &report.variants {
        table.row(vec![
            v.variant.clone(),
            v.settings.l_low.to_string(),
            v.settings.l_high.to_string(),
            v.settings.shadows.to_string(),
            format!("{:.2}", v.times_s.precompute),
            format!("{:.1}", v.times_s.frame * 1e3),
        ]);
    }
    Ok(Outcome {
        pictures: report.pictures,
        table,
        comparison: None,
    })
}
