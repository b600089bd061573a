//! PSH Fig. 13: (a) the visibility `V` at a vertex (here the upper hemisphere with a
//! spherical occluder of angular radius 35 degrees, 50 degrees from the zenith), (b) its
//! real SH coefficients `v_lm`, (c) the shadowing operator's PSH matrix from triple
//! products: the spin 0-to-0 block by real Gaunt coefficients (PSH (55)), the spin 2-to-2
//! block by the spin-2 triple product (PSH (56)).

use super::panels::diverging_bar;
use super::{Comparison, FigureOptions, Outcome, Table};
use crate::apps::plot::{Axis, LinePlot, Series, Stroke};
use crate::error::Result;
use crate::geometry::{direction, PixelGrid};
use crate::io::{diverging, srgb8, write_matrix_png, write_png_with_legend, Legend};
use crate::map::MapLayout;
use crate::polarized::{visibility_transfer, visibility_transfer_quadrature, PshVector};
use crate::sh::{lm_of_index, num_coeffs, ShEvaluator, ShTransform};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

/// The transfer's band limit and the visibility's (PSH uses `2 l_low`).
const LMAX: usize = 4;
const LV: usize = 2 * LMAX;
/// The band of the grid that projects the (discontinuous) visibility.
const GRID: usize = 512;
/// The occluder: its centre's polar angle and its angular radius (radians).
const OCCLUDER: (f64, f64) = (50.0 * PI / 180.0, 35.0 * PI / 180.0);

/// `V(w)`: above the horizon and outside the occluder.
fn visible(w: [f64; 3]) -> bool {
    let c = direction(OCCLUDER.0, 0.0);
    let cos = w[0] * c[0] + w[1] * c[1] + w[2] * c[2];
    w[2] > 0.0 && cos < OCCLUDER.1.cos()
}

pub fn run(out: &Path, _options: &FigureOptions) -> Result<Outcome> {
    let v = visibility_coefficients()?;
    let visibility = visibility_panel(out, &v)?;
    let coefficients = coefficient_panel(out, &v)?;
    // (c) the matrix by triple products, and by direct quadrature of PSH (54).
    let m = visibility_transfer(&v, LMAX)?;
    let q = visibility_transfer_quadrature(&v, LMAX)?;
    let against_quadrature = m
        .data()
        .iter()
        .zip(q.data())
        .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
    let nm = num_coeffs(LMAX);
    let mut pictures = vec![visibility, coefficients];
    for (name, p) in [("fig13c_spin0_block.png", 0), ("fig13c_spin2_block.png", 1)] {
        let block: Vec<f64> = (0..nm * nm).map(|k| m.get(k / nm, k % nm, p, p)).collect();
        let path = out.join(name);
        write_matrix_png(&path, &block, nm, 12, true)?;
        pictures.push(path);
    }
    // M_00,00 = int V / (4 pi): the visible solid angle, in closed form 2 pi cos(radius)
    // (the hemisphere less the occluder's cap, which lies wholly above the horizon).
    let solid_angle = 4.0 * PI * m.get(0, 0, 0, 0);
    let closed_form = 2.0 * PI * OCCLUDER.1.cos();
    let relative = (solid_angle - closed_form).abs() / closed_form;
    let mut table = Table::new(&["quantity", "value"]);
    table.row(vec![
        "visible solid angle from M_00,00 (sr)".into(),
        format!("{solid_angle:.6}"),
    ]);
    table.row(vec![
        "closed form 2 pi cos(35 deg) (sr)".into(),
        format!("{closed_form:.6}"),
    ]);
    table.row(vec![
        format!("their relative difference (the indicator's edge on the exact grid of band {GRID}: O(1/band), 3e-2 at band 64)"),
        format!("{relative:.2e}"),
    ]);
    table.row(vec![
        "triple products against quadrature of PSH (54), max |difference|".into(),
        format!("{against_quadrature:.2e}"),
    ]);
    for l in 0..=LV {
        let e: f64 = (l * l..(l + 1) * (l + 1))
            .map(|k| v.data()[k].powi(2))
            .sum();
        table.row(vec![
            format!("sum over m of v_lm^2, l = {l}"),
            format!("{e:.5e}"),
        ]);
    }
    Ok(Outcome {
        pictures,
        table,
        comparison: Some(Comparison {
            measured: format!(
                "visible solid angle {relative:.1e} from the closed form, triple products {against_quadrature:.1e} from quadrature"
            ),
            expected: "<= 1e-2 and <= 1e-12".into(),
            holds: relative <= 1e-2 && against_quadrature <= 1e-12,
        }),
    })
}

/// (b)'s coefficients `v_lm`, `l <= LV`, by quadrature on a fine exact grid (exact for
/// the polynomial part; the indicator's edge limits it).
fn visibility_coefficients() -> Result<PshVector> {
    let t = ShTransform::new(GRID)?;
    let grid = t.grid();
    let values = (0..grid.len())
        .map(|i| Ok(f64::from(u8::from(visible(grid.direction(i)?)))))
        .collect::<Result<Vec<_>>>()?;
    let mut all = vec![0.0; num_coeffs(t.lmax())];
    t.analysis_real(&values, &mut all)?;
    PshVector::scalar(LV, all[..num_coeffs(LV)].to_vec())
}

/// (a) V and its band-limited reconstruction from `v`, side by side.
fn visibility_panel(out: &Path, v: &PshVector) -> Result<PathBuf> {
    let MapLayout::Equirect(eq) = MapLayout::from_image_size(128, 256)? else {
        unreachable!("a 1:2 image is equirectangular")
    };
    let eval = ShEvaluator::new(LV)?;
    let n = num_coeffs(LV);
    let dirs: Vec<[f64; 3]> = (0..eq.len()).map(|i| eq.direction(i)).collect();
    let mut basis = vec![0.0; dirs.len() * n];
    eval.real_batch(&dirs, &mut basis)?;
    let exact: Vec<[u8; 3]> = dirs
        .iter()
        .map(|&w| [srgb8(f64::from(u8::from(visible(w)))); 3])
        .collect();
    let limited: Vec<[u8; 3]> = basis
        .chunks_exact(n)
        .map(|y| {
            let x: f64 = y.iter().zip(v.data()).map(|(a, b)| a * b).sum();
            diverging(2.0 * x - 1.0)
        })
        .collect();
    let (rgb, total) = super::panels::side_by_side(&[exact, limited], eq.width, eq.height);
    let legend = Legend::bar(
        format!("(a) visibility V (left, black 0, white 1) and its SH cut to l <= {LV} (right)"),
        &diverging_bar,
        vec![(0.0, "0".into()), (0.5, "0.5".into()), (1.0, "1".into())],
    )
    .panels(&["V", &format!("sum v_lm Y_lm, l <= {LV}")]);
    let visibility = out.join("fig13a_visibility.png");
    write_png_with_legend(&visibility, &legend, total, eq.height, &rgb)?;
    Ok(visibility)
}

/// (b) the coefficients `v` as stems, one per `(l, m)`, in flat order.
fn coefficient_panel(out: &Path, v: &PshVector) -> Result<PathBuf> {
    let n = num_coeffs(LV);
    let vmax = v.data().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut plot = LinePlot::new(
        &format!("(b) visibility's SH coefficients v_lm, l <= {LV}"),
        Axis::integer("flat index l*l + l + m", (-0.5, n as f64 - 0.5)),
        Axis::linear("v_lm", (-1.1 * vmax, 1.1 * vmax)),
    )?;
    for (parity, label, color) in [(0, "even l", [60, 90, 170]), (1, "odd l", [200, 80, 40])] {
        plot.add(Series {
            label: label.into(),
            color,
            stroke: Stroke::Stems,
            points: (0..n)
                .filter(|&k| lm_of_index(k).0 % 2 == parity)
                .map(|k| (k as f64, v.data()[k]))
                .collect(),
        });
    }
    plot.write(out.join("fig13b_coefficients"), 720, 360)
}
