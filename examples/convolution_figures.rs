//! PSH Figs. 16 and 17 reproduced numerically, with PNG pictures (`docs/worked-example.md`):
//!
//! ```text
//! cargo run --release --example convolution_figures -- [output directory, default target/figures]
//! ```
//!
//! Fig. 16: a real environment map (`sponza_64` from the shared data; a synthetic
//! band-limited map when the data is absent), band-limited to l <= 8, convolved with the
//! paper's kernel `k(theta) = (pi - theta) I` in the angular domain (PSH (63), quadrature in
//! polar coordinates about each point of the exact grid) and in the frequency domain
//! (PSH (69)); both timed, compared, and reconstructed as pictures.
//! Fig. 17: a polarized plastic pBRDF (PSH coefficient matrix, l <= 4) averaged over
//! rotations on Euler grids of resolution n = 1..7; the residual of its projection onto
//! the convolutions against n, as a table and a PNG plot. The example fails (non-zero
//! exit) if the two convolutions differ by more than 1e-10 or the residual does not
//! reach 1e-12 at n = lmax + 1.

#[path = "common/sponza.rs"]
mod sponza;
use psh::apps::plot::{Axis, LinePlot, Series};
use psh::io::write_map_pngs;
use psh::map::{MapLayout, StokesMap};
use psh::optics::PolarizedPlastic;
use psh::polarized::{
    convolve_angular, kernel_coefficients, project_operator, project_to_convolution,
    rotation_average, Codomain, ConvolutionKernel, PshTransform, SpinBlock22,
};
use sponza::sponza_or_synthetic;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Band limit of Fig. 16's map (the angular-domain side costs `O(lmax^6)`).
const FIG16_LMAX: usize = 8;
/// Band limit of Fig. 17's pBRDF matrix.
const FIG17_LMAX: usize = 4;

fn main() -> psh::Result<()> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "target/figures".into()),
    );
    std::fs::create_dir_all(&out).map_err(|e| psh::Error::Io {
        path: out.clone(),
        source: e,
    })?;
    let fig16 = figure16(&out)?;
    let fig17 = figure17(&out)?;
    println!("pictures written to {}", out.display());
    if fig16 > 1e-10 || fig17 > 1e-12 {
        eprintln!(
            "comparison failed: Fig. 16 difference {fig16:e}, Fig. 17 final residual {fig17:e}"
        );
        std::process::exit(1);
    }
    Ok(())
}

/// Returns the largest relative difference of the two convolutions.
fn figure16(out: &Path) -> psh::Result<f64> {
    let lmax = FIG16_LMAX;
    let (map, source) = sponza_or_synthetic(lmax)?;
    println!("Fig. 16: k = (pi - theta) I on {source}, l <= {lmax}, RGB");
    let kernel = ConvolutionKernel::linear_zenith();

    let start = Instant::now();
    let k = kernel_coefficients(&kernel, lmax)?;
    let freq = k.convolve(&map)?;
    let t_freq = start.elapsed();

    let start = Instant::now();
    let t = PshTransform::new(lmax)?;
    let g = t.grid();
    let points = (0..g.len())
        .map(|i| g.direction(i))
        .collect::<psh::Result<Vec<_>>>()?;
    let channels = (0..map.channels())
        .map(|c| convolve_angular(&kernel, &map, c, &points, 48))
        .collect::<psh::Result<Vec<_>>>()?;
    let refs: Vec<&[[f64; 4]]> = channels.iter().map(Vec::as_slice).collect();
    let angular = t.project_channels(&refs, Codomain::Full)?;
    let t_ang = start.elapsed();

    let scale = freq.data().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let diff = freq
        .data()
        .iter()
        .zip(angular.data())
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
        / scale;
    println!(
        "  frequency domain {:.3} ms (coefficients included), angular domain {:.1} ms on {} points",
        t_freq.as_secs_f64() * 1e3,
        t_ang.as_secs_f64() * 1e3,
        g.len()
    );
    println!("  largest coefficient difference, relative: {diff:.2e}");
    let layout = MapLayout::from_image_size(128, 256)?;
    for (name, v) in [("input", &map), ("frequency", &freq), ("angular", &angular)] {
        let files = write_map_pngs(
            &StokesMap::reconstruct(v, layout.clone())?,
            out.join(format!("fig16_{name}")),
        )?;
        println!("  {name}: {} pictures (fig16_{name}_*.png)", files.len());
    }
    Ok(diff)
}

/// Returns the residual at `n = lmax + 1`.
fn figure17(out: &Path) -> psh::Result<f64> {
    let lmax = FIG17_LMAX;
    let brdf = PolarizedPlastic::new(0.3, 1.5, 0.5)?;
    let m = project_operator(&brdf, lmax, 2 * lmax, SpinBlock22::ComplexPair)?;
    let (_, raw) = project_to_convolution(&m)?;
    println!("Fig. 17: polarized plastic (alpha 0.3, n 1.5, albedo 0.5), l <= {lmax}");
    println!("  residual of the pBRDF itself: {raw:.3e}");
    println!("  | n (Euler grid 2n x n x 2n) | residual |");
    let mut points = Vec::new();
    let mut last = f64::NAN;
    for n in 1..=lmax + 3 {
        let (_, residual) = project_to_convolution(&rotation_average(&m, n)?)?;
        println!("  | {n} | {residual:.3e} |");
        points.push((n as f64, residual.max(1e-17)));
        if n == lmax + 1 {
            last = residual;
        }
    }
    let mut plot = LinePlot::new(
        "PSH Fig. 17: rotation average of a polarized plastic",
        Axis::linear(
            "Euler grid n (2n x n x 2n rotations)",
            (1.0, (lmax + 3) as f64),
        ),
        Axis::log("residual from a convolution", (1e-17, 1.0)),
    )?;
    plot.add(Series {
        label: format!("plastic, l <= {lmax}"),
        color: [200, 40, 40],
        dashed: false,
        points,
    });
    let path = out.join("fig17_residual.png");
    plot.write_png(&path, 720, 480)?;
    println!("  plot: {}", path.display());
    Ok(last)
}
