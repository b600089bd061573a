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
    let mut options = BenchErrorOptions::default();
    options.l_max = 3;
    options.rays = 16;
    options.spp = vec![1, 4];
    options.ground_truth_spp = 16;
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
    let mut bad = options.clone();
    bad.l_max = 7;
    let e = bench_error(&scene, &bad, &dir, &psh::progress::Silent)
        .unwrap_err()
        .to_string();
    assert!(e.contains("l_max 7"), "{e}");
}

/// An outside ground truth read from a Stokes image EXR with layers `S0..S3` (Mitsuba 3's
/// layout, written here with the `exr` crate): PPRT's own render written so and read back
/// is the ground truth of the matching row, whose RMSE is then the file's f32 rounding;
/// a file of another size is refused naming both sizes.
#[test]
fn bench_error_takes_an_outside_ground_truth() {
    use exr::prelude::*;
    use psh::apps::bench_error::{bench_error, ground_truth_image, BenchErrorOptions};
    use psh::pprt::{
        stages::{direct_light, precompute_planned, primary_hits, render_frame},
        Plan,
    };
    let dir = std::env::temp_dir().join(format!("psh-outside-truth-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = builtin_scene(3, 20, 15).unwrap();
    let settings = psh::pprt::TransferSettings::new(3, None, 16, psh::pprt::Visibility::Rays);
    let plan = Plan::new(&scene, settings, psh::pprt::Planning::Full).unwrap();
    let transfer = precompute_planned(&scene, &plan, &psh::progress::Silent).unwrap();
    let hits = primary_hits(&scene);
    let direct = direct_light(&scene, &hits).unwrap();
    let image = render_frame(&scene, &transfer, &plan.high_fields(), &hits, &direct).unwrap();
    let (w, h) = (image.width, image.height);
    let mut list = Vec::new();
    for p in 0..4 {
        for (c, name) in ["R", "G", "B"].iter().enumerate() {
            let values: Vec<f32> = image.channels[c].iter().map(|s| s[p] as f32).collect();
            let channel = format!("S{p}.{name}");
            list.push(AnyChannel::new(channel.as_str(), FlatSamples::F32(values)));
        }
    }
    let layer = Layer::new(
        (w, h),
        LayerAttributes::default(),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(list.into()),
    );
    let path = dir.join("truth.exr");
    Image::from_layer(layer).write().to_file(&path).unwrap();
    let read = psh::io::read_stokes_image(&path).unwrap();
    let truth = ground_truth_image(&scene, read).unwrap();
    let mut options = BenchErrorOptions::default();
    options.l_max = 3;
    options.rays = 16;
    options.spp = vec![1];
    options.ground_truth_spp = 4;
    options.ground_truth = Some(truth);
    let report = bench_error(&scene, &options, &dir, &psh::progress::Silent).unwrap();
    assert_eq!(report.ground_truth, "outside image");
    let row = report
        .rows
        .iter()
        .find(|r| r.method == "pprt" && r.setting == "low_only" && r.l_max == Some(3))
        .unwrap();
    assert!(row.rmse.iter().all(|&e| e < 1e-6), "{:?}", row.rmse);
    let other = report
        .rows
        .iter()
        .find(|r| r.method == "pprt" && r.l_max == Some(2))
        .unwrap();
    assert!(other.rmse[0] > 1e-4, "{:?}", other.rmse);
    let small = builtin_scene(3, 10, 8).unwrap();
    let e = ground_truth_image(&small, psh::io::read_stokes_image(&path).unwrap())
        .unwrap_err()
        .to_string();
    assert!(e.contains("20 x 15") && e.contains("10 x 8"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
