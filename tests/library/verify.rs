//! Runs every `psh verify` check in the test suite, one test per group, so that
//! `cargo test` fails exactly when `psh verify` would.

fn run_group(prefix: &str) {
    let results = psh::verify::run(Some(prefix));
    assert!(!results.is_empty(), "no check matches {prefix}");
    for r in &results {
        println!(
            "{:<28} {:<16} max error {:>9.2e}  tolerance {:>7.0e}  {}",
            r.id,
            r.source,
            r.max_error,
            r.tolerance,
            if r.passed { "pass" } else { "FAIL" }
        );
    }
    let failed: Vec<_> = results.iter().filter(|r| !r.passed).collect();
    assert!(failed.is_empty(), "failed checks: {failed:#?}");
}

#[test]
fn verify_sh() {
    run_group("sh.");
}

#[test]
fn verify_wigner() {
    run_group("wigner.");
}

#[test]
fn verify_transform() {
    run_group("transform.");
}

#[test]
fn verify_zonal() {
    run_group("zonal.");
}

#[test]
fn verify_gaunt() {
    run_group("gaunt.");
}

#[test]
fn verify_swsh() {
    run_group("swsh.");
}

#[test]
fn verify_stokes() {
    run_group("stokes.");
}

#[test]
fn verify_polarized() {
    run_group("polarized.");
}

#[test]
fn verify_optics() {
    run_group("optics.");
}

#[test]
fn verify_matrix() {
    run_group("matrix.");
}

#[test]
fn verify_triple() {
    run_group("triple.");
}

#[test]
fn verify_convolution() {
    run_group("conv.");
}

#[test]
fn verify_filter() {
    run_group("filter.");
}

#[test]
fn verify_pprt() {
    run_group("pprt.");
}

#[test]
fn verify_solid() {
    run_group("solid.");
}

#[test]
fn verify_lights() {
    run_group("lights.");
}

#[test]
fn verify_isd() {
    run_group("isd.");
}

#[test]
fn verify_polygon() {
    run_group("polygon.");
}
