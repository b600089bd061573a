//! Basis functions and rotations at one point, printed as JSON: `sh`, `swsh`, `wigner`,
//! `legendre`, `grid`.

use super::{pairs, Kind, MAX_SWSH_EVAL_DEGREE};
use crate::args::parse_rotvec;
use clap::Args;
use num_complex::Complex64;
use psh::geometry::rotation_from_rotvec;
use psh::sh::{for_each_block, real_block, sh_complex, sh_real, MAX_DEGREE};
use psh::Error;
use serde_json::json;

/// The band limit and direction of an evaluation.
#[derive(Args)]
pub struct Evaluation {
    #[arg(long)]
    lmax: usize,
    /// Polar angle in radians, in [0, pi].
    #[arg(long, allow_hyphen_values = true)]
    theta: f64,
    /// Azimuth in radians.
    #[arg(long, allow_hyphen_values = true)]
    phi: f64,
}

#[derive(Args)]
pub struct ShArgs {
    #[arg(long, value_enum)]
    kind: Kind,
    #[command(flatten)]
    at: Evaluation,
}

#[derive(Args)]
pub struct SwshArgs {
    /// Spin weight s (2 for linear polarization).
    #[arg(long, allow_hyphen_values = true)]
    spin: i64,
    #[command(flatten)]
    at: Evaluation,
}

#[derive(Args)]
pub struct WignerArgs {
    #[arg(long, value_enum)]
    kind: Kind,
    #[arg(long)]
    lmax: usize,
    /// Rotation vector X,Y,Z: axis times angle in radians (active rotation, PSH (8)).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_rotvec)]
    rotvec: [f64; 3],
}

#[derive(Args)]
pub struct LegendreArgs {
    /// The degree l.
    #[arg(long)]
    l: usize,
    /// Polar angle in radians, in [0, pi].
    #[arg(long, allow_hyphen_values = true)]
    theta: f64,
    /// The f64 path of the transforms (psh::sh::kernels::Legendre) instead of the
    /// double-double path (for_each_column_accurate).
    #[arg(long)]
    fast: bool,
}

#[derive(Args)]
pub struct GridArgs {
    /// Number of rings, 1..=8193 (the grid of band limit 8192).
    #[arg(long)]
    n: usize,
}

/// Largest degree `psh eval wigner` prints (the output grows like lmax^3).
const MAX_WIGNER_EVAL_DEGREE: usize = 200;

/// Bytes a printed number holds: its JSON value and its text.
const JSON_NUMBER_BYTES: usize = 64;

pub fn sh(args: &ShArgs) -> psh::Result<serde_json::Value> {
    let a = &args.at;
    psh::sh::check_lmax(a.lmax)?;
    let n = psh::sh::num_coeffs(a.lmax);
    psh::budget::check("the printed SH values (JSON)", &[n, 2], JSON_NUMBER_BYTES)?;
    let values = match args.kind {
        Kind::Real => pairs(
            sh_real(a.lmax, a.theta, a.phi)?
                .into_iter()
                .map(|x| Complex64::new(x, 0.0)),
        ),
        Kind::Complex => pairs(sh_complex(a.lmax, a.theta, a.phi)?),
    };
    Ok(
        json!({"lmax": a.lmax, "theta": a.theta, "phi": a.phi, "kind": args.kind.name(), "values": values}),
    )
}

pub fn swsh(args: &SwshArgs) -> psh::Result<serde_json::Value> {
    let a = &args.at;
    if a.lmax > MAX_SWSH_EVAL_DEGREE {
        return Err(Error::DegreeOutOfRange {
            name: "lmax",
            value: a.lmax as i128,
            reason: format!("psh eval swsh evaluates at most lmax = {MAX_SWSH_EVAL_DEGREE}"),
        });
    }
    let values = pairs(psh::swsh::swsh(args.spin, a.lmax, a.theta, a.phi)?);
    Ok(json!({"lmax": a.lmax, "spin": args.spin, "theta": a.theta, "phi": a.phi, "values": values}))
}

pub fn wigner(a: &WignerArgs) -> psh::Result<serde_json::Value> {
    let v = a.rotvec;
    if a.lmax > MAX_WIGNER_EVAL_DEGREE.min(MAX_DEGREE) {
        return Err(Error::DegreeOutOfRange {
            name: "lmax",
            value: a.lmax as i128,
            reason: format!("psh eval wigner prints at most lmax = {MAX_WIGNER_EVAL_DEGREE}"),
        });
    }
    let r = rotation_from_rotvec(v)?;
    let mut blocks = Vec::new();
    let mut real = Vec::new();
    for_each_block(&r, a.lmax, |l, b| match a.kind {
        Kind::Complex => blocks.push(pairs(b.iter().copied())),
        Kind::Real => {
            real_block(l, b, &mut real);
            blocks.push(pairs(real.iter().map(|&x| Complex64::new(x, 0.0))));
        }
    })?;
    Ok(json!({"lmax": a.lmax, "kind": a.kind.name(), "rotvec": v, "blocks": blocks}))
}

pub fn grid(a: &GridArgs) -> psh::Result<serde_json::Value> {
    // At most the rings of the largest band limit; checked before the O(n^2) Newton
    // iterations.
    if a.n > MAX_DEGREE + 1 {
        return Err(Error::invalid(
            "n",
            a.n.to_string(),
            format!(
                "at most {} rings (the grid of band limit {})",
                MAX_DEGREE + 1,
                MAX_DEGREE
            ),
        ));
    }
    let g = psh::sh::GaussLegendre::new(a.n)?;
    Ok(json!({"n": a.n, "theta": g.theta, "weights": g.weights}))
}

pub fn legendre(a: &LegendreArgs) -> psh::Result<serde_json::Value> {
    use psh::sh::kernels::{for_each_column_accurate, Legendre, Polar};
    psh::sh::check_lmax(a.l)?;
    psh::geometry::check_theta(a.theta)?;
    let mut values = vec![0.0; a.l + 1];
    let mut keep = |m: usize, col: &[f64]| values[m] = col[a.l - m];
    let path = if a.fast {
        Legendre::new(a.l)?.for_each_column(Polar::from_theta(a.theta), &mut keep);
        "fast"
    } else {
        for_each_column_accurate(a.l, Polar::from_theta_accurate(a.theta), &mut keep);
        "accurate"
    };
    Ok(json!({"l": a.l, "theta": a.theta, "path": path, "values": values}))
}
