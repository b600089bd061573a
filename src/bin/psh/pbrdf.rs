//! Measured pBRDF tables (`psh pbrdf`): what a table holds, and its projection to PSH
//! coefficient matrices.

use crate::args::writing;
use clap::{Args, Subcommand};
use psh::polarized::{project_isotropic_with, table_grid};
use psh::progress::Silent;
use psh::stokes::MuellerField;
use serde_json::json;
use std::path::PathBuf;

#[derive(Subcommand)]
pub enum Pbrdf {
    /// What a measured table (Mitsuba 3 .pbsdf, or a KAIST dataset MAT-file with --info)
    /// holds: its angles' ranges and counts, its wavelengths, the fraction of invalid (NaN)
    /// samples, the frames turned; printing JSON.
    Info(InfoArgs),
    /// Project a measured table (Mitsuba 3 .pbsdf, or a KAIST dataset MAT-file with --info)
    /// to isotropic PSH coefficient matrices
    /// (PSH (40), (52); one channel per wavelength, or R, G, B with --rgb), written as an
    /// ISOBI2 .npz in polarsh's convention.
    Project(ProjectArgs),
}

#[derive(Args)]
pub struct InfoArgs {
    #[command(flatten)]
    table: TableArgs,
}

/// A measured table and, for a KAIST data file, its info file.
#[derive(Args)]
pub struct TableArgs {
    /// The table: a Mitsuba 3 .pbsdf, or a KAIST dataset data file (.mat, `pbrdf_T_f`).
    input: PathBuf,
    /// The KAIST info file giving each sample's Stokes frames (`xyzi_T`, `xyzo_T`); without
    /// it a MAT-file's matrices are read in the convention of psh's tables
    /// (docs/measured-pbrdf.md).
    #[arg(long)]
    info: Option<PathBuf>,
}

impl TableArgs {
    fn read(&self) -> psh::Result<psh::io::MeasuredTable> {
        psh::io::read_measured_pbrdf(&self.input, self.info.as_deref())
    }

    fn inputs(&self) -> Vec<PathBuf> {
        std::iter::once(self.input.clone())
            .chain(self.info.clone())
            .collect()
    }
}

#[derive(Args)]
pub struct ProjectArgs {
    #[command(flatten)]
    table: TableArgs,
    /// Band limit of the matrices.
    #[arg(long)]
    lmax: usize,
    /// Band of the exact quadrature grid (default max(lmax, 19) rounded up to odd: an even
    /// number of rings, none on the horizon, where a pBRDF steps to zero, and at least the
    /// KAIST dataset's resolution). The JSON reports band_limit_residual: the share of the
    /// table's norm on this grid that degrees <= lmax leave out.
    #[arg(long)]
    grid_lmax: Option<usize>,
    /// Convert the KAIST dataset's five bands (450..650 nm) to linear sRGB first, as the
    /// dataset's own code does: three channels R, G, B.
    #[arg(long)]
    rgb: bool,
    /// Largest isotropy defect accepted (relative to the largest entry). A table is
    /// isotropic by construction: its defect is the quadrature's aliasing of a function
    /// that is piecewise linear, not band-limited (reported as isotropy_defect; the
    /// entries are dropped).
    #[arg(long, default_value_t = 1e-3)]
    tolerance: f64,
    /// Output .npz (ISOBI2).
    #[arg(short, long)]
    output: PathBuf,
}

pub fn run(p: &Pbrdf) -> psh::Result<serde_json::Value> {
    match p {
        Pbrdf::Info(a) => info(a),
        Pbrdf::Project(a) => writing(&a.table.inputs(), &a.output, || project(a)),
    }
}

/// An axis as its count and range in degrees.
fn axis(v: &[f64]) -> serde_json::Value {
    let deg = |x: f64| x.to_degrees();
    json!({"samples": v.len(), "first_deg": deg(v[0]), "last_deg": deg(v[v.len() - 1])})
}

fn info(a: &InfoArgs) -> psh::Result<serde_json::Value> {
    let m = a.table.read()?;
    let t = &m.table;
    Ok(json!({
        "input": a.table.input,
        "info": a.table.info,
        "phi_d": axis(t.phi_d()),
        "theta_d": axis(t.theta_d()),
        "theta_h": axis(t.theta_h()),
        "wavelengths_nm": t.wavelengths_nm(),
        "invalid_fraction": t.invalid_fraction(),
        "frames": frames(&m),
    }))
}

/// What reading did to the Stokes frames.
fn frames(m: &psh::io::MeasuredTable) -> serde_json::Value {
    json!({
        "turned": m.turned,
        "undefined": m.undefined_frames,
        "largest_turn_deg": m.largest_turn.to_degrees(),
    })
}

fn project(a: &ProjectArgs) -> psh::Result<serde_json::Value> {
    let read = a.table.read()?;
    let rgb;
    let t = if a.rgb {
        rgb = read.table.to_rgb()?;
        &rgb
    } else {
        &read.table
    };
    let grid = a.grid_lmax.unwrap_or(table_grid(a.lmax));
    let start = std::time::Instant::now();
    let channels = (0..t.wavelengths_nm().len())
        .map(|k| t.channel(k))
        .collect::<psh::Result<Vec<_>>>()?;
    let fields: Vec<&dyn MuellerField> = channels.iter().map(|c| c as _).collect();
    let p = project_isotropic_with(&fields, a.lmax, grid, a.tolerance, &Silent)?;
    let seconds = start.elapsed().as_secs_f64();
    psh::io::write_isotropic_npz(&a.output, &p.matrix)?;
    Ok(json!({
        "input": a.table.input, "info": a.table.info, "frames": frames(&read),
        "lmax": a.lmax, "grid_lmax": grid, "channels_nm": t.wavelengths_nm(),
        "isotropy_defect": p.isotropy_defect, "band_limit_residual": p.band_limit_residual,
        "seconds": seconds, "output": a.output,
    }))
}
