//! `psh eval` on `.npy` files, for the external cross-validation suite (`validation/`):
//! `wigner-block`, `swsh-points`, `sh-derivatives`, `sht`, `spin-sht`.

use super::{Kind, MAX_SWSH_EVAL_DEGREE};
use crate::args::parse_rotvec;
use clap::{Args, ValueEnum};
use num_complex::Complex64;
use psh::io::{read_npy_rows, read_npy_shaped, write_npy};
use psh::sh::{for_each_block, num_coeffs, real_block};
use psh::Error;
use serde_json::json;
use std::path::PathBuf;

#[derive(Args)]
pub struct WignerBlockArgs {
    #[arg(long, value_enum)]
    kind: Kind,
    /// The degree l of the block.
    #[arg(long)]
    l: usize,
    /// Rotation vector X,Y,Z: axis times angle in radians (active rotation, PSH (8)).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_rotvec)]
    rotvec: [f64; 3],
    /// Output .npy: float64 [2l+1, 2l+1] (real) or [2l+1, 2l+1, 2] (complex).
    #[arg(short, long)]
    pub output: PathBuf,
}

#[derive(Args)]
pub struct SwshPointsArgs {
    /// Spin weight s.
    #[arg(long, allow_hyphen_values = true)]
    spin: i64,
    #[arg(long)]
    lmax: usize,
    /// Input .npy: float64 [points, 2] of (theta, phi) in radians.
    #[arg(long)]
    pub points: PathBuf,
    /// Output .npy: float64 [points, (lmax+1)^2, 2].
    #[arg(short, long)]
    pub output: PathBuf,
}

#[derive(Args)]
pub struct ShDerivativesArgs {
    #[arg(long)]
    lmax: usize,
    /// Input .npy: float64 [points, 3] of unit directions.
    #[arg(long)]
    pub points: PathBuf,
    /// Output .npy: float64 [points, (lmax+1)^2, 10].
    #[arg(short, long)]
    pub output: PathBuf,
}

/// The direction of a transform.
#[derive(Clone, Copy, ValueEnum)]
enum TransformOp {
    /// Coefficients (flat order l*l + l + m) to grid values (ring-major).
    Synthesis,
    /// Grid values to coefficients.
    Analysis,
}

#[derive(Args)]
pub struct ShtArgs {
    #[arg(long, value_enum)]
    kind: Kind,
    #[arg(long)]
    lmax: usize,
    #[arg(long, value_enum)]
    op: TransformOp,
    /// Input .npy: coefficients [(lmax+1)^2] (real) or [(lmax+1)^2, 2] (complex) for
    /// synthesis; grid values [lmax+1, 2 lmax+2] (real) or [lmax+1, 2 lmax+2, 2] (complex)
    /// for analysis.
    #[arg(long)]
    pub input: PathBuf,
    /// Output .npy (the other of the two shapes).
    #[arg(short, long)]
    pub output: PathBuf,
}

#[derive(Args)]
pub struct SpinShtArgs {
    /// Spin weight s, 1 <= |s| <= lmax.
    #[arg(long, allow_hyphen_values = true)]
    spin: i64,
    #[arg(long)]
    lmax: usize,
    #[arg(long, value_enum)]
    op: TransformOp,
    /// Input .npy: coefficients [(lmax+1)^2, 2] for synthesis; grid values
    /// [lmax+1, 2 lmax+2, 2] for analysis.
    #[arg(long)]
    pub input: PathBuf,
    /// Output .npy (the other of the two shapes).
    #[arg(short, long)]
    pub output: PathBuf,
}

/// Largest degree of `psh eval wigner-block` (the recursion costs l^3).
const MAX_WIGNER_BLOCK_DEGREE: usize = 1024;

/// Largest number of values `psh eval swsh-points` and `sh-derivatives` write.
const MAX_EVAL_VALUES: usize = 1 << 27;

/// Largest `points x (lmax+1)^3` of `psh eval swsh-points` (about a minute).
const MAX_SWSH_POINTS_WORK: u128 = 1 << 36;

/// `[re, im]` pairs to complex numbers.
fn complex_of_pairs(data: &[f64]) -> Vec<Complex64> {
    data.chunks_exact(2)
        .map(|p| Complex64::new(p[0], p[1]))
        .collect()
}

/// Complex numbers to a flat `[re, im, re, im, ...]` stream.
fn pairs_flat(v: &[Complex64]) -> impl Iterator<Item = f64> + '_ {
    v.iter().flat_map(|z| [z.re, z.im])
}

/// Errors when `count` values exceed [`MAX_EVAL_VALUES`].
fn check_output_size(name: &'static str, count: usize) -> psh::Result<()> {
    if count > MAX_EVAL_VALUES {
        return Err(Error::invalid(
            name,
            count.to_string(),
            format!("at most {MAX_EVAL_VALUES} output values"),
        ));
    }
    Ok(())
}

pub fn wigner_block(a: &WignerBlockArgs) -> psh::Result<serde_json::Value> {
    let v = a.rotvec;
    if a.l > MAX_WIGNER_BLOCK_DEGREE {
        return Err(Error::DegreeOutOfRange {
            name: "l",
            value: a.l as i128,
            reason: format!("psh eval wigner-block computes at most l = {MAX_WIGNER_BLOCK_DEGREE}"),
        });
    }
    let r = psh::geometry::rotation_from_rotvec(v)?;
    let n = (2 * a.l + 1) as u64;
    let mut block = Vec::new();
    for_each_block(&r, a.l, |l, b| {
        if l == a.l {
            block = b.to_vec();
        }
    })?;
    let shape = match a.kind {
        Kind::Complex => {
            write_npy(&a.output, &[n, n, 2], pairs_flat(&block))?;
            vec![n, n, 2]
        }
        Kind::Real => {
            let mut real = Vec::new();
            real_block(a.l, &block, &mut real);
            write_npy(&a.output, &[n, n], real)?;
            vec![n, n]
        }
    };
    Ok(json!({"l": a.l, "kind": a.kind.name(), "rotvec": v, "output": a.output, "shape": shape}))
}

pub fn swsh_points(a: &SwshPointsArgs) -> psh::Result<serde_json::Value> {
    if a.lmax > MAX_SWSH_EVAL_DEGREE {
        return Err(Error::DegreeOutOfRange {
            name: "lmax",
            value: a.lmax as i128,
            reason: format!("psh eval swsh-points evaluates at most lmax = {MAX_SWSH_EVAL_DEGREE}"),
        });
    }
    let (count, points) = read_npy_rows(&a.points, 2)?;
    let n = num_coeffs(a.lmax);
    check_output_size("number of points", count.saturating_mul(n))?;
    let work = count as u128 * (a.lmax as u128 + 1).pow(3);
    if work > MAX_SWSH_POINTS_WORK {
        return Err(Error::invalid(
            "points x (lmax+1)^3",
            work.to_string(),
            format!(
                "psh eval swsh-points evaluates at most {MAX_SWSH_POINTS_WORK} (about a minute)"
            ),
        ));
    }
    let mut out = Vec::with_capacity(count * n);
    for p in points.chunks_exact(2) {
        out.extend(psh::swsh::swsh(a.spin, a.lmax, p[0], p[1])?);
    }
    let shape = [count as u64, n as u64, 2];
    write_npy(&a.output, &shape, pairs_flat(&out))?;
    Ok(json!({"spin": a.spin, "lmax": a.lmax, "points": count, "output": a.output, "shape": shape}))
}

pub fn sh_derivatives(a: &ShDerivativesArgs) -> psh::Result<serde_json::Value> {
    let sh = psh::sh::SolidHarmonics::new(a.lmax)?;
    let (count, points) = read_npy_rows(&a.points, 3)?;
    let n = sh.len();
    check_output_size(
        "number of points",
        count.saturating_mul(n).saturating_mul(10),
    )?;
    let dirs: Vec<[f64; 3]> = points.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
    let mut values = vec![0.0; count * n];
    let mut gradients = vec![[0.0; 3]; count * n];
    let mut hessians = vec![[0.0; 6]; count * n];
    sh.eval_batch(&dirs, &mut values, &mut gradients, &mut hessians)?;
    let rows = (0..count * n).flat_map(|i| {
        std::iter::once(values[i])
            .chain(gradients[i])
            .chain(hessians[i])
    });
    let shape = [count as u64, n as u64, 10];
    write_npy(&a.output, &shape, rows)?;
    Ok(json!({
        "lmax": a.lmax, "points": count, "output": a.output, "shape": shape,
        "hessian_entries": ["xx", "xy", "xz", "yy", "yz", "zz"],
    }))
}

/// The grid of a transform as JSON: its size and polar angles.
fn grid_json(grid: &psh::sh::SphereGrid) -> serde_json::Value {
    json!({"n_theta": grid.rings.len(), "n_phi": grid.n_phi, "theta": grid.rings.theta})
}

/// Errors when the exact grid of band `lmax` (`lmax + 1` rings of `2 lmax + 2` points)
/// would hold more than [`MAX_EVAL_VALUES`] values, before any table is built.
fn check_grid_size(lmax: usize) -> psh::Result<()> {
    psh::sh::check_lmax(lmax)?;
    check_output_size("grid values", (lmax + 1) * (2 * lmax + 2))
}

/// The complex transform of `c` (`[re, im]` pairs of `shape_in`) written as `shape_out`.
fn complex_transform(
    input: &std::path::Path,
    output: &std::path::Path,
    shape_in: &[u64],
    shape_out: &[u64],
    len_out: usize,
    f: impl FnOnce(&[Complex64], &mut [Complex64]) -> psh::Result<()>,
) -> psh::Result<Vec<u64>> {
    let c = complex_of_pairs(&read_npy_shaped(input, shape_in)?);
    let mut out = vec![Complex64::default(); len_out];
    f(&c, &mut out)?;
    write_npy(output, shape_out, pairs_flat(&out))?;
    Ok(shape_out.to_vec())
}

pub fn sht(a: &ShtArgs) -> psh::Result<serde_json::Value> {
    check_grid_size(a.lmax)?;
    let t = psh::sh::ShTransform::new(a.lmax)?;
    let grid = t.grid();
    let n = num_coeffs(a.lmax) as u64;
    let (nt, np) = (grid.rings.len() as u64, grid.n_phi as u64);
    let (input, output) = (&a.input, &a.output);
    let shape = match (a.kind, a.op) {
        (Kind::Real, TransformOp::Synthesis) => {
            let c = read_npy_shaped(input, &[n])?;
            let mut out = vec![0.0; grid.len()];
            t.synthesis_real(&c, &mut out)?;
            write_npy(output, &[nt, np], out)?;
            vec![nt, np]
        }
        (Kind::Real, TransformOp::Analysis) => {
            let v = read_npy_shaped(input, &[nt, np])?;
            let mut out = vec![0.0; n as usize];
            t.analysis_real(&v, &mut out)?;
            write_npy(output, &[n], out)?;
            vec![n]
        }
        (Kind::Complex, TransformOp::Synthesis) => {
            complex_transform(input, output, &[n, 2], &[nt, np, 2], grid.len(), |c, o| {
                t.synthesis_complex(c, o)
            })?
        }
        (Kind::Complex, TransformOp::Analysis) => {
            complex_transform(input, output, &[nt, np, 2], &[n, 2], n as usize, |v, o| {
                t.analysis_complex(v, o)
            })?
        }
    };
    Ok(json!({
        "kind": a.kind.name(), "lmax": a.lmax, "output": a.output, "shape": shape,
        "grid": grid_json(grid),
    }))
}

pub fn spin_sht(a: &SpinShtArgs) -> psh::Result<serde_json::Value> {
    check_grid_size(a.lmax)?;
    let t = psh::swsh::SpinTransform::new(a.spin, a.lmax)?;
    let grid = t.grid();
    let n = num_coeffs(a.lmax) as u64;
    let (nt, np) = (grid.rings.len() as u64, grid.n_phi as u64);
    let (input, output) = (&a.input, &a.output);
    let shape = match a.op {
        TransformOp::Synthesis => {
            complex_transform(input, output, &[n, 2], &[nt, np, 2], grid.len(), |c, o| {
                t.synthesis(c, o)
            })?
        }
        TransformOp::Analysis => {
            complex_transform(input, output, &[nt, np, 2], &[n, 2], n as usize, |v, o| {
                t.analysis(v, o)
            })?
        }
    };
    Ok(json!({
        "spin": a.spin, "lmax": a.lmax, "output": a.output, "shape": shape, "grid": grid_json(grid),
    }))
}
