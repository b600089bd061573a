//! The `psh` command line: one module per command family, each with its arguments beside
//! the function that runs them.
//!
//! | command | module |
//! |---|---|
//! | `render` (bare `psh-render`, the default run target), `bench-error`, `export-mitsuba` | [`render`], [`scene_jobs`] |
//! | `project`, `rotate`, `reconstruct`, `convolve`, `apply` | [`coefficients`] |
//! | `eval ...` (basis functions, rotations, transforms, optics) | [`eval`] |
//! | `pbrdf info`, `pbrdf project` (measured tables) | [`pbrdf`] |
//! | `filter-report`, `lights-demo`, `polygon-lights-demo`, `isd-report`, `figures` | [`reports`] |
//! | `verify` | [`verify`] |
//! | `view` (feature `view`) | [`view`] |

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// `print!` that ends the process quietly (exit 0) when standard output is a closed pipe
/// (`psh eval ... | head`) instead of panicking; other write errors exit 1.
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::terminal::write_stdout(format_args!($($arg)*))
    };
}

/// [`out!`] with a newline.
macro_rules! outln {
    ($($arg:tt)*) => {
        $crate::terminal::write_stdout(format_args!("{}\n", format_args!($($arg)*)))
    };
}

mod args;
mod coefficients;
mod eval;
mod pbrdf;
mod render;
mod reports;
mod scene_jobs;
mod terminal;
mod verify;
#[cfg(feature = "view")]
mod view;

#[derive(Parser)]
#[command(
    name = "psh",
    version,
    about = "Spherical harmonics for polarized light transport",
    after_help = "Start with `psh render` (the built-in scene into ./psh-out: what \
                  `cargo run --release` runs) or `psh verify` (the library's checks)."
)]
struct Cli {
    /// Memory budget for work sized by the input (bytes, or with K, M, G, T: powers of
    /// 1024); default 4G, or $PSH_MAX_MEMORY. Work over it stops with an error naming the
    /// bytes it needs.
    #[arg(long, global = true, value_parser = psh::budget::parse_bytes)]
    max_memory: Option<u64>,
    /// Format of the line plots written (bench-error, filter-report, isd-report, figures):
    /// png, or svg or pdf for papers
    #[arg(long, global = true, default_value = "png", value_parser = ["png", "svg", "pdf"])]
    plot_format: String,
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Run the library's checks and print a table (or JSON); non-zero exit if any fails.
    Verify(verify::VerifyArgs),
    /// Evaluate basis functions or rotation matrices, printing JSON.
    #[command(subcommand)]
    Eval(eval::Eval),
    /// Project a polarized environment map (EXR, one file per Stokes component) to PSH
    /// coefficients, written as a polarsh-compatible .npz.
    Project(coefficients::ProjectArgs),
    /// Rotate a PSH coefficient vector (.npz) in the frequency domain (PSH (35)-(37)).
    Rotate(coefficients::RotateArgs),
    /// Reconstruct a PSH coefficient vector (.npz) on an image (--equirect or --cube): EXR
    /// per Stokes component and PNG pictures (s0..s3, degree and angle of polarization).
    Reconstruct(coefficients::ReconstructArgs),
    /// Write the polarizing factor psi of PF Table 1's materials and the error of its
    /// specular-colour approximation (PF Fig. 3, Fig. 5) as CSV and PNG plots into a
    /// directory; print the largest errors (JSON, or a Markdown table).
    FilterReport(reports::FilterReportArgs),
    /// Convolve a PSH coefficient vector (.npz) with a polarized kernel k(theta) (--kernel
    /// or --kernel-table) by the convolution theorem (PSH (68)-(69)), writing a POLAR4 .npz.
    Convolve(coefficients::ConvolveArgs),
    /// Apply an isotropic pBRDF coefficient matrix (ISOBI2 .npz, one matrix per channel) to
    /// a PSH coefficient vector (.npz) cut to the matrix's band limit (PSH (41)), writing the
    /// reflected field as a POLAR4 .npz; both files in polarsh's convention.
    Apply(coefficients::ApplyArgs),
    /// Measured pBRDF tables (Mitsuba 3 .pbsdf, KAIST dataset MAT-files): `info`, and
    /// `project` to isotropic PSH coefficient matrices (ISOBI2 .npz).
    #[command(subcommand)]
    Pbrdf(pbrdf::Pbrdf),
    /// Render a scene by precomputed polarized radiance transfer (PSH Sec. 7), or by the
    /// reference renderer (--reference), or the ablation (--ablation): pictures and
    /// report.json into a directory (without a scene: the built-in one into ./psh-out, as
    /// `cargo run --release` and bare `psh-render` do).
    Render(render::RenderArgs),
    /// Many spherical lights: uniform grids vs a Hessian-adaptive grid (SHH Sec. 5, 6.2),
    /// errors against the per-point exact SH coefficients; writes table.md and
    /// false-colour error images into a directory and prints the table (Markdown).
    LightsDemo(reports::OutDir),
    /// Many triangular lights (SHG): per-point exact SH coefficients vs grids of
    /// coefficients and gradients interpolated trilinearly and by cubic Hermite;
    /// writes table.md and error images into --out.
    PolygonLightsDemo(reports::OutDir),
    /// Isotropic spherical decomposition: condition numbers of M against L (ISD Fig. 13)
    /// as CSV and PNG, and ISD filtering timed against SH rotation; writes into a
    /// directory and prints the tables (Markdown).
    IsdReport(reports::OutDir),
    /// Run time against error: PPRT at l_max = 2..9 (full, no_shadow, low_only) and the
    /// reference renderer at a ladder of samples, against a high-sample ground truth;
    /// writes bench-error.json, .csv, .png and fig19.png (PSH Fig. 19) into a directory.
    BenchError(scene_jobs::BenchErrorArgs),
    /// The paper's computable figures (PSH Figs. 5, 7, 8, 10, 11, 13, 16, 17, 19-22) as
    /// labelled PNGs, each with figN.md (caption, equations, the `psh verify` checks, the numbers),
    /// and the gallery figures.md into a directory; non-zero exit if a figure's
    /// comparison does not hold.
    Figures(reports::FiguresArgs),
    /// The scene as a Mitsuba 3 scene (scene.xml, PLY meshes, the environment as a lat-long
    /// EXR, docs/mitsuba.md) into a directory; prints the files and the ways Mitsuba's
    /// scene differs from psh's (JSON).
    ExportMitsuba(scene_jobs::ExportMitsubaArgs),
    /// The scene interactive in a browser (docs/view.md): precomputes it, prints a URL on
    /// 127.0.0.1 and serves a page that orbits the camera, turns the environment and a
    /// polarizer, shows s0..s3, DoP, AoLP, and saves the view as `psh render` would.
    #[cfg(feature = "view")]
    View(view::ViewArgs),
}

/// Every argument that takes a value accepts a negative number as one (`--tolerance -0.5`
/// is the value -0.5, which psh then refuses with its reason, not an unknown flag).
fn allow_negative_numbers(cmd: clap::Command) -> clap::Command {
    cmd.mut_args(|a| {
        if a.get_action().takes_values() {
            a.allow_negative_numbers(true)
        } else {
            a
        }
    })
    .mut_subcommands(allow_negative_numbers)
}

/// What a command ended with: JSON to print, or an exit code of its own (it printed).
enum Outcome {
    Json(serde_json::Value),
    Exit(ExitCode),
}

impl From<serde_json::Value> for Outcome {
    fn from(v: serde_json::Value) -> Self {
        Outcome::Json(v)
    }
}

/// Whether this program runs as `psh-render`, the repository's default run target
/// (`cargo run --release`): the same command line, whose bare invocation renders the
/// built-in scene (`psh render`); bare `psh` prints its commands instead.
fn invoked_as_render() -> bool {
    std::env::args_os()
        .next()
        .and_then(|a| {
            std::path::Path::new(&a)
                .file_stem()
                .map(|s| s == "psh-render")
        })
        .unwrap_or(false)
}

fn main() -> ExitCode {
    use clap::{CommandFactory, FromArgMatches};
    // Interrupted (SIGINT, SIGTERM, SIGHUP), psh removes its temporary files and exits:
    // the outputs stay as they were.
    let _ = ctrlc::set_handler(|| {
        psh::io::remove_partial_outputs();
        std::process::exit(130);
    });
    let parsed = allow_negative_numbers(Cli::command())
        .try_get_matches()
        .and_then(|m| Cli::from_arg_matches(&m));
    let cli = match parsed {
        Ok(c) => c,
        Err(e) => {
            use clap::error::ErrorKind::{DisplayHelp, DisplayVersion};
            if matches!(e.kind(), DisplayHelp | DisplayVersion) {
                out!("{e}");
                return ExitCode::SUCCESS;
            }
            // clap's whole message: the error, the usage, and its suggestions.
            eprint!("{e}");
            return ExitCode::from(2);
        }
    };
    if let Ok(format) = psh::apps::plot::PlotFormat::from_name(&cli.plot_format) {
        psh::apps::plot::set_plot_format(format);
    }
    if let Some(bytes) = cli.max_memory {
        psh::budget::set_budget(bytes);
    }
    let result = match cli.command {
        None if invoked_as_render() => render::run_default(),
        None => {
            out!("{}", Cli::command().render_long_help());
            return ExitCode::SUCCESS;
        }
        Some(Command::Verify(a)) => Ok(Outcome::Exit(verify::run(&a))),
        Some(Command::Eval(e)) => eval::run(&e).map(Outcome::from),
        Some(Command::Project(a)) => coefficients::project(&a).map(Outcome::from),
        Some(Command::Rotate(a)) => coefficients::rotate(&a).map(Outcome::from),
        Some(Command::Reconstruct(a)) => coefficients::reconstruct(&a).map(Outcome::from),
        Some(Command::Convolve(a)) => coefficients::convolve(&a).map(Outcome::from),
        Some(Command::Apply(a)) => coefficients::apply(&a).map(Outcome::from),
        Some(Command::Pbrdf(p)) => pbrdf::run(&p).map(Outcome::from),
        Some(Command::Render(a)) => render::run(&a),
        Some(Command::BenchError(a)) => scene_jobs::bench_error(&a).map(Outcome::from),
        Some(Command::ExportMitsuba(a)) => scene_jobs::export_mitsuba(&a).map(Outcome::from),
        Some(Command::FilterReport(a)) => reports::filter_report(&a),
        Some(Command::LightsDemo(a)) => reports::lights_demo(&a),
        Some(Command::PolygonLightsDemo(a)) => reports::polygon_lights_demo(&a),
        Some(Command::IsdReport(a)) => reports::isd_report(&a),
        Some(Command::Figures(a)) => reports::figures(&a),
        #[cfg(feature = "view")]
        Some(Command::View(a)) => view::run(&a),
    };
    match result {
        Ok(Outcome::Json(v)) => {
            outln!("{v}");
            ExitCode::SUCCESS
        }
        Ok(Outcome::Exit(code)) => code,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}
