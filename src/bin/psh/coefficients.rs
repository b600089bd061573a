//! Commands on coefficient files: `project` a map, `rotate`, `reconstruct` a map,
//! `convolve` with a kernel, `apply` a pBRDF matrix.

use crate::args::{named, parse_rotvec, writing, WindowArg};
use clap::{Args, ValueEnum};
use psh::geometry::rotation_from_rotvec;
use psh::map::{MapLayout, StokesMap};
use psh::polarized::{Codomain, FieldArgument};
use psh::Error;
use serde_json::json;
use std::path::PathBuf;

#[derive(Args)]
pub struct ProjectArgs {
    /// The component files: a pattern with %d (map_s%d.exr) or one of them (map_s0.exr);
    /// or one EXR file with layers S0..S3 (Mitsuba 3's multichannel layout), same frames.
    input: String,
    /// Band limit: coefficients of degrees l <= lmax.
    #[arg(long)]
    lmax: usize,
    /// Stokes components to keep (polarsh's names): SCALAR (s0), POLAR2 (s1, s2), POLAR3
    /// (s0..s2) or POLAR4 (s0..s3).
    #[arg(long, default_value_t = Codomain::Full, value_parser = named::<Codomain>())]
    codomain: Codomain,
    /// Output .npz.
    #[arg(short, long)]
    output: PathBuf,
    #[command(flatten)]
    window: WindowArg,
}

#[derive(Args)]
pub struct RotateArgs {
    /// Input .npz.
    input: PathBuf,
    /// Rotation vector X,Y,Z: axis times angle in radians (active rotation, PSH (8)).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_rotvec)]
    rotvec: [f64; 3],
    /// Output .npz.
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Args)]
pub struct ReconstructArgs {
    /// Input .npz.
    input: PathBuf,
    /// Equirectangular image of H rows and W = 2H columns, written H,W (or --cube).
    #[arg(
        long,
        conflicts_with = "cube",
        required_unless_present = "cube",
        value_parser = parse_equirect
    )]
    equirect: Option<EquirectSize>,
    /// Cube cross of faces of E x E texels (3E x 4E image; or --equirect).
    #[arg(long)]
    cube: Option<usize>,
    /// Output prefix: writes {prefix}_s0..s3.exr and {prefix}_{s0,s1,s2,s3,dop,aop}.png.
    #[arg(short, long)]
    output: String,
    #[command(flatten)]
    window: WindowArg,
}

#[derive(Args)]
pub struct ConvolveArgs {
    /// Input .npz.
    input: PathBuf,
    /// A built-in kernel: linear-zenith, k(theta) = (pi - theta) I (PSH Sec. 6.4.3); or
    /// --kernel-table.
    #[arg(
        long,
        conflicts_with = "kernel_table",
        required_unless_present = "kernel_table"
    )]
    kernel: Option<KernelName>,
    /// A kernel table (CSV: theta in radians, then the 16 entries row-major; angles
    /// strictly increasing from 0 to pi; docs/conventions.md); or --kernel.
    #[arg(long)]
    kernel_table: Option<PathBuf>,
    /// Output .npz.
    #[arg(short, long)]
    output: PathBuf,
    #[command(flatten)]
    window: WindowArg,
}

#[derive(Args)]
pub struct ApplyArgs {
    /// The pBRDF's isotropic coefficient matrices (.npz, dom_type ISOBI2).
    matrix: PathBuf,
    /// The incident field's coefficient vector (.npz).
    input: PathBuf,
    /// Output .npz.
    #[arg(short, long)]
    output: PathBuf,
}

/// The built-in convolution kernels.
#[derive(Clone, Copy, ValueEnum)]
enum KernelName {
    LinearZenith,
}

/// An equirectangular size `H,W` (rows, columns).
#[derive(Clone, Copy)]
struct EquirectSize(usize, usize);

/// `H,W` with `W = 2H > 0`.
fn parse_equirect(size: &str) -> psh::Result<EquirectSize> {
    let hw: Option<Vec<usize>> = size.split(',').map(|x| x.trim().parse().ok()).collect();
    match hw.as_deref() {
        Some(&[h, w]) if h > 0 && w == 2 * h => Ok(EquirectSize(h, w)),
        _ => Err(Error::invalid(
            "--equirect",
            size.to_string(),
            "expected H,W with W = 2H (rows, columns)",
        )),
    }
}

pub fn project(a: &ProjectArgs) -> psh::Result<serde_json::Value> {
    let codomain = a.codomain;
    psh::sh::check_lmax(a.lmax)?;
    let inputs = psh::io::stokes_map_files(&a.input)?;
    let (map, v) = writing(&inputs, &a.output, || {
        let map = psh::io::read_stokes_map(&a.input)?;
        let mut v = map.project(codomain, a.lmax)?;
        v.apply_window(a.window.window);
        psh::io::write_psh_npz(&a.output, &v)?;
        Ok((map, v))
    })?;
    Ok(json!({
        "input": a.input, "layout": [map.layout().height(), map.layout().width()],
        "channels": v.channels(), "lmax": v.lmax(), "codomain": codomain.name(),
        "window": a.window.window.name(), "output": a.output,
    }))
}

pub fn rotate(a: &RotateArgs) -> psh::Result<serde_json::Value> {
    let rotvec = a.rotvec;
    let r = rotation_from_rotvec(rotvec)?;
    let v = writing(std::slice::from_ref(&a.input), &a.output, || {
        let v = psh::io::read_psh_npz(&a.input)?;
        psh::io::write_psh_npz(&a.output, &v.rotated(&r)?)?;
        Ok(v)
    })?;
    Ok(json!({"input": a.input, "rotvec": rotvec, "lmax": v.lmax(), "output": a.output}))
}

pub fn reconstruct(a: &ReconstructArgs) -> psh::Result<serde_json::Value> {
    let layout = match (a.equirect, a.cube) {
        (Some(EquirectSize(h, w)), _) => MapLayout::from_image_size(h, w)?,
        (None, Some(e)) => MapLayout::CubeCross(psh::geometry::CubeCross::new(e)?),
        (None, None) => unreachable!("clap requires --equirect or --cube"),
    };
    let window = a.window.window;
    // Where the files go, before any work.
    psh::io::check_output(format!("{}_s0.exr", a.output))?;
    let v = psh::io::read_psh_npz(&a.input)?;
    // The map with its files and pictures, before the map is made.
    psh::io::check_stokes_output(layout.width().saturating_mul(layout.height()), v.channels())?;
    // A map is indexed by the direction towards the source.
    let map = StokesMap::reconstruct(
        &v.converted(FieldArgument::TowardsSource).windowed(window),
        layout,
    )?;
    let written = psh::io::all_or_nothing(std::slice::from_ref(&a.input), || {
        let mut written = psh::io::write_stokes_map(&map, format!("{}_s%d.exr", a.output))?;
        written.extend(psh::io::write_map_pngs(&map, &a.output)?);
        Ok(written)
    })?;
    Ok(json!({"input": a.input, "lmax": v.lmax(), "window": window.name(), "written": written}))
}

pub fn convolve(a: &ConvolveArgs) -> psh::Result<serde_json::Value> {
    let inputs: Vec<PathBuf> = std::iter::once(a.input.clone())
        .chain(a.kernel_table.clone())
        .collect();
    writing(&inputs, &a.output, || {
        let v = psh::io::read_psh_npz(&a.input)?;
        let (kernel, name) = match (&a.kernel, &a.kernel_table) {
            (Some(KernelName::LinearZenith), _) => (
                psh::polarized::ConvolutionKernel::linear_zenith(),
                "linear-zenith".to_string(),
            ),
            (None, Some(path)) => (psh::io::read_kernel_csv(path)?, path.display().to_string()),
            (None, None) => unreachable!("clap requires --kernel or --kernel-table"),
        };
        let k = psh::polarized::kernel_coefficients(&kernel, v.lmax())?;
        let out = k.convolve(&v)?.windowed(a.window.window);
        psh::io::write_psh_npz(&a.output, &out)?;
        Ok(json!({
            "input": a.input, "kernel": name, "lmax": v.lmax(), "window": a.window.window.name(),
            "quadrature_error_estimate": k.error_estimate(), "output": a.output,
        }))
    })
}

pub fn apply(a: &ApplyArgs) -> psh::Result<serde_json::Value> {
    writing(&[a.matrix.clone(), a.input.clone()], &a.output, || {
        let m = psh::io::read_isotropic_npz(&a.matrix)?;
        let v = psh::io::read_psh_npz(&a.input)?;
        let cut = v.truncated(m.lmax()).map_err(|e| {
            Error::malformed(
                a.input.clone(),
                format!(
                    "the matrix {} needs l <= {}: {e}",
                    a.matrix.display(),
                    m.lmax()
                ),
            )
        })?;
        let out = m.apply(&cut)?;
        psh::io::write_psh_npz(&a.output, &out)?;
        Ok(json!({
            "matrix": a.matrix, "input": a.input, "lmax": m.lmax(), "channels": out.channels(),
            "output": a.output,
        }))
    })
}
