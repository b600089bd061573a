//! PSH Fig. 16: an environment map band-limited to l <= 8, convolved with the paper's
//! kernel `k(theta) = (pi - theta) I` in the angular domain (PSH (63), quadrature in polar
//! coordinates about each point of the exact grid) and in the frequency domain
//! (PSH (68), (69)); both timed, compared, and reconstructed as pictures.

use super::sponza::sponza_or_sky;
use super::{Comparison, FigureOptions, Outcome, Table};
use crate::error::Result;
use crate::io::write_map_pngs;
use crate::map::{MapLayout, StokesMap};
use crate::polarized::{
    convolve_angular, kernel_coefficients, Codomain, ConvolutionKernel, PshTransform,
};
use std::path::Path;
use std::time::Instant;

/// Band limit of the map (the angular-domain side costs `O(lmax^6)`; 4 with `--quick`).
const LMAX: [usize; 2] = [8, 4];
/// Polar quadrature order of the angular convolution (24 with `--quick`).
const POLAR: [usize; 2] = [48, 24];

pub fn run(out: &Path, options: &FigureOptions) -> Result<Outcome> {
    let quick = usize::from(options.quick);
    let lmax = LMAX[quick];
    let (map, source) = sponza_or_sky(lmax)?;
    let kernel = ConvolutionKernel::linear_zenith();

    let start = Instant::now();
    let freq = kernel_coefficients(&kernel, lmax)?.convolve(&map)?;
    let t_freq = start.elapsed().as_secs_f64();

    let start = Instant::now();
    let t = PshTransform::new(lmax)?;
    let g = t.grid();
    let points = (0..g.len())
        .map(|i| g.direction(i))
        .collect::<Result<Vec<_>>>()?;
    let channels = (0..map.channels())
        .map(|c| convolve_angular(&kernel, &map, c, &points, POLAR[quick]))
        .collect::<Result<Vec<_>>>()?;
    let refs: Vec<&[[f64; 4]]> = channels.iter().map(Vec::as_slice).collect();
    let angular = t.project_channels(&refs, Codomain::Full)?;
    let t_ang = start.elapsed().as_secs_f64();

    let scale = freq.data().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let diff = freq
        .data()
        .iter()
        .zip(angular.data())
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
        / scale;
    let layout = MapLayout::from_image_size(128, 256)?;
    let mut pictures = Vec::new();
    for (name, v) in [("input", &map), ("frequency", &freq), ("angular", &angular)] {
        pictures.extend(write_map_pngs(
            &StokesMap::reconstruct(v, layout.clone())?,
            out.join(format!("fig16_{name}")),
        )?);
    }
    let mut table = Table::new(&["map", "l_max", "domain", "time (ms)", "points"]);
    table.row(vec![
        source.clone(),
        lmax.to_string(),
        "frequency (PSH (69), coefficients included)".into(),
        format!("{:.3}", t_freq * 1e3),
        "-".into(),
    ]);
    table.row(vec![
        source,
        lmax.to_string(),
        "angular (PSH (63))".into(),
        format!("{:.1}", t_ang * 1e3),
        g.len().to_string(),
    ]);
    Ok(Outcome {
        pictures,
        table,
        comparison: Some(Comparison {
            measured: format!("largest coefficient difference, relative: {diff:.1e}"),
            expected: "<= 1e-10".into(),
            holds: diff <= 1e-10,
        }),
    })
}
