//! `psh pbrdf`: a measured table (a `.pbsdf` written by psh from its plastic model)
//! described and projected, and bad tables refused.

use crate::mat;
use std::path::Path;
use std::process::Command;

fn psh(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_psh"))
        .args(args)
        .output()
        .expect("run psh")
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `n` samples from `lo` to `hi`, both included.
fn line(n: usize, lo: f64, hi: f64) -> Vec<f64> {
    (0..n)
        .map(|k| lo + (hi - lo) * k as f64 / (n - 1) as f64)
        .collect()
}

#[test]
fn a_table_is_described_and_projected() {
    use std::f64::consts::{FRAC_PI_2, PI};
    let d = std::env::temp_dir().join(format!("psh_pbrdf_cli_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let model = psh::optics::PolarizedPlastic::new(0.4, 1.5, 0.3).unwrap();
    let table = psh::optics::TabulatedPbrdf::sample(
        &[&model, &model],
        line(37, -PI, PI),
        line(10, 0.0, FRAC_PI_2),
        line(10, 0.0, FRAC_PI_2),
        vec![500.0, 600.0],
    )
    .unwrap();
    let path = d.join("plastic.pbsdf");
    psh::io::write_pbsdf(&path, &table).unwrap();
    let out = psh(&["pbrdf", "info", s(&path)]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let info: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(info["phi_d"]["samples"], 37);
    assert_eq!(info["wavelengths_nm"], serde_json::json!([500.0, 600.0]));
    assert_eq!(info["invalid_fraction"], 0.0);
    let npz = d.join("plastic.npz");
    let out = psh(&["pbrdf", "project", s(&path), "--lmax", "3", "-o", s(&npz)]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["grid_lmax"], 19);
    let residual = report["band_limit_residual"].as_f64().unwrap();
    assert!(residual > 0.0 && residual < 1.0, "{residual}");
    let m = psh::io::read_isotropic_npz(&npz).unwrap();
    assert_eq!((m.lmax(), m.channels()), (3, 2));
    // The command's matrix is the library's projection of the table it read, on the
    // default grid of a table.
    let read = psh::io::read_pbsdf(&path).unwrap();
    let dense = psh::polarized::project_operator(
        &read.channel(1).unwrap(),
        3,
        psh::polarized::table_grid(3),
        psh::polarized::SpinBlock22::ComplexPair,
    )
    .unwrap();
    let want = psh::polarized::IsotropicMatrix::from_dense(&dense, 1e-6).unwrap();
    // The file holds polarsh's convention (travel -> travel): converted back first.
    let got = m.with_input(want.input()).unwrap().to_dense(1).unwrap();
    let back = want.to_dense(0).unwrap();
    assert_eq!((got.input(), got.output()), (back.input(), back.output()));
    let diff = got
        .data()
        .iter()
        .zip(back.data())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(diff < 1e-12, "{diff:e}");
    // A truncated table and an output over the input are refused, naming them.
    let bytes = std::fs::read(&path).unwrap();
    let cut = d.join("cut.pbsdf");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let out = psh(&["pbrdf", "project", s(&cut), "--lmax", "3", "-o", s(&npz)]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("cut.pbsdf") && err.contains("'M'"), "{err}");
    let out = psh(&["pbrdf", "project", s(&path), "--lmax", "3", "-o", s(&path)]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("does not overwrite"));
    std::fs::remove_dir_all(&d).unwrap();
}

/// `--rgb`: a spectrally flat table on the KAIST bands gives R, G and B equal to the
/// matrix of any one band (the dataset's weights sum to 1 per channel).
#[test]
fn rgb_channels_of_a_flat_table() {
    use std::f64::consts::{FRAC_PI_2, PI};
    let d = std::env::temp_dir().join(format!("psh_pbrdf_rgb_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let model = psh::optics::PolarizedPlastic::new(0.4, 1.5, 0.3).unwrap();
    let bands = psh::optics::KAIST_BANDS_NM.to_vec();
    let fields: Vec<&dyn psh::stokes::MuellerField> = vec![&model; 5];
    let table = psh::optics::TabulatedPbrdf::sample(
        &fields,
        line(19, -PI, PI),
        line(7, 0.0, FRAC_PI_2),
        line(7, 0.0, FRAC_PI_2),
        bands,
    )
    .unwrap();
    let path = d.join("flat.pbsdf");
    psh::io::write_pbsdf(&path, &table).unwrap();
    let (bands_npz, rgb_npz) = (d.join("bands.npz"), d.join("rgb.npz"));
    for (out, extra) in [(&bands_npz, None), (&rgb_npz, Some("--rgb"))] {
        let mut args = vec!["pbrdf", "project", s(&path), "--lmax", "2", "-o", s(out)];
        args.extend(extra);
        let o = psh(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let bands = psh::io::read_isotropic_npz(&bands_npz).unwrap();
    let rgb = psh::io::read_isotropic_npz(&rgb_npz).unwrap();
    assert_eq!((bands.channels(), rgb.channels()), (5, 3));
    let one = bands.to_dense(2).unwrap();
    for c in 0..3 {
        let got = rgb.to_dense(c).unwrap();
        let diff = got
            .data()
            .iter()
            .zip(one.data())
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        // float32 storage of the table, weighted sums of five bands.
        assert!(diff < 1e-6, "channel {c}: {diff:e}");
    }
    std::fs::remove_dir_all(&d).unwrap();
}

/// KAIST MAT-files from the command line: a table of NaN alone, and a variable whose
/// values (8 bytes each, twice) exceed the memory budget though the file fits it, are
/// clear errors naming them.
#[test]
fn nan_only_and_over_budget_mat_files_are_refused() {
    let d = std::env::temp_dir().join(format!("psh_pbrdf_mat_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let angles = |n: usize, hi: f64| line(n, 0.0, hi);
    let vars = |values: Vec<f64>| {
        vec![
            ("phi_d", vec![1, 3], line(3, -3.0, 3.0)),
            ("theta_d", vec![1, 2], angles(2, 1.5)),
            ("theta_h", vec![1, 2], angles(2, 1.5)),
            ("wvls", vec![1, 1], vec![550.0]),
            ("pbrdf_T_f", vec![3, 2, 2, 1, 4, 4], values),
        ]
    };
    let nan = d.join("nan.mat");
    std::fs::write(&nan, mat::file(&vars(vec![f64::NAN; 192]))).unwrap();
    let out = psh(&["pbrdf", "info", s(&nan)]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("nan.mat") && err.contains("every one NaN"),
        "{err}"
    );
    // 4,000 single values: a 16 kB file, 64 kB as f64 twice.
    let big = d.join("big.mat");
    std::fs::write(&big, mat::file(&[("x", vec![1, 4000], vec![0.5; 4000])])).unwrap();
    let out = psh(&["pbrdf", "info", s(&big), "--max-memory", "32K"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("MAT variable 'x'"), "{err}");
    std::fs::remove_dir_all(&d).unwrap();
}
