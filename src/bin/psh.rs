//! The `psh` command line: `verify`, `eval`, the environment-map pipeline
//! `project`, `rotate`, `reconstruct`, `filter-report` (PF), `convolve` and
//! `lights-demo` (SHH).

use clap::{Args, Parser, Subcommand, ValueEnum};
use num_complex::Complex64;
use psh::map::{MapLayout, StokesMap};
use psh::polarized::{Codomain, PshRotation};
use psh::sh::harmonics::{sh_complex, sh_real};
use psh::sh::wigner::{for_each_block, real_block, rotation_from_rotvec};
use psh::sh::MAX_DEGREE;
use psh::Error;
use serde_json::json;
use std::path::PathBuf;
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
    /// Project a polarized environment map (EXR, one file per Stokes component) to PSH
    /// coefficients, written as a polarsh-compatible .npz.
    Project(ProjectArgs),
    /// Rotate a PSH coefficient vector (.npz) in the frequency domain (PSH (35)-(37)).
    Rotate(RotateArgs),
    /// Reconstruct a PSH coefficient vector (.npz) on an image: EXR per Stokes component
    /// and PNG pictures (s0..s3, degree and angle of polarization).
    Reconstruct(ReconstructArgs),
    /// Write the polarizing factor psi of PF Table 1's materials and the error of its
    /// specular-colour approximation (PF Fig. 3, Fig. 5) as CSV and PNG plots into a
    /// directory; print the largest errors (JSON, or a Markdown table).
    FilterReport(FilterReportArgs),
    /// Convolve a PSH coefficient vector (.npz) with a polarized kernel k(theta) by the
    /// convolution theorem (PSH (68)-(69)), writing a POLAR4 .npz.
    Convolve(ConvolveArgs),
    /// Many spherical lights: uniform grids vs a Hessian-adaptive grid (SHH Sec. 5, 6.2),
    /// errors against the per-point exact SH coefficients; writes table.md and
    /// false-colour error images into a directory and prints the table (Markdown).
    LightsDemo(LightsDemoArgs),
}

#[derive(Args)]
struct LightsDemoArgs {
    /// Output directory (created if missing).
    #[arg(long)]
    out: PathBuf,
}

#[derive(Args)]
struct ConvolveArgs {
    /// Input .npz.
    input: PathBuf,
    /// A built-in kernel: linear-zenith, k(theta) = (pi - theta) I (PSH Sec. 6.4.3).
    #[arg(
        long,
        conflicts_with = "kernel_table",
        required_unless_present = "kernel_table"
    )]
    kernel: Option<KernelName>,
    /// A kernel table (CSV: theta in radians, then the 16 entries row-major; angles
    /// strictly increasing from 0 to pi; docs/conventions.md).
    #[arg(long)]
    kernel_table: Option<PathBuf>,
    /// Output .npz.
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Clone, Copy, ValueEnum)]
enum KernelName {
    LinearZenith,
}

#[derive(Args)]
struct FilterReportArgs {
    /// Output directory (created if missing).
    #[arg(long)]
    out: PathBuf,
    /// Print the largest errors as a Markdown table instead of JSON.
    #[arg(long)]
    markdown: bool,
}

#[derive(Args)]
struct ProjectArgs {
    /// The component files: a pattern with %d (map_s%d.exr) or one of them (map_s0.exr).
    input: String,
    /// Band limit: coefficients of degrees l <= lmax.
    #[arg(long)]
    lmax: usize,
    /// Stokes components to keep: POLAR2 (s1, s2), POLAR3 (s0..s2) or POLAR4 (s0..s3).
    #[arg(long, default_value = "POLAR4")]
    codomain: String,
    /// Output .npz.
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Args)]
struct RotateArgs {
    /// Input .npz.
    input: PathBuf,
    /// Rotation vector X,Y,Z: axis times angle in radians (active rotation, PSH (8)).
    #[arg(long, allow_hyphen_values = true)]
    rotvec: String,
    /// Output .npz.
    #[arg(short, long)]
    output: PathBuf,
}

#[derive(Args)]
struct ReconstructArgs {
    /// Input .npz.
    input: PathBuf,
    /// Equirectangular image of H rows and W = 2H columns.
    #[arg(long, conflicts_with = "cube", required_unless_present = "cube")]
    equirect: Option<String>,
    /// Cube cross of faces of E x E texels (3E x 4E image).
    #[arg(long)]
    cube: Option<usize>,
    /// Output prefix: writes {prefix}_s0..s3.exr and {prefix}_{s0,s1,s2,s3,dop,aop}.png.
    #[arg(short, long)]
    output: String,
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
        Command::Project(a) => project(&a),
        Command::Rotate(a) => rotate(&a),
        Command::Reconstruct(a) => reconstruct(&a),
        Command::FilterReport(a) => return filter_report(&a),
        Command::Convolve(a) => convolve(&a),
        Command::LightsDemo(a) => return lights_demo(&a),
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

fn lights_demo(a: &LightsDemoArgs) -> ExitCode {
    match psh::io::lights_demo::write_lights_demo(&a.out) {
        Ok(report) => {
            print!("{}", report.markdown_table());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

fn filter_report(a: &FilterReportArgs) -> ExitCode {
    let report = match psh::io::filter_report::write_filter_report(&a.out) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
    };
    if a.markdown {
        print!("{}", report.markdown_table());
    } else {
        let errors: Vec<serde_json::Value> = report
            .errors
            .iter()
            .map(|e| {
                json!({
                    "material": e.material.name(),
                    "channel": format!("{:?}", e.channel),
                    "r0_ior": e.r0_ior,
                    "r0_table": e.r0_printed,
                    "max_error_60deg": e.from_ior[0].abs,
                    "max_error_89deg": e.from_ior[1].abs,
                    "max_error_table_r0_60deg": e.printed[0].abs,
                    "max_error_table_r0_89deg": e.printed[1].abs,
                })
            })
            .collect();
        println!(
            "{}",
            json!({"out": a.out, "files": report.files, "max_error": errors})
        );
    }
    ExitCode::SUCCESS
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
            "{:<36} {:<16} {:>10} {:>10}  result",
            "check", "source", "max error", "tolerance"
        );
        for r in &results {
            println!(
                "{:<36} {:<16} {:>10.2e} {:>10.1e}  {}",
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

/// A rotation vector `X,Y,Z`.
fn parse_rotvec(text: &str) -> psh::Result<[f64; 3]> {
    let parts: Vec<&str> = text.split(',').collect();
    let bad = |reason: &str| Error::InvalidRotation {
        value: text.to_string(),
        reason: reason.into(),
    };
    if parts.len() != 3 {
        return Err(bad("expected three comma-separated numbers X,Y,Z"));
    }
    let mut v = [0.0; 3];
    for (c, p) in v.iter_mut().zip(&parts) {
        *c = p.trim().parse().map_err(|_| bad("not a number"))?;
    }
    Ok(v)
}

fn project(a: &ProjectArgs) -> psh::Result<serde_json::Value> {
    let codomain = Codomain::from_name(&a.codomain)?;
    psh::sh::check_lmax(a.lmax)?;
    let map = psh::io::exr::read_stokes_map(&a.input)?;
    let v = map.project(codomain, a.lmax)?;
    psh::io::npz::write_psh_npz(&a.output, &v)?;
    Ok(json!({
        "input": a.input, "layout": [map.layout().height(), map.layout().width()],
        "channels": v.channels(), "lmax": v.lmax(), "codomain": codomain.name(),
        "output": a.output,
    }))
}

fn rotate(a: &RotateArgs) -> psh::Result<serde_json::Value> {
    let v = psh::io::npz::read_psh_npz(&a.input)?;
    let rotvec = parse_rotvec(&a.rotvec)?;
    let r = rotation_from_rotvec(rotvec)?;
    let rotated = PshRotation::new(&r, v.lmax())?.rotate(&v)?;
    psh::io::npz::write_psh_npz(&a.output, &rotated)?;
    Ok(json!({"input": a.input, "rotvec": rotvec, "lmax": v.lmax(), "output": a.output}))
}

fn convolve(a: &ConvolveArgs) -> psh::Result<serde_json::Value> {
    let v = psh::io::npz::read_psh_npz(&a.input)?;
    let (kernel, name) = match (&a.kernel, &a.kernel_table) {
        (Some(KernelName::LinearZenith), _) => (
            psh::polarized::ConvolutionKernel::linear_zenith(),
            "linear-zenith".to_string(),
        ),
        (None, Some(path)) => (
            psh::io::kernel_csv::read_kernel_csv(path)?,
            path.display().to_string(),
        ),
        (None, None) => unreachable!("clap requires --kernel or --kernel-table"),
    };
    let k = psh::polarized::kernel_coefficients(&kernel, v.lmax())?;
    let out = k.convolve(&v)?;
    psh::io::npz::write_psh_npz(&a.output, &out)?;
    Ok(json!({
        "input": a.input, "kernel": name, "lmax": v.lmax(),
        "quadrature_error_estimate": k.error_estimate(), "output": a.output,
    }))
}

fn reconstruct(a: &ReconstructArgs) -> psh::Result<serde_json::Value> {
    let layout = match (&a.equirect, a.cube) {
        (Some(size), _) => {
            let bad = || Error::InvalidArgument {
                name: "--equirect",
                value: size.clone(),
                reason: "expected H,W with W = 2H (rows, columns)".into(),
            };
            let hw: Vec<usize> = size
                .split(',')
                .map(|x| x.trim().parse().map_err(|_| bad()))
                .collect::<psh::Result<_>>()?;
            match hw[..] {
                [h, w] if h > 0 && w == 2 * h => MapLayout::from_image_size(h, w)?,
                _ => return Err(bad()),
            }
        }
        (None, Some(e)) => MapLayout::CubeCross(psh::geometry::image_grid::CubeCross::new(e)?),
        (None, None) => unreachable!("clap requires --equirect or --cube"),
    };
    let v = psh::io::npz::read_psh_npz(&a.input)?;
    let map = StokesMap::reconstruct(&v, layout)?;
    let mut written = psh::io::exr::write_stokes_map(&map, &format!("{}_s%d.exr", a.output))?;
    written.extend(psh::io::png::write_map_pngs(&map, &a.output)?);
    Ok(json!({"input": a.input, "lmax": v.lmax(), "written": written}))
}

fn eval_wigner(a: &WignerArgs) -> psh::Result<serde_json::Value> {
    let v = parse_rotvec(&a.rotvec)?;
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
