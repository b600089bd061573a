//! `psh verify`: the library's checks as a table or JSON.

use clap::Args;
use std::process::ExitCode;

#[derive(Args)]
pub struct VerifyArgs {
    /// Print a JSON array of {"id","source","description","max_error","tolerance","passed"}.
    #[arg(long)]
    json: bool,
    /// Run only the checks whose id contains this text.
    #[arg(long)]
    filter: Option<String>,
}

/// Runs the checks; exit 1 if one fails, 2 if the filter matches none.
pub fn run(a: &VerifyArgs) -> ExitCode {
    let filter = a.filter.as_deref();
    let results = psh::verify::run(filter);
    if let (true, Some(f)) = (results.is_empty(), filter) {
        eprintln!(
            "error: no check id contains {:?} (`psh verify` without --filter lists them all)",
            psh::error::clip(f)
        );
        return ExitCode::from(2);
    }
    if a.json {
        outln!(
            "{}",
            serde_json::to_string_pretty(&results).expect("plain data")
        );
    } else {
        print_table(&results);
    }
    if results.iter().all(|r| r.passed) {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

/// The results as a table with a count line.
fn print_table(results: &[psh::verify::CheckResult]) {
    outln!(
        "{:<36} {:<16} {:>10} {:>10}  result",
        "check",
        "source",
        "max error",
        "tolerance"
    );
    for r in results {
        outln!(
            "{:<36} {:<16} {:>10.2e} {:>10.1e}  {}",
            r.id,
            r.source,
            r.max_error,
            r.tolerance,
            match (r.passed, &r.skipped) {
                (_, Some(_)) => "skip",
                (true, None) => "pass",
                (false, None) => "FAIL",
            }
        );
        if let Some(e) = &r.error {
            outln!("    error: {e}");
        }
        if let Some(s) = &r.skipped {
            outln!("    skipped: {s}");
        }
    }
    let failed = results.iter().filter(|r| !r.passed).count();
    let skipped = results.iter().filter(|r| r.skipped.is_some()).count();
    outln!(
        "{} passed, {} failed, {} skipped",
        results.len() - failed - skipped,
        failed,
        skipped
    );
}
