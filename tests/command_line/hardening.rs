//! Hostile input to the command line (issue 21): every case a clean error naming the
//! value, with exit 1 (psh's error) or 2 (usage), never a panic (101) or an abort, and
//! no memory allocated beyond the budget.

use std::process::{Command, Output};

fn psh(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_psh"))
        .args(args)
        .env_remove("PSH_MAX_MEMORY")
        .output()
        .expect("run psh")
}

fn dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("psh_hardening_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A polarsh `.npz` of one zero POLAR4 channel with `lmax = 3`, written by psh.
fn small_npz(d: &std::path::Path) -> String {
    let path = d.join("small.npz");
    let v = psh::polarized::PshVector::zeros(3, psh::polarized::Codomain::Full, 1).unwrap();
    psh::io::write_psh_npz(&path, &v).unwrap();
    path.to_str().unwrap().to_string()
}

/// A fresh directory with `small.npz`, and an output prefix in it.
fn setup(name: &str) -> (std::path::PathBuf, String, String) {
    let d = dir(name);
    let npz = small_npz(&d);
    let out = d.join("out").to_str().unwrap().to_string();
    (d, npz, out)
}

/// Runs `args`, expecting exit `code` and a message containing every one of `needles`.
fn refused(args: &[&str], code: i32, needles: &[&str]) {
    let out = psh(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(code), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    for n in needles {
        assert!(err.contains(n), "{args:?}: {err} lacks {n:?}");
    }
}

#[test]
fn reported_panics_are_clean_errors() {
    let (d, npz, out) = setup("panics");
    let out = out.as_str();
    refused(
        &[
            "eval",
            "swsh",
            "--spin",
            "-9223372036854775808",
            "--lmax",
            "3",
            "--theta",
            "1",
            "--phi",
            "1",
        ],
        1,
        &["spin", "-9223372036854775808"],
    );
    refused(
        &["reconstruct", &npz, "--cube", "1073741824", "-o", out],
        1,
        &["memory budget"],
    );
    refused(
        &[
            "reconstruct",
            &npz,
            "--cube",
            "4611686018427387904",
            "-o",
            out,
        ],
        1,
        &["cube map edge"],
    );
    refused(
        &[
            "render",
            "--size",
            "8x6",
            "--l-low",
            "2",
            "--l-high",
            "3",
            "--rays",
            "18446744073709551615",
            "--out",
            out,
        ],
        1,
        &["visibility rays", "memory budget"],
    );
    refused(
        &["render", "--size", "100000x100000", "--out", out],
        1,
        &["rendered image", "bytes"],
    );
    let scene = d.join("scene.toml");
    std::fs::write(
        &scene,
        "[environment]\ntype = \"sky\"\nsun_elevation_deg = 40.0\nsun_azimuth_deg = 120.0\n\n\
         [camera]\nposition = [0.0, -4.0, 1.5]\ntarget = [0.0, 0.0, 0.0]\nfov_deg = 35.0\n\
         width = 8\nheight = 6\n\n[[material]]\nname = \"p\"\n\
         type = \"plastic\"\nalpha = 0.5\nior = 1e300\nalbedo = 0.5\n\n[[mesh]]\ntype = \"sphere\"\n\
         center = [0.0, 0.0, 0.6]\nradius = 0.6\nmaterial = \"p\"\n",
    )
    .unwrap();
    refused(
        &["render", "--scene", scene.to_str().unwrap(), "--out", out],
        1,
        &["1e300"],
    );
}

#[test]
fn outputs_sized_by_input_are_checked_first() {
    // One channel at edge 2100: the map (3.0 GB of components and texel angles) fits the
    // 4 GiB budget, with its EXR files and pictures it does not (4.9 GB; a three-channel
    // map peaked at 7.4 GB at edge 1700 before the writers' memory was counted).
    let (_, npz, out) = setup("output_budget");
    refused(
        &["reconstruct", &npz, "--cube", "2100", "-o", &out],
        1,
        &["EXR files and pictures", "4868640000"],
    );
    // 8192: 67M complex values printed as JSON, about 8.6 GB.
    refused(
        &[
            "eval", "sh", "--kind", "real", "--lmax", "8192", "--theta", "1", "--phi", "0",
        ],
        1,
        &["printed SH values", "memory budget"],
    );
    refused(
        &[
            "eval",
            "sh",
            "--kind",
            "real",
            "--lmax",
            "9223372036854775807",
            "--theta",
            "1",
            "--phi",
            "0",
        ],
        1,
        &["9223372036854775807"],
    );
}

/// `psh eval ... | head`: a reader that closes the pipe early ends psh quietly, with no
/// panic message.
#[test]
fn a_closed_pipe_is_not_a_panic() {
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_psh"))
        .args([
            "eval", "sh", "--kind", "complex", "--lmax", "300", "--theta", "1", "--phi", "0",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(err.is_empty(), "{err}");
}

#[test]
fn degrees_past_i64_are_named_as_given() {
    for lmax in ["9223372036854775808", "18446744073709551615"] {
        refused(
            &[
                "eval", "sh", "--kind", "real", "--lmax", lmax, "--theta", "1", "--phi", "0",
            ],
            1,
            &["lmax", lmax],
        );
    }
}

/// Render settings are checked before the scene is loaded or projected: a scene file
/// whose environment does not exist is refused for its settings, not for the file, and
/// the built-in scene's `--l-low 2000` or `--l-high 8192` stop before any projection.
#[test]
fn render_settings_are_checked_before_any_work() {
    let d = dir("settings");
    let out = d.join("out");
    let out = out.to_str().unwrap();
    let scene = d.join("scene.toml");
    std::fs::write(
        &scene,
        "[environment]\ntype = \"npz\"\npath = \"missing.npz\"\n\n\
         [camera]\nposition = [0.0, -4.0, 1.5]\ntarget = [0.0, 0.0, 0.0]\nfov_deg = 35.0\n\
         width = 8\nheight = 6\n\n[settings]\nl_low = 2000\n\n[[material]]\nname = \"d\"\n\
         type = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\n[[mesh]]\ntype = \"sphere\"\n\
         center = [0.0, 0.0, 0.6]\nradius = 0.6\nmaterial = \"d\"\n",
    )
    .unwrap();
    refused(
        &["render", "--scene", scene.to_str().unwrap(), "--out", out],
        1,
        &["transfer settings", "l_low 2000"],
    );
    // With the settings overridden, the missing environment is the error.
    refused(
        &[
            "render",
            "--scene",
            scene.to_str().unwrap(),
            "--l-low",
            "3",
            "--out",
            out,
        ],
        1,
        &["missing.npz"],
    );
    for (flag, value) in [("--l-low", "2000"), ("--l-high", "8192")] {
        refused(
            &["render", "--size", "8x6", flag, value, "--out", out],
            1,
            &["transfer settings", value],
        );
    }
}

#[test]
fn the_memory_budget_is_set_by_flag_and_environment() {
    let (_, npz, out) = setup("budget");
    let out = out.as_str();
    // 200^2 x 12 texels x 4 components x 8 bytes: within 4 GiB, over 1 MiB.
    assert!(psh(&["reconstruct", &npz, "--cube", "20", "-o", out])
        .status
        .success());
    refused(
        &[
            "--max-memory",
            "1M",
            "reconstruct",
            &npz,
            "--cube",
            "200",
            "-o",
            out,
        ],
        1,
        &["1048576"],
    );
    refused(
        &[
            "reconstruct",
            &npz,
            "--cube",
            "200",
            "-o",
            out,
            "--max-memory",
            "12X",
        ],
        2,
        &["12X"],
    );
    // The projection's work space (not only its output) is checked: at lmax 1000 the
    // output (one channel: 32 MB) fits in 48 MiB, the output with the work space of the
    // order sums (about as much again) does not; both fit in 200 MiB.
    assert!(psh(&["reconstruct", &npz, "--cube", "8", "-o", out])
        .status
        .success());
    let project = |budget: &str| {
        let input = format!("{out}_s%d.exr");
        let output = format!("{out}.npz");
        let args = [
            "--max-memory",
            budget,
            "project",
            &input,
            "--lmax",
            "1000",
            "-o",
            &output,
        ];
        args.map(String::from)
    };
    let args = project("48M");
    refused(
        &args.iter().map(String::as_str).collect::<Vec<_>>(),
        1,
        &["work space", "50331648"],
    );
    let args = project("200M");
    let run = psh(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    // The transforms' recursion tables at lmax 4000 (about 1 GB) are checked before they
    // are built, for the scalar and the spin transforms alike.
    for sht in [["sht", "--kind"], ["spin-sht", "--spin"]] {
        let kind = if sht[0] == "sht" { "real" } else { "2" };
        refused(
            &[
                "--max-memory",
                "256M",
                "eval",
                sht[0],
                sht[1],
                kind,
                "--lmax",
                "4000",
                "--op",
                "synthesis",
                "--input",
                &npz,
                "--output",
                &format!("{out}.npy"),
            ],
            1,
            &["recursion tables", "268435456"],
        );
    }
    let env = Command::new(env!("CARGO_BIN_EXE_psh"))
        .args(["reconstruct", &npz, "--cube", "200", "-o", out])
        .env("PSH_MAX_MEMORY", "2M")
        .output()
        .unwrap();
    assert_eq!(env.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&env.stderr).contains("2097152"));
}

#[test]
fn usage_errors_say_everything() {
    // clap's whole message: every missing argument and the usage line.
    refused(
        &["project"],
        2,
        &["--lmax", "--output", "<INPUT>", "Usage: psh project"],
    );
    // A negative number is a value, refused by psh with the reason.
    refused(
        &[
            "render",
            "--tolerance",
            "-0.5",
            "--size",
            "8x6",
            "--out",
            "/nonexistent/x",
        ],
        1,
        &["tolerance", "-0.5"],
    );
    // A filter that matches no check is an error, not an empty success.
    refused(
        &["verify", "--filter", "no-such-check"],
        2,
        &["no-such-check"],
    );
}

/// Every file of `dir` with its bytes.
fn snapshot(d: &std::path::Path) -> Vec<(std::path::PathBuf, Vec<u8>)> {
    let mut files: Vec<_> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| {
            let bytes = std::fs::read(&p).unwrap();
            (p, bytes)
        })
        .collect();
    files.sort();
    files
}

/// A one-channel `lmax = 1` vector: `s0` coefficients of band 1 all `x`.
fn band1_npz(path: &std::path::Path, x: f64) {
    use psh::polarized::{Codomain, PshVector};
    let mut data = vec![0.0; 16];
    for i in 1..4 {
        data[4 * i] = x;
    }
    let v = PshVector::from_data(1, Codomain::Full, 1, data).unwrap();
    psh::io::write_psh_npz(path, &v).unwrap();
}

#[test]
fn outputs_are_finite_whole_and_never_over_inputs() {
    let d = dir("outputs");
    let s = |p: &std::path::Path| p.to_str().unwrap().to_string();
    let (big, huge, ok) = (d.join("big.npz"), d.join("huge.npz"), d.join("ok.npz"));
    band1_npz(&big, 1e200);
    band1_npz(&huge, 1.5e308);
    band1_npz(&ok, 1.0);
    let prefix = s(&d.join("map"));
    assert!(psh(&["reconstruct", &s(&ok), "--cube", "4", "-o", &prefix])
        .status
        .success());
    let rotated = d.join("rotated.npz");
    assert!(psh(&[
        "rotate",
        &s(&ok),
        "--rotvec",
        "0.1,0.2,0.3",
        "-o",
        &s(&rotated)
    ])
    .status
    .success());
    // This turn gives (-1.155, 0.577, -1.155) * 1.5e308, all finite: written, although
    // two of the three terms of a sum already pass f64::MAX (the sums run in SIMD lanes,
    // `polarized::rotation`). The opposite turn below puts (1, 1, 1) on an axis.
    let out = psh(&[
        "rotate",
        &s(&huge),
        "--rotvec",
        "0.6755,-0.6755,0",
        "-o",
        &s(&d.join("huge_rotated.npz")),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let before = snapshot(&d);
    // 1e200 is finite in f64 but not as the 32-bit float of an EXR texel: nothing of
    // the ten files is replaced, no temporary file stays.
    refused(
        &["reconstruct", &s(&big), "--cube", "4", "-o", &prefix],
        1,
        &["map_s0.exr", "finite"],
    );
    // (1, 1, 1) * 1.5e308 turned onto an axis is sqrt(3) * 1.5e308: infinite.
    let out = psh(&[
        "rotate",
        &s(&huge),
        "--rotvec",
        "-0.6755,0.6755,0",
        "-o",
        &s(&rotated),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.code() == Some(1) && err.contains("finite"),
        "{err}"
    );
    // An output that is an input, under another spelling, is refused before any work.
    let alias = s(&d.join(".").join("ok.npz"));
    refused(
        &["rotate", &s(&ok), "--rotvec", "0.1,0,0", "-o", &alias],
        1,
        &["does not overwrite"],
    );
    assert_eq!(snapshot(&d), before, "files changed by failed runs");
    // Reproducible: the same data gives the same bytes (no zip timestamps).
    let again = d.join("again.npz");
    assert!(psh(&[
        "rotate",
        &s(&ok),
        "--rotvec",
        "0.1,0.2,0.3",
        "-o",
        &s(&again)
    ])
    .status
    .success());
    let bytes = std::fs::read(&again).unwrap();
    assert_eq!(bytes, std::fs::read(&rotated).unwrap());
    // The first entry's DOS time and date: 00:00:00, 1980-01-01.
    assert_eq!(bytes[10..14], [0, 0, 0x21, 0]);
}
