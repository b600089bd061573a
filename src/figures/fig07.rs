//! PSH Fig. 7: a polarized environment map (band-limited to l <= 32, the "original")
//! band-limited to a low degree under PSH (spin-2 SH for `s1 + i s2`, PSH (26)-(30)) and
//! under the naive basis (each theta-phi component on scalar SH): near the poles, where
//! the theta-phi frame field is singular, the naive basis leaves artefacts that the
//! spin-2 basis does not have.

use super::naive::naive_field;
use super::panels::{diverging_bar, signed_ticks};
use super::sponza::sponza_or_sky;
use super::{Comparison, FigureOptions, Outcome, Table};
use crate::error::Result;
use crate::geometry::{Equirect, PixelGrid, ThetaPhiFrameField};
use crate::io::{diverging, write_png_with_legend, Legend};
use crate::map::MapLayout;
use crate::polarized::reconstruct_image;
use std::path::Path;

/// The original's band limit, the low one, the picture height (width twice).
const SOURCE_LMAX: usize = 32;
const LMAX: usize = 6;
const HEIGHT: usize = 128;
/// The polar caps: within this angle of a pole (radians, 30 degrees).
const CAP: f64 = std::f64::consts::PI / 6.0;
/// The channel shown (green).
const CHANNEL: usize = 1;

pub fn run(out: &Path, _options: &FigureOptions) -> Result<Outcome> {
    let (v, source) = sponza_or_sky(SOURCE_LMAX)?;
    let MapLayout::Equirect(grid) = MapLayout::from_image_size(HEIGHT, 2 * HEIGHT)? else {
        unreachable!("a 1:2 image is equirectangular")
    };
    let field = ThetaPhiFrameField::new();
    let original = reconstruct_image(&v, &grid, &field)?;
    let psh = reconstruct_image(&v.truncated(LMAX)?, &grid, &field)?;
    let naive = naive_field(&v, LMAX, None, &grid)?;
    let mut table = Table::new(&[
        "basis",
        "l_max",
        "RMS error of s1, s2 within 30 deg of the poles",
        "elsewhere",
    ]);
    let mut caps = Vec::new();
    for (name, img) in [
        ("PSH (spin-2 SH)", &psh),
        ("naive (scalar SH per component)", &naive),
    ] {
        let (cap, rest) = rms_errors(&grid, img, &original);
        table.row(vec![
            name.into(),
            LMAX.to_string(),
            format!("{cap:.4e}"),
            format!("{rest:.4e}"),
        ]);
        caps.push(cap);
    }
    let c = CHANNEL;
    let lin = original[c]
        .iter()
        .fold(0.0f64, |m, s| m.max(s[1].abs()).max(s[2].abs()));
    let mut pictures = Vec::new();
    for p in [1, 2] {
        let panel = |img: &[Vec<[f64; 4]>]| -> Vec<[u8; 3]> {
            img[c].iter().map(|s| diverging(s[p] / lin)).collect()
        };
        let (rgb, total) = super::panels::side_by_side(
            &[panel(&original), panel(&psh), panel(&naive)],
            grid.width,
            grid.height,
        );
        let legend = Legend::bar(
            format!("s{p} in the theta-phi frame field ({source}, green channel), equirect"),
            &diverging_bar,
            signed_ticks(lin),
        )
        .panels(&[
            &format!("original, l <= {SOURCE_LMAX}"),
            &format!("PSH, l <= {LMAX}"),
            &format!("naive, l <= {LMAX}"),
        ]);
        let path = out.join(format!("fig07_s{p}.png"));
        write_png_with_legend(&path, &legend, total, grid.height, &rgb)?;
        pictures.push(path);
    }
    Ok(Outcome {
        pictures,
        table,
        comparison: Some(Comparison {
            measured: format!(
                "RMS error near the poles: PSH {:.2e}, naive {:.2e}",
                caps[0], caps[1]
            ),
            expected: "naive above PSH".into(),
            holds: caps[1] > caps[0],
        }),
    })
}

/// The RMS error of `s1`, `s2` of `img` against `original` (all channels, weighted by
/// solid angle) within [`CAP`] of the poles and elsewhere.
fn rms_errors(grid: &Equirect, img: &[Vec<[f64; 4]>], original: &[Vec<[f64; 4]>]) -> (f64, f64) {
    let mut sums = [[0.0; 2]; 2];
    for (a, b) in img.iter().zip(original) {
        for (i, (x, y)) in a.iter().zip(b).enumerate() {
            let theta = grid.direction(i)[2].clamp(-1.0, 1.0).acos();
            let k = usize::from(theta > CAP && theta < std::f64::consts::PI - CAP);
            let w = grid.solid_angle(i);
            sums[k][0] += w * ((x[1] - y[1]).powi(2) + (x[2] - y[2]).powi(2));
            sums[k][1] += w;
        }
    }
    let rms = |s: [f64; 2]| (s[0] / s[1]).sqrt();
    (rms(sums[0]), rms(sums[1]))
}
