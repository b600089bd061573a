//! The `psh` command line: `verify`, `eval`.

use clap::{Args, Parser, Subcommand, ValueEnum};
use num_complex::Complex64;
use psh::sh::harmonics::{sh_complex, sh_real};
use psh::sh::wigner::{for_each_block, real_block, rotation_from_rotvec};
use psh::sh::MAX_DEGREE;
use psh::Error;
use serde_json::json;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "psh",
    version,
    about = "Spherical harmonics for polarized light transport"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Run the library's checks and print a table (or JSON); non-zero exit if any fails.
    Verify {
        /// Print a JSON array of {"id","source","description","max_error","tolerance","passed"}.
        #[arg(long)]
        json: bool,
        /// Run only the checks whose id contains this text.
        #[arg(long)]
        filter: Option<String>,
    },
    /// Evaluate basis functions or rotation matrices, printing JSON.
    #[command(subcommand)]
    Eval(Eval),
}

#[derive(Subcommand)]
enum Eval {
    /// SH of all l <= lmax at one direction, flat order l*l + l + m, as [re, im] pairs.
    Sh(ShArgs),
    /// Wigner D blocks l <= lmax of the rotation given by a rotation vector.
    Wigner(WignerArgs),
    /// Spin-weighted SH sY_lm of all l <= lmax at one direction (flat order, zeros where
    /// l < |spin|), as [re, im] pairs.
    Swsh(SwshArgs),
}

#[derive(Args)]
struct SwshArgs {
    /// Spin weight s (2 for linear polarization).
    #[arg(long, allow_hyphen_values = true)]
    spin: i64,
    #[command(flatten)]
    at: Evaluation,
}

/// The band limit and direction of an evaluation.
#[derive(Args)]
struct Evaluation {
    #[arg(long)]
    lmax: usize,
    /// Polar angle in radians, in [0, pi].
    #[arg(long, allow_hyphen_values = true)]
    theta: f64,
    /// Azimuth in radians.
    #[arg(long, allow_hyphen_values = true)]
    phi: f64,
}

/// Largest degree `psh eval swsh` evaluates (the Wigner recursion costs lmax^3).
const MAX_SWSH_EVAL_DEGREE: usize = 2048;

#[derive(Clone, Copy, ValueEnum)]
enum Kind {
    Real,
    Complex,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Real => "real",
            Kind::Complex => "complex",
        }
    }
}

#[derive(Args)]
struct ShArgs {
    #[arg(long, value_enum)]
    kind: Kind,
    #[command(flatten)]
    at: Evaluation,
}

#[derive(Args)]
struct WignerArgs {
    #[arg(long, value_enum)]
    kind: Kind,
    #[arg(long)]
    lmax: usize,
    /// Rotation vector X,Y,Z: axis times angle in radians (active rotation, PSH (8)).
    #[arg(long, allow_hyphen_values = true)]
    rotvec: String,
}

/// Largest degree `psh eval wigner` prints (the output grows like lmax^3).
const MAX_WIGNER_EVAL_DEGREE: usize = 200;

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            use clap::error::ErrorKind::{DisplayHelp, DisplayVersion};
            if matches!(e.kind(), DisplayHelp | DisplayVersion) {
                print!("{e}");
                return ExitCode::SUCCESS;
            }
            let text = e.to_string();
            eprintln!("{}", text.lines().next().unwrap_or("invalid arguments"));
            return ExitCode::from(2);
        }
    };
    let result = match cli.command.unwrap_or(Command::Verify {
        json: false,
        filter: None,
    }) {
        Command::Verify { json, filter } => return verify(json, filter.as_deref()),
        Command::Eval(Eval::Sh(a)) => eval_sh(&a),
        Command::Eval(Eval::Wigner(a)) => eval_wigner(&a),
        Command::Eval(Eval::Swsh(a)) => eval_swsh(&a),
    };
    match result {
        Ok(v) => {
            println!("{v}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

fn verify(json: bool, filter: Option<&str>) -> ExitCode {
    let results = psh::verify::run(filter);
    let ok = results.iter().all(|r| r.passed);
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(&results).expect("plain data")
        );
    } else {
        println!(
            "{:<28} {:<16} {:>10} {:>10}  result",
            "check", "source", "max error", "tolerance"
        );
        for r in &results {
            println!(
                "{:<28} {:<16} {:>10.2e} {:>10.0e}  {}",
                r.id,
                r.source,
                r.max_error,
                r.tolerance,
                if r.passed { "pass" } else { "FAIL" }
            );
            if let Some(e) = &r.error {
                println!("    error: {e}");
            }
        }
        let failed = results.iter().filter(|r| !r.passed).count();
        println!("{} passed, {} failed", results.len() - failed, failed);
    }
    if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

fn pairs(v: impl IntoIterator<Item = Complex64>) -> Vec<[f64; 2]> {
    v.into_iter().map(|z| [z.re, z.im]).collect()
}

fn eval_sh(args: &ShArgs) -> psh::Result<serde_json::Value> {
    let a = &args.at;
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

fn eval_swsh(args: &SwshArgs) -> psh::Result<serde_json::Value> {
    let a = &args.at;
    if a.lmax > MAX_SWSH_EVAL_DEGREE {
        return Err(Error::DegreeOutOfRange {
            name: "lmax",
            value: a.lmax as i64,
            reason: format!("psh eval swsh evaluates at most lmax = {MAX_SWSH_EVAL_DEGREE}"),
        });
    }
    let values = pairs(psh::swsh::swsh(args.spin, a.lmax, a.theta, a.phi)?);
    Ok(json!({"lmax": a.lmax, "spin": args.spin, "theta": a.theta, "phi": a.phi, "values": values}))
}

fn eval_wigner(a: &WignerArgs) -> psh::Result<serde_json::Value> {
    let parts: Vec<&str> = a.rotvec.split(',').collect();
    let bad = |reason: &str| Error::InvalidRotation {
        value: a.rotvec.clone(),
        reason: reason.into(),
    };
    if parts.len() != 3 {
        return Err(bad("expected three comma-separated numbers X,Y,Z"));
    }
    let mut v = [0.0; 3];
    for (c, p) in v.iter_mut().zip(&parts) {
        *c = p.trim().parse().map_err(|_| bad("not a number"))?;
    }
    if a.lmax > MAX_WIGNER_EVAL_DEGREE.min(MAX_DEGREE) {
        return Err(Error::DegreeOutOfRange {
            name: "lmax",
            value: a.lmax as i64,
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
