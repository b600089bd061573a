//! Reports and demos that write a directory and print a table: `filter-report` (PF),
//! `lights-demo` (SHH), `polygon-lights-demo` (SHG), `isd-report` (ISD), `figures`.

use crate::terminal::TerminalProgress;
use crate::Outcome;
use clap::Args;
use psh::apps::{filter_report, isd_report, lights_demo, polygon_lights_demo};
use serde_json::json;
use std::path::PathBuf;
use std::process::ExitCode;

/// The output directory of a report.
#[derive(Args)]
pub struct OutDir {
    /// Output directory (created if missing).
    #[arg(long)]
    out: PathBuf,
}

#[derive(Args)]
pub struct FilterReportArgs {
    #[command(flatten)]
    out: OutDir,
    /// Print the largest errors as a Markdown table instead of JSON.
    #[arg(long)]
    markdown: bool,
}

#[derive(Args)]
pub struct FiguresArgs {
    #[command(flatten)]
    out: OutDir,
    /// Only these figures (numbers such as 5,10 or stems such as fig10).
    #[arg(long, value_delimiter = ',')]
    only: Vec<String>,
    /// Smaller sizes: every figure in under a minute on 2 vCPUs.
    #[arg(long)]
    quick: bool,
    /// A Python interpreter with the `mitsuba` package (Mitsuba 3): PSH Fig. 19 also
    /// against Mitsuba 3's renders of scenes/mitsuba_sky.toml and, under the polarized
    /// sky through psh's plugin, scenes/mitsuba_polarized_sky.toml.
    #[arg(long)]
    mitsuba: Option<PathBuf>,
}

/// Prints a report's text as it is.
fn printed(text: String) -> Outcome {
    out!("{text}");
    Outcome::Exit(ExitCode::SUCCESS)
}

pub fn lights_demo(a: &OutDir) -> psh::Result<Outcome> {
    lights_demo::write_lights_demo(&a.out).map(|r| printed(r.markdown_table()))
}

pub fn polygon_lights_demo(a: &OutDir) -> psh::Result<Outcome> {
    polygon_lights_demo::write_polygon_lights_demo(
        &a.out,
        polygon_lights_demo::PAPER_FINEST,
        &TerminalProgress::new(),
    )
    .map(|r| printed(r.markdown_table()))
}

pub fn isd_report(a: &OutDir) -> psh::Result<Outcome> {
    isd_report::write_isd_report(&a.out, isd_report::PAPER_TOP, &TerminalProgress::new())
        .map(|r| printed(r.markdown_table()))
}

pub fn figures(a: &FiguresArgs) -> psh::Result<Outcome> {
    use psh::figures;
    let mut options = figures::FigureOptions::default();
    options.quick = a.quick;
    options.mitsuba = a.mitsuba.clone();
    let done = |r: &figures::FigureReport| {
        let verdict = r.comparison.as_ref().map_or(String::new(), |c| {
            let holds = if c.holds { "holds" } else { "DOES NOT HOLD" };
            format!(": {} ({holds})", c.measured)
        });
        outln!("{} in {:.2} s{verdict}", r.id, r.seconds);
    };
    let out = &a.out.out;
    let selected = figures::select(&a.only)?;
    figures::run(&selected, out, &options, &TerminalProgress::new(), &done)?;
    Ok(printed(format!(
        "figures and figures.md written to {}\n",
        out.display()
    )))
}

pub fn filter_report(a: &FilterReportArgs) -> psh::Result<Outcome> {
    let report = filter_report::write_filter_report(&a.out.out)?;
    if a.markdown {
        return Ok(printed(report.markdown_table()));
    }
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
    Ok(Outcome::Json(
        json!({"out": a.out.out, "files": report.files, "max_error": errors}),
    ))
}
