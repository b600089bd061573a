//! Hostile cases of issue 50 (Hardening III): parsers bounded by their input and the
//! budget, sizes checked before work, outputs that only ever create or replace regular
//! files. Each run has a watchdog: a hang fails the test instead of stalling the suite.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Runs psh with `args`, killed (and the test failed) after `limit`.
fn psh_within(args: &[&str], limit: Duration) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_psh"))
        .args(args)
        .env_remove("PSH_MAX_MEMORY")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run psh");
    let start = Instant::now();
    while child.try_wait().expect("wait").is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("psh {args:?} still running after {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("output")
}

/// Expects exit 1 (psh's error) and a message with every one of `needles`, within a
/// minute.
fn refused(args: &[&str], needles: &[&str]) -> String {
    refused_with(1, args, needles)
}

/// Expects exit `code` (2: a usage error) and a message with every one of `needles`.
fn refused_with(code: i32, args: &[&str], needles: &[&str]) -> String {
    let out = psh_within(args, Duration::from_secs(60));
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(code), "{args:?}: {err}");
    for n in needles {
        assert!(err.contains(n), "{args:?}: {err} lacks {n:?}");
    }
    err
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("psh_bounded_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `psh eval wigner-block` of degree 2 written to `out`.
fn wigner_block(out: &Path) -> [&str; 10] {
    [
        "eval",
        "wigner-block",
        "--kind",
        "real",
        "--l",
        "2",
        "--rotvec",
        "0,0,1",
        "-o",
        s(out),
    ]
}

/// A polarsh `.npz` of zero coefficients (POLAR4, band limit `lmax`) at `path`.
fn zero_npz(path: &Path, lmax: usize, channels: usize) {
    let v =
        psh::polarized::PshVector::zeros(lmax, psh::polarized::Codomain::Full, channels).unwrap();
    psh::io::write_psh_npz(path, &v).unwrap();
}

/// A version-1 `.npy` file with header text `header` and `data` after it.
fn npy(path: &Path, header: &str, data: &[u8]) {
    let mut b = b"\x93NUMPY\x01\x00".to_vec();
    b.extend((header.len() as u16).to_le_bytes());
    b.extend(header.as_bytes());
    b.extend(data);
    std::fs::write(path, b).unwrap();
}

/// Headers nested 32 deep (exponential work for `npyz`'s parser: 20 deep took 2.8 s) and one
/// announcing more data than the file holds are refused at once.
#[test]
fn npy_headers_are_parsed_in_linear_time() {
    let d = dir("npy");
    let deep = d.join("deep.npy");
    npy(
        &deep,
        &format!(
            "{{'descr': '<f8', 'fortran_order': False, 'shape': {}16{}, }}\n",
            "[".repeat(32),
            "]".repeat(32)
        ),
        &[0; 128],
    );
    let out = d.join("out.npy");
    let args = |input: &Path| {
        [
            "eval",
            "sht",
            "--kind",
            "real",
            "--lmax",
            "3",
            "--op",
            "synthesis",
            "--input",
        ]
        .iter()
        .map(|a| a.to_string())
        .chain([s(input).to_string(), "-o".into(), s(&out).to_string()])
        .collect::<Vec<_>>()
    };
    let run = |input: &Path, needles: &[&str]| {
        let a = args(input);
        refused(&a.iter().map(String::as_str).collect::<Vec<_>>(), needles)
    };
    run(&deep, &["deep.npy", "expected '('"]);
    let keys = d.join("keys.npy");
    npy(
        &keys,
        &format!(
            "{{'descr': '<f8', 'fortran_order': False, 'shape': (16,), 'x': {}1{}}}\n",
            "{'a': ".repeat(32),
            "}".repeat(32)
        ),
        &[0; 128],
    );
    run(&keys, &["keys.npy", "unexpected key 'x'"]);
    let short = d.join("short.npy");
    npy(
        &short,
        "{'descr': '<f8', 'fortran_order': False, 'shape': (1000000000000,), }\n",
        &[0; 64],
    );
    run(&short, &["short.npy", "the file holds 64"]);
    assert!(!out.exists());
}

/// The central directory's declared size of `coeff.npy` in an npz, patched to `size`
/// (central record and local header).
fn declare_size(bytes: &mut [u8], size: u32) {
    for (sig, at) in [(b"PK\x01\x02", 24), (b"PK\x03\x04", 22)] {
        let starts: Vec<usize> = (0..bytes.len() - 4)
            .filter(|&i| &bytes[i..i + 4] == sig)
            .collect();
        for i in starts {
            bytes[i + at..i + at + 4].copy_from_slice(&size.to_le_bytes());
        }
    }
}

/// Compressed entries: the declared size is checked against the budget before a byte is
/// inflated, and inflation stops one byte past the declared size.
#[test]
fn compressed_entries_are_bounded() {
    let d = dir("npz");
    let zeros = d.join("zeros.npz");
    // 40401 x 4 zeros: 1.3 MB inflated, a few KB compressed.
    zero_npz(&zeros, 200, 1);
    let out = d.join("out.npz");
    refused(
        &[
            "--max-memory",
            "1M",
            "rotate",
            s(&zeros),
            "--rotvec",
            "0,0,0.1",
            "-o",
            s(&out),
        ],
        &["zip entry", "1048576"],
    );
    // Every entry declared small: the inflation overruns the declaration.
    let mut bytes = std::fs::read(&zeros).unwrap();
    declare_size(&mut bytes, 200);
    let lying = d.join("lying.npz");
    std::fs::write(&lying, &bytes).unwrap();
    refused(
        &["rotate", s(&lying), "--rotvec", "0,0,0.1", "-o", s(&out)],
        &["lying.npz", "zip entry"],
    );
    assert!(!out.exists());
}

/// Devices, FIFOs and directories are refused as inputs without reading them; an OBJ's
/// `mtllib` opens nothing.
#[cfg(unix)]
#[test]
fn only_regular_files_are_inputs() {
    let d = dir("special_in");
    let out = d.join("out.npz");
    for special in ["/dev/zero", "/dev/urandom"] {
        refused(
            &["rotate", special, "--rotvec", "0,0,0.1", "-o", s(&out)],
            &["not a regular file", special],
        );
        refused(
            &["render", "--scene", special, "--out", s(&d)],
            &["not a regular file", special],
        );
    }
    let fifo = d.join("fifo.csv");
    if Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success())
    {
        let npz = d.join("v.npz");
        zero_npz(&npz, 2, 1);
        refused(
            &[
                "convolve",
                s(&npz),
                "--kernel-table",
                s(&fifo),
                "-o",
                s(&out),
            ],
            &["not a regular file"],
        );
    }
    // An OBJ naming /dev/zero as its material library: read, the library ignored.
    let obj = d.join("quad.obj");
    std::fs::write(
        &obj,
        "mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n",
    )
    .unwrap();
    let mesh = psh::io::read_obj(&obj).unwrap();
    assert_eq!(mesh.triangles().len(), 2);
}

/// Sample counts past the reference's limit are refused before any work, in every
/// command that takes one.
#[test]
fn sample_counts_are_bounded() {
    let d = dir("spp");
    let huge = "18446744073709551615";
    refused_with(
        2,
        &["render", "--reference", huge, "--out", s(&d)],
        &[huge, "1048576"],
    );
    for flag in ["--spp", "--ground-truth-spp"] {
        refused_with(
            2,
            &["bench-error", flag, huge, "--out", s(&d)],
            &[huge, "1048576"],
        );
    }
}

/// A sphere whose BVH would not fit the budget is refused before its mesh is made.
#[test]
fn scene_meshes_count_their_bvh() {
    let d = dir("sphere");
    let scene = d.join("big.toml");
    std::fs::write(
        &scene,
        "[environment]\ntype = \"sky\"\nsun_elevation_deg = 35.0\nsun_azimuth_deg = 137.0\n\n\
         [camera]\nposition = [0.0, -4.0, 1.5]\ntarget = [0.0, 0.0, 0.0]\nfov_deg = 35.0\n\
         width = 32\nheight = 24\n\n\
         [[material]]\nname = \"m\"\ntype = \"plastic\"\nalpha = 0.15\nior = 1.5\nalbedo = 0.3\n\n\
         [[mesh]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = \"m\"\n\
         rings = 4000\nsegments = 8000\n",
    )
    .unwrap();
    refused(
        &["render", "--scene", s(&scene), "--out", s(&d)],
        &["sphere mesh", "big.toml", "budget"],
    );
    // usize::MAX rings: the vertex count overflowed to 0 and passed the check, then the
    // mesh grew until the machine killed the process (found by the fuzzer).
    let text = std::fs::read_to_string(&scene).unwrap();
    std::fs::write(&scene, text.replace("4000", "18446744073709551615")).unwrap();
    refused(
        &["render", "--scene", s(&scene), "--out", s(&d)],
        &["sphere mesh", "budget"],
    );
    let e = psh::pprt::Mesh::sphere([0.0; 3], 1.0, usize::MAX, 3).unwrap_err();
    assert!(e.to_string().contains("budget"), "{e}");
}

/// Outputs: devices are never replaced, an output naming an input is refused in the
/// `eval` commands, and the output's directory is checked before any work.
#[cfg(unix)]
#[test]
fn outputs_never_touch_what_they_should_not() {
    let d = dir("outputs");
    let points = d.join("points.npy");
    psh::io::write_npy(&points, &[1, 2], vec![0.5, 0.25]).unwrap();
    let before = std::fs::read(&points).unwrap();
    refused(
        &[
            "eval",
            "swsh-points",
            "--spin",
            "2",
            "--lmax",
            "3",
            "--points",
            s(&points),
            "-o",
            s(&points),
        ],
        &["does not overwrite"],
    );
    assert_eq!(std::fs::read(&points).unwrap(), before);
    refused(&wigner_block(&d.join("no/such/dir.npy")), &["no directory"]);
    let fifo = d.join("out.fifo");
    if Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success())
    {
        refused(&wigner_block(&fifo), &["regular files only"]);
        use std::os::unix::fs::FileTypeExt;
        assert!(std::fs::symlink_metadata(&fifo)
            .unwrap()
            .file_type()
            .is_fifo());
    }
    // A name of 255 bytes (the file system's limit) is written: temporary names are short.
    let long = d.join(format!("{}.npy", "n".repeat(251)));
    let out = psh_within(&wigner_block(&long), Duration::from_secs(60));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(long.exists());
}

/// Render settings that name pictures are checked first: a polarizer angle of 1e308 is
/// refused by value (not as a file name too long), an output directory that is a file
/// refused before the render.
#[test]
fn render_outputs_are_checked_first() {
    let d = dir("render_out");
    refused(
        &["render", "--polarizer", "1e308", "--out", s(&d)],
        &["polarizer angle", "1e308"],
    );
    let file = d.join("a-file");
    std::fs::write(&file, "not a directory").unwrap();
    let err = refused(&["render", "--out", s(&file)], &["not a directory"]);
    assert!(!err.contains("rendered"), "{err}");
}

/// A polarizer angle of 1e308 degrees is finite: the axis (modulo 180 degrees) gives a
/// polarizer's Mueller matrix, finite, `m00 = 1/2`, no panic.
#[test]
fn huge_polarizer_angles_are_reduced() {
    let out = psh_within(
        &["eval", "polarizer", "--angle-deg", "1e308"],
        Duration::from_secs(60),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let m: Vec<f64> = json["mueller"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|row| row.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
        .collect();
    assert_eq!(m.len(), 16);
    assert_eq!(m[0], 0.5);
    // A projector scaled by 1/2: m11 + m22 = 1/2 (c^2 + s^2 = 1).
    assert!((m[5] + m[10] - 0.5).abs() < 1e-15);
}

/// A render never writes over a file its scene reads: an environment stored under the
/// name of the report is refused, the file kept.
#[test]
fn renders_never_replace_their_inputs() {
    let d = dir("render_inputs");
    let env = d.join("report.json");
    zero_npz(&env, 4, 3);
    let before = std::fs::read(&env).unwrap();
    let scene = d.join("scene.toml");
    std::fs::write(
        &scene,
        "[environment]\ntype = \"npz\"\npath = \"report.json\"\n\n\
         [camera]\nposition = [0.0, -4.0, 1.5]\ntarget = [0.0, 0.0, 0.0]\nfov_deg = 35.0\n\
         width = 8\nheight = 6\n\n[settings]\nl_low = 2\nl_high = 3\nrays = 4\n\n\
         [[material]]\nname = \"m\"\ntype = \"plastic\"\nalpha = 0.15\nior = 1.5\nalbedo = 0.3\n\n\
         [[mesh]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = \"m\"\n\
         rings = 6\nsegments = 12\n",
    )
    .unwrap();
    refused(
        &["render", "--scene", s(&scene), "--out", s(&d)],
        &["report.json", "does not overwrite"],
    );
    assert_eq!(std::fs::read(&env).unwrap(), before);
    assert!(
        !d.join("render_s0.png").exists(),
        "a partial set was written"
    );
}
