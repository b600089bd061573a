//! PSH Fig. 8: the spin-2 spherical harmonics of degree 2 (PSH (26), (27)) as fields of
//! linear polarization `s1 + i s2 = 2Y_2m` in the theta-phi frame field, one equirect
//! panel per `m`, with `|2Y_2m|` in grey under the segments; and their values at the
//! poles, where a spin-2 field can be nonzero only for `m = -s` (north) and `m = s`
//! (south): there `|sY_l,-+s| = sqrt((2l + 1) / (4 pi))`.

use super::ellipses::{SegmentPanel, SEGMENT};
use super::panels::side_by_side;
use super::{Comparison, FigureOptions, Outcome, Table};
use crate::error::Result;
use crate::io::{srgb8, tick_label, write_png_with_legend, Legend};
use crate::sh::lm_index;
use crate::swsh::swsh;
use std::f64::consts::PI;
use std::path::Path;

/// Panel size (width = 2 height) and segments per row of samples.
const HEIGHT: usize = 120;
const SAMPLES: usize = 12;

pub fn run(out: &Path, _options: &FigureOptions) -> Result<Outcome> {
    let (w, h) = (2 * HEIGHT, HEIGHT);
    // The largest |2Y_2m| is at the poles (m = -+2): sqrt(5 / (4 pi)).
    let peak = (5.0 / (4.0 * PI)).sqrt();
    let value =
        |m: i64, theta: f64, phi: f64| -> Result<_> { Ok(swsh(2, 2, theta, phi)?[lm_index(2, m)]) };
    let angles = |x: f64, y: f64| (PI * y / h as f64, 2.0 * PI * x / w as f64);
    let mut panels = Vec::new();
    let mut table = Table::new(&[
        "m",
        "|2Y_2m| at the north pole",
        "|2Y_2m| at the south pole",
    ]);
    let mut pole_error = 0.0f64;
    for m in -2..=2i64 {
        let mut rgb = Vec::with_capacity(w * h);
        for y in 0..h {
            for x in 0..w {
                let (theta, phi) = angles(x as f64 + 0.5, y as f64 + 0.5);
                rgb.push([srgb8(0.15 + 0.6 * value(m, theta, phi)?.norm() / peak); 3]);
            }
        }
        let step = w as f64 / (2 * SAMPLES) as f64;
        let mut samples = Vec::new();
        for i in 0..SAMPLES {
            for j in 0..2 * SAMPLES {
                let (x, y) = ((j as f64 + 0.5) * step, (i as f64 + 0.5) * step);
                let (theta, phi) = angles(x, y);
                samples.push(((x, y), value(m, theta, phi)?));
            }
        }
        let panel = SegmentPanel {
            width: w,
            height: h,
            rgb,
            samples,
        };
        panels.push(panel.draw(0.9 * step, peak)?);
        let (north, south) = (value(m, 0.0, 0.0)?.norm(), value(m, PI, 0.0)?.norm());
        // PSH Fig. 8: nonzero at the north pole for m = -2 only, the south for m = 2 only.
        let expected = |nonzero: bool| if nonzero { peak } else { 0.0 };
        pole_error = pole_error
            .max((north - expected(m == -2)).abs())
            .max((south - expected(m == 2)).abs());
        table.row(vec![
            m.to_string(),
            format!("{north:.15}"),
            format!("{south:.15}"),
        ]);
    }
    let (rgb, total) = side_by_side(&panels, w, h);
    let shade = |t: f64| [srgb8(0.15 + 0.6 * t); 3];
    let legend = Legend::bar(
        "2Y_2m as s1 + i s2 in the theta-phi frame field: |2Y_2m| (grey), segments along the AoLP, length |2Y_2m|",
        &shade,
        vec![(0.0, "0".into()), (1.0, tick_label(peak))],
    )
    .panels(&["m = -2", "m = -1", "m = 0", "m = 1", "m = 2"])
    .flag(SEGMENT, "linear polarization (theta down, phi right; phi = 0 at the left edge)");
    let path = out.join("fig08_spin2_l2.png");
    write_png_with_legend(&path, &legend, total, h, &rgb)?;
    Ok(Outcome {
        pictures: vec![path],
        table,
        comparison: Some(Comparison {
            measured: format!("largest deviation of |2Y_2m| at the poles from the paper's pattern: {pole_error:.1e}"),
            expected: "<= 1e-14 (north: sqrt(5/(4 pi)) for m = -2 only; south: for m = 2 only)"
                .into(),
            holds: pole_error <= 1e-14,
        }),
    })
}
