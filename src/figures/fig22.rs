//! PSH Fig. 22: a PPRT render (the built-in scene with its sun as a lobe of the sky, which
//! rings at the band limit, [`Sun::Lobe`]) projected pixel by pixel onto the physically valid range PSH (70),
//! `s0 >= |(s1, s2, s3)|`: the pixels breaking it are counted before and after, and the
//! projection keeps the angle of linear polarization and never darkens `s0`.

use super::{Comparison, FigureOptions, Outcome, Table};
use crate::error::Result;
use crate::io::{write_stokes_pngs, PictureNotes};
use crate::pprt::plan::Plan;
use crate::pprt::render::{direct_light, primary_hits, render_frame, UnphysicalPixels};
use crate::pprt::settings::{Planning, TransferSettings};
use crate::pprt::transfer::precompute_planned;
use crate::pprt::{builtin_scene, Sun};
use crate::progress::Silent;
use std::path::Path;

/// Image size (half with `--quick`).
const SIZE: [(usize, usize); 2] = [(320, 240), (160, 120)];

pub fn run(out: &Path, options: &FigureOptions) -> Result<Outcome> {
    let (w, h) = SIZE[usize::from(options.quick)];
    let settings = TransferSettings::default();
    let scene = builtin_scene(settings.environment_lmax(), w, h)?.with_sun(Sun::Lobe)?;
    let plan = Plan::with_progress(&scene, settings, Planning::Full, &Silent)?;
    let transfer = precompute_planned(&scene, &plan, &Silent)?;
    let hits = primary_hits(&scene);
    let direct = direct_light(&scene, &hits)?;
    let before = render_frame(&scene, &transfer, &plan.high_fields(), &hits, &direct)?;
    let mut after = before.clone();
    after.to_nearest_physical()?;
    let (count_before, count_after) = (before.unphysical(), after.unphysical());

    // What the projection keeps: the AoLP wherever there is linear polarization, and
    // s0 never lower.
    let (mut aolp, mut darker) = (0.0f64, 0.0f64);
    for (a, b) in before
        .channels
        .iter()
        .flatten()
        .zip(after.channels.iter().flatten())
    {
        darker = darker.max(a[0] - b[0]);
        let (za, zb) = (a[1].hypot(a[2]), b[1].hypot(b[2]));
        if za > 1e-9 && zb > 1e-9 {
            let cross = a[1] * b[2] - a[2] * b[1];
            let dot = a[1] * b[1] + a[2] * b[2];
            aolp = aolp.max(0.5 * cross.atan2(dot).abs());
        }
    }
    let mut pictures = Vec::new();
    let on = vec![true; w * h];
    for (name, image) in [("before", &before), ("after", &after)] {
        let notes = PictureNotes {
            title: if name == "before" {
                "PPRT, no projection"
            } else {
                "PPRT projected onto PSH (70)"
            },
            frames: "camera frames (x right, y up)",
            panels: &[],
        };
        pictures.extend(write_stokes_pngs(
            &image.channels,
            &on,
            None,
            w,
            h,
            notes,
            out.join(format!("fig22_{name}")),
        )?);
    }
    let mut table = Table::new(&[
        "image",
        "pixels with s0 < 0 (R, G, B)",
        "pixels with DoP > 1 (R, G, B)",
    ]);
    for (name, c) in [("before", &count_before), ("after", &count_after)] {
        table.row(vec![name.into(), sum(c, true), sum(c, false)]);
    }
    table.row(vec![
        "largest AoLP change (rad), largest s0 decrease".into(),
        format!("{aolp:.2e}"),
        format!("{darker:.2e}"),
    ]);
    let left = total(&count_after);
    Ok(Outcome {
        pictures,
        table,
        comparison: Some(Comparison {
            measured: format!(
                "{} unphysical pixels before, {left} after; AoLP changed by {aolp:.1e} rad, s0 lowered by {darker:.1e}",
                total(&count_before)
            ),
            expected: "none after, AoLP <= 1e-12, s0 never lowered".into(),
            holds: left == 0 && aolp <= 1e-12 && darker <= 0.0,
        }),
    })
}

/// The counts of `s0 < 0` (`negative`) or of DoP > 1, surface and sky, per channel.
fn sum(c: &UnphysicalPixels, negative: bool) -> String {
    let (a, b) = if negative {
        (c.surface_s0_negative, c.sky_s0_negative)
    } else {
        (c.surface_dop_above_one, c.sky_dop_above_one)
    };
    format!("{}, {}, {}", a[0] + b[0], a[1] + b[1], a[2] + b[2])
}

fn total(c: &UnphysicalPixels) -> usize {
    [
        c.surface_s0_negative,
        c.sky_s0_negative,
        c.surface_dop_above_one,
        c.sky_dop_above_one,
    ]
    .iter()
    .flatten()
    .sum()
}
