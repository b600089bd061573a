//! The command line: JSON output of `psh eval`, one-line errors and exit codes.

use std::process::Command;

fn psh(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_psh"))
        .args(args)
        .output()
        .expect("run psh")
}

#[test]
fn eval_sh_prints_flat_values() {
    let out = psh(&[
        "eval", "sh", "--kind", "complex", "--lmax", "2", "--theta", "0.3", "--phi", "-1.2",
    ]);
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["lmax"], 2);
    assert_eq!(v["kind"], "complex");
    let values = v["values"].as_array().unwrap();
    assert_eq!(values.len(), 9);
    // Y_00 = 1/sqrt(4 pi); Y_1,1 = -sqrt(3/(8 pi)) sin(theta) e^{i phi}.
    assert!((values[0][0].as_f64().unwrap() - 0.28209479177387814).abs() < 1e-16);
    let y11 = -(3.0 / (8.0 * std::f64::consts::PI)).sqrt() * 0.3f64.sin();
    assert!((values[3][0].as_f64().unwrap() - y11 * (-1.2f64).cos()).abs() < 1e-15);
    assert!((values[3][1].as_f64().unwrap() - y11 * (-1.2f64).sin()).abs() < 1e-15);
}

#[test]
fn eval_wigner_prints_blocks() {
    let out = psh(&[
        "eval",
        "wigner",
        "--kind",
        "real",
        "--lmax",
        "2",
        "--rotvec",
        "0,0,1.5707963267948966",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let blocks = v["blocks"].as_array().unwrap();
    assert_eq!(blocks.len(), 3);
    assert_eq!(blocks[2].as_array().unwrap().len(), 25);
    // A quarter turn about z maps Y^R_{1,1} ~ x to y ~ Y^R_{1,-1}: block 1 is the
    // permutation [[0,0,-1],[0,1,0],[1,0,0]] up to rounding (rows m = -1, 0, 1).
    let b1: Vec<f64> = blocks[1]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p[0].as_f64().unwrap())
        .collect();
    let expect = [0.0, 0.0, 1.0, 0.0, 1.0, 0.0, -1.0, 0.0, 0.0];
    for (x, e) in b1.iter().zip(expect) {
        assert!((x - e).abs() < 1e-15, "{b1:?}");
    }
}

#[test]
fn eval_swsh_prints_spin_two_values() {
    let out = psh(&[
        "eval", "swsh", "--spin", "2", "--lmax", "3", "--theta", "0", "--phi", "0.5",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let values = v["values"].as_array().unwrap();
    assert_eq!(values.len(), 16);
    // l < 2 are zeros; at the north pole only m = -2 survives (PSH (27)), with modulus
    // sqrt((2l+1)/(4 pi)) and phase e^{-2 i phi}.
    for (i, p) in values.iter().enumerate() {
        let (re, im) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
        let (l, m) = psh::sh::lm_of_index(i);
        if l >= 2 && m == -2 {
            let e = ((2 * l + 1) as f64 / (4.0 * std::f64::consts::PI)).sqrt();
            assert!(
                (re - e * (-1.0f64).cos()).abs() < 1e-14
                    && (im - e * (-1.0f64).sin()).abs() < 1e-14
            );
        } else {
            assert!(re.abs() < 1e-15 && im.abs() < 1e-15, "l {l} m {m}");
        }
    }
}

#[test]
fn bad_arguments_give_one_line_errors() {
    for args in [
        &[
            "eval", "sh", "--kind", "real", "--lmax", "2", "--theta", "nan", "--phi", "0",
        ][..],
        &[
            "eval", "sh", "--kind", "real", "--lmax", "2", "--theta", "4", "--phi", "0",
        ],
        &[
            "eval", "sh", "--kind", "real", "--lmax", "99999", "--theta", "1", "--phi", "0",
        ],
        &[
            "eval",
            "sh",
            "--kind",
            "imaginary",
            "--lmax",
            "2",
            "--theta",
            "1",
            "--phi",
            "0",
        ],
        &[
            "eval", "wigner", "--kind", "real", "--lmax", "2", "--rotvec", "0,0,0",
        ],
        &[
            "eval", "wigner", "--kind", "real", "--lmax", "2", "--rotvec", "1,inf,0",
        ],
        &[
            "eval", "wigner", "--kind", "real", "--lmax", "2", "--rotvec", "1,2",
        ],
    ] {
        let out = psh(args);
        assert!(!out.status.success(), "{args:?} succeeded");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(out.stdout.is_empty());
    }
}

#[test]
fn verify_json_follows_the_contract() {
    let out = psh(&["verify", "--json", "--filter", "zonal"]);
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let checks = v.as_array().unwrap();
    assert!(!checks.is_empty());
    for c in checks {
        for key in [
            "id",
            "source",
            "description",
            "max_error",
            "tolerance",
            "passed",
        ] {
            assert!(c.get(key).is_some(), "missing {key} in {c}");
        }
    }
}
