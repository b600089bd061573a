//! PSH Fig. 5: one Stokes vector field (a polarized environment map) seen through two
//! frame fields, the theta-phi frame field (PSH Fig. 5(b), (d)) and the perspective frame
//! field of Mitsuba 3 (PSH Fig. 5(e); [`PerspectiveFrameField`]): the components `s1`,
//! `s2` (PSH (15)) differ, while the Stokes vectors they stand for are one field: read in
//! the other frame by PSH (14), each pixel's components agree to rounding.

use super::ellipses::{SegmentPanel, SEGMENT};
use super::panels::side_by_side;
use super::panels::{diverging_bar, signed_ticks};
use super::sponza::sponza_or_sky;
use super::{Comparison, FigureOptions, Outcome, Table};
use crate::error::Result;
use crate::geometry::{FrameField, PerspectiveFrameField, PixelGrid, ThetaPhiFrameField};
use crate::io::{diverging, srgb8, tick_label, write_png_with_legend, Legend};
use crate::map::MapLayout;
use crate::polarized::reconstruct_image;
use crate::sh::Window;
use crate::stokes::FrameChange;
use num_complex::Complex64;
use std::path::Path;

/// Band limit of the map (Hann-windowed, [`Window::Hann`], against ringing), the height
/// of the component panels and of the field picture (widths twice).
const LMAX: usize = 16;
const HEIGHT: usize = 120;
const FIELD_HEIGHT: usize = 240;
/// The channel shown (green).
const CHANNEL: usize = 1;

pub fn run(out: &Path, _options: &FigureOptions) -> Result<Outcome> {
    let (v, source) = sponza_or_sky(LMAX)?;
    let v = v.windowed(Window::Hann);
    let MapLayout::Equirect(grid) = MapLayout::from_image_size(HEIGHT, 2 * HEIGHT)? else {
        unreachable!("a 1:2 image is equirectangular")
    };
    let (w, h) = (grid.width, grid.height);
    let theta_phi = ThetaPhiFrameField::new();
    let perspective = PerspectiveFrameField::look([1.0, 0.0, 0.0], [0.0, 0.0, 1.0])?;
    let a = &reconstruct_image(&v, &grid, &theta_phi)?[CHANNEL];
    let b = &reconstruct_image(&v, &grid, &perspective)?[CHANNEL];
    // The same Stokes vectors: b's components read in a's frames (PSH (14)).
    let (mut same, mut differ, mut scale) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..grid.len() {
        let d = grid.direction(i);
        let change = FrameChange::between(&perspective.frame(d)?, &theta_phi.frame(d)?)?;
        let read = change.components(b[i]);
        for p in 0..4 {
            same = same.max((read[p] - a[i][p]).abs());
            differ = differ.max((b[i][p] - a[i][p]).abs());
            scale = scale.max(a[i][p].abs());
        }
    }
    let (same, differ) = (same / scale, differ / scale);
    let lin = a
        .iter()
        .fold(0.0f64, |m, s| m.max(s[1].abs()).max(s[2].abs()));
    let signed = |img: &[[f64; 4]], p: usize| -> Vec<[u8; 3]> {
        img.iter().map(|s| diverging(s[p] / lin)).collect()
    };
    let (rgb, total) = side_by_side(
        &[signed(a, 1), signed(a, 2), signed(b, 1), signed(b, 2)],
        w,
        h,
    );
    let legend = Legend::bar(
        format!("Stokes components of one field ({source}, green channel, l <= {LMAX}, Hann window), equirect"),
        &diverging_bar,
        signed_ticks(lin),
    )
    .panels(&[
        "s1, theta-phi frames",
        "s2, theta-phi frames",
        "s1, perspective frames",
        "s2, perspective frames",
    ]);
    let components = out.join("fig05_components.png");
    write_png_with_legend(&components, &legend, total, h, &rgb)?;

    let MapLayout::Equirect(big) = MapLayout::from_image_size(FIELD_HEIGHT, 2 * FIELD_HEIGHT)?
    else {
        unreachable!("a 1:2 image is equirectangular")
    };
    let f = &reconstruct_image(&v, &big, &theta_phi)?[CHANNEL];
    let (fw, fh) = (big.width, big.height);
    let s0max = f.iter().fold(0.0f64, |m, s| m.max(s[0]));
    let step = fw as f64 / 48.0;
    let panel = SegmentPanel {
        width: fw,
        height: fh,
        rgb: f.iter().map(|s| [srgb8(s[0] / s0max); 3]).collect(),
        samples: (0..24)
            .flat_map(|i| (0..48).map(move |j| ((j as f64 + 0.5) * step, (i as f64 + 0.5) * step)))
            .map(|(x, y)| {
                let k = (y as usize).min(fh - 1) * fw + (x as usize).min(fw - 1);
                ((x, y), Complex64::new(f[k][1], f[k][2]))
            })
            .collect(),
    };
    let shade = |t: f64| [srgb8(t); 3];
    let legend = Legend::bar(
        "The field itself: s0 (grey) and the linear polarization (segments), in any frame field",
        &shade,
        vec![(0.0, "0".into()), (1.0, tick_label(s0max))],
    )
    .flag(
        SEGMENT,
        "along the AoLP, length |s1 + i s2| (theta down, phi right)",
    );
    let field = out.join("fig05_field.png");
    write_png_with_legend(&field, &legend, fw, fh, &panel.draw(0.95 * step, lin)?)?;

    let mut table = Table::new(&[
        "quantity",
        "largest difference over pixels and components, relative to the largest component",
    ]);
    table.row(vec![
        "components in theta-phi frames minus perspective frames".into(),
        format!("{differ:.3e}"),
    ]);
    table.row(vec![
        "the same, after reading the perspective ones in theta-phi frames (PSH (14))".into(),
        format!("{same:.3e}"),
    ]);
    Ok(Outcome {
        pictures: vec![components, field],
        table,
        comparison: Some(Comparison {
            measured: format!("components differ by {differ:.1e}, Stokes vectors by {same:.1e}"),
            expected: "components >= 1e-2, Stokes vectors <= 1e-13".into(),
            holds: differ >= 1e-2 && same <= 1e-13,
        }),
    })
}
