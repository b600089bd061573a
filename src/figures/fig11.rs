//! PSH Fig. 11: a polarized map band-limited to l <= 16, rotated in the frequency domain
//! (PSH (35)-(37)) and reconstructed, against the same band-limited map rotated in the
//! angular domain (PSH (25)); and the naive rotation of the theta-phi components.

use super::fig10::ROTVEC;
use super::naive::naive_field;
use super::panels::{diverging_bar, signed_ticks};
use super::sponza::sponza_or_sky;
use super::{Comparison, FigureOptions, Outcome, Table};
use crate::error::Result;
use crate::geometry::PixelGrid;
use crate::geometry::{rotation_from_rotvec, Rotated, ThetaPhiFrameField};
use crate::io::{diverging, write_map_pngs, write_png_with_legend, Legend};
use crate::map::{MapLayout, StokesMap};
use crate::polarized::{reconstruct_image, PshRotation};
use std::path::Path;

/// Band limit of the map (8 with `--quick`).
const LMAX: [usize; 2] = [16, 8];
/// Picture size, height x width (half with `--quick`).
const SIZE: [(usize, usize); 2] = [(128, 256), (64, 128)];

pub fn run(out: &Path, options: &FigureOptions) -> Result<Outcome> {
    let r = &rotation_from_rotvec(ROTVEC)?;
    let quick = usize::from(options.quick);
    let lmax = LMAX[quick];
    let (v, source) = sponza_or_sky(lmax)?;
    let layout = MapLayout::from_image_size(SIZE[quick].0, SIZE[quick].1)?;
    let MapLayout::Equirect(grid) = layout.clone() else {
        unreachable!("a 1:2 image is equirectangular")
    };
    let field = ThetaPhiFrameField::new();
    // Frequency domain: rotate the coefficients, reconstruct.
    let rotated = PshRotation::new(r, lmax)?.rotate(&v)?;
    let freq = StokesMap::reconstruct(&rotated, layout.clone())?;
    // Angular domain: the band-limited field at R^-1 w_i, frames R^-1 F(w_i) (PSH (25)).
    let q = r.inverse();
    let angular = StokesMap::new(
        layout.clone(),
        reconstruct_image(&v, &Rotated::new(grid.clone(), q), &Rotated::new(field, q))?,
    )?;
    let naive = StokesMap::new(layout.clone(), naive_field(&v, lmax, Some(r), &grid)?)?;
    let scale = max_abs(&angular);
    let err_psh = max_diff(&freq, &angular) / scale;
    let err_naive = max_diff(&naive, &angular) / scale;
    let mut pictures = Vec::new();
    for (name, map) in [("angular", &angular), ("psh", &freq), ("naive", &naive)] {
        pictures.extend(write_map_pngs(map, out.join(format!("fig11_{name}")))?);
    }
    for (name, map) in [("psh", &freq), ("naive", &naive)] {
        for p in [1, 2] {
            let rgb: Vec<[u8; 3]> = (0..grid.len())
                .map(|i| {
                    let d = map.channels()[1][i][p] - angular.channels()[1][i][p];
                    diverging(d / (0.1 * scale))
                })
                .collect();
            let path = out.join(format!("fig11_{name}_minus_angular_s{p}.png"));
            let legend = Legend::bar(
                format!("s{p} ({name}) - s{p} (angular), green channel"),
                &diverging_bar,
                signed_ticks(0.1 * scale),
            );
            write_png_with_legend(&path, &legend, grid.width, grid.height, &rgb)?;
            pictures.push(path);
        }
    }
    let mut table = Table::new(&[
        "map",
        "l_max",
        "rotation",
        "max |difference| / max |s| against the angular rotation",
    ]);
    for (name, e) in [
        ("PSH (35)-(37)", err_psh),
        ("naive, per component", err_naive),
    ] {
        table.row(vec![
            source.clone(),
            lmax.to_string(),
            name.into(),
            format!("{e:.2e}"),
        ]);
    }
    Ok(Outcome {
        pictures,
        table,
        comparison: Some(Comparison {
            measured: format!("PSH {err_psh:.1e}, naive {err_naive:.1e}"),
            expected: "PSH <= 1e-12, naive >= 1e-2".into(),
            holds: err_psh <= 1e-12 && err_naive >= 1e-2,
        }),
    })
}

fn max_abs(m: &StokesMap) -> f64 {
    m.channels()
        .iter()
        .flatten()
        .flatten()
        .fold(0.0f64, |a, x| a.max(x.abs()))
}

fn max_diff(a: &StokesMap, b: &StokesMap) -> f64 {
    a.channels()
        .iter()
        .flatten()
        .zip(b.channels().iter().flatten())
        .flat_map(|(x, y)| (0..4).map(move |p| (x[p] - y[p]).abs()))
        .fold(0.0f64, f64::max)
}
