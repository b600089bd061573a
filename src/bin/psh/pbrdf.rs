//! Measured pBRDF tables (`psh pbrdf`): what a table holds, and its projection to PSH
//! coefficient matrices.

use crate::args::writing;
use clap::{Args, Subcommand};
use psh::polarized::{project_operator, IsotropicMatrix, SpinBlock22};
use serde_json::json;
use std::path::PathBuf;

#[derive(Subcommand)]
pub enum Pbrdf {
    /// What a measured table (Mitsuba 3 .pbsdf) holds: its angles' ranges and counts, its
    /// wavelengths, the fraction of invalid (NaN) samples; printing JSON.
    Info(InfoArgs),
    /// Project a measured table (Mitsuba 3 .pbsdf) to isotropic PSH coefficient matrices
    /// (PSH (40), (52); one channel per wavelength, or R, G, B with --rgb), written as an
    /// ISOBI2 .npz in polarsh's convention.
    Project(ProjectArgs),
}

#[derive(Args)]
pub struct InfoArgs {
    /// The table (.pbsdf).
    input: PathBuf,
}

#[derive(Args)]
pub struct ProjectArgs {
    /// The table (.pbsdf).
    input: PathBuf,
    /// Band limit of the matrices.
    #[arg(long)]
    lmax: usize,
    /// Band of the exact quadrature grid (default max(lmax, 2) rounded up to odd: an even
    /// number of rings, none on the horizon, where a pBRDF steps to zero).
    #[arg(long)]
    grid_lmax: Option<usize>,
    /// Convert the KAIST dataset's five bands (450..650 nm) to linear sRGB first, as the
    /// dataset's own code does: three channels R, G, B.
    #[arg(long)]
    rgb: bool,
    /// Largest isotropy defect accepted (relative to the largest entry).
    #[arg(long, default_value_t = 1e-6)]
    tolerance: f64,
    /// Output .npz (ISOBI2).
    #[arg(short, long)]
    output: PathBuf,
}

pub fn run(p: &Pbrdf) -> psh::Result<serde_json::Value> {
    match p {
        Pbrdf::Info(a) => info(a),
        Pbrdf::Project(a) => writing(std::slice::from_ref(&a.input), &a.output, || project(a)),
    }
}

/// An axis as its count and range in degrees.
fn axis(v: &[f64]) -> serde_json::Value {
    let deg = |x: f64| x.to_degrees();
    json!({"samples": v.len(), "first_deg": deg(v[0]), "last_deg": deg(v[v.len() - 1])})
}

fn info(a: &InfoArgs) -> psh::Result<serde_json::Value> {
    let t = psh::io::read_pbsdf(&a.input)?;
    Ok(json!({
        "input": a.input,
        "phi_d": axis(t.phi_d()),
        "theta_d": axis(t.theta_d()),
        "theta_h": axis(t.theta_h()),
        "wavelengths_nm": t.wavelengths_nm(),
        "invalid_fraction": t.invalid_fraction(),
    }))
}

fn project(a: &ProjectArgs) -> psh::Result<serde_json::Value> {
    let t = psh::io::read_pbsdf(&a.input)?;
    let t = if a.rgb { t.to_rgb()? } else { t };
    let grid = a.grid_lmax.unwrap_or(a.lmax.max(2) | 1);
    let start = std::time::Instant::now();
    let channels = (0..t.wavelengths_nm().len())
        .map(|k| {
            let dense = project_operator(&t.channel(k)?, a.lmax, grid, SpinBlock22::ComplexPair)?;
            IsotropicMatrix::from_dense(&dense, a.tolerance)
        })
        .collect::<psh::Result<Vec<_>>>()?;
    let seconds = start.elapsed().as_secs_f64();
    let m = IsotropicMatrix::from_channels(&channels)?;
    psh::io::write_isotropic_npz(&a.output, &m)?;
    Ok(json!({
        "input": a.input, "lmax": a.lmax, "grid_lmax": grid,
        "channels_nm": t.wavelengths_nm(), "seconds": seconds, "output": a.output,
    }))
}
