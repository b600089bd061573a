//! The reference renderer (`pprt::reference`) against PPRT: integrating exactly what
//! unshadowed PPRT integrates (the band-limited environment and pBRDF matrices over the
//! whole sphere), it converges to the PPRT vertex values as the samples grow.

use psh::pprt::builtin_scene;

/// The error falls like a quasi-Monte Carlo rate on a smooth integrand (expected slope
/// near -1; plain Monte Carlo would give -0.5).
#[test]
fn reference_converges_to_pprt_on_a_band_limited_scene() {
    let ladder = [64, 256, 1024, 4096];
    let errors: Vec<f64> = ladder
        .iter()
        .map(|&n| psh::verify::pprt_reference_discrepancy(n).unwrap())
        .collect();
    let slope = (errors[3] / errors[0]).ln() / (4096f64 / 64.0).ln();
    println!(
        "RMS error relative to the largest s0 per sample count {ladder:?}: {errors:?}; \
         log-log slope {slope:.2}"
    );
    assert!(errors[3] < 1e-3, "{errors:?}");
    assert!(slope < -0.8, "{slope}");
}

/// `bench_error` writes the contract's JSON (and the CSV and plots): PPRT rows for every
/// band limit and setting, reference rows for every sample count and the band-limit floor.
#[test]
fn bench_error_writes_the_contract() {
    use psh::apps::bench_error::{bench_error, BenchErrorOptions};
    let dir = std::env::temp_dir().join(format!("psh-bench-error-{}", std::process::id()));
    let scene = builtin_scene(3, 24, 18).unwrap();
    let options = BenchErrorOptions {
        l_max: 3,
        rays: 16,
        spp: vec![1, 4],
        ground_truth_spp: 16,
    };
    let report = bench_error(&scene, &options, &dir, &psh::progress::Silent).unwrap();
    assert_eq!(report.ground_truth_spp, 16);
    let rows = &report.rows;
    assert_eq!(rows.len(), 2 * 3 + 2 + 1);
    for r in rows {
        assert!(r.rmse.iter().all(|x| x.is_finite()));
        assert!(r.frame_s > 0.0);
        assert!(["pprt", "reference"].contains(&r.method));
    }
    assert_eq!(rows[0].setting, "full");
    assert_eq!(rows[6].spp, Some(1));
    // The file holds the same report.
    let file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("bench-error.json")).unwrap())
            .unwrap();
    assert_eq!(file["rows"].as_array().unwrap().len(), rows.len());
    assert_eq!(file["ground_truth_spp"], 16);
    // The CSV filled row by row is renamed at the end.
    assert!(!dir.join("bench-error.partial.csv").exists());
    let csv = std::fs::read_to_string(dir.join("bench-error.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + rows.len());
    for f in [
        "bench-error.json",
        "bench-error.csv",
        "bench-error.png",
        "fig19.png",
    ] {
        assert!(dir.join(f).exists(), "{f}");
    }
    let bad = BenchErrorOptions {
        l_max: 7,
        ..options
    };
    let e = bench_error(&scene, &bad, &dir, &psh::progress::Silent)
        .unwrap_err()
        .to_string();
    assert!(e.contains("l_max 7"), "{e}");
}
