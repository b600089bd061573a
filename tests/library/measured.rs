//! Measured pBRDF tables: an analytic model sampled into a table in Mitsuba's
//! `measured_polarized` convention (`.pbsdf`), read back and projected, against the
//! model itself and its analytic projection.

#[path = "../support/mat.rs"]
mod mat;

use psh::optics::{PolarizedPlastic, TabulatedPbrdf};
use psh::polarized::{project_operator, IsotropicMatrix, SpinBlock22};
use psh::stokes::MuellerField;
use std::f64::consts::{FRAC_PI_2, PI};

/// The KAIST dataset's sampling at `step` times its downsampled resolution: `phi_d` over
/// `[-pi, pi]`, `theta_d` uniform and `theta_h` quadratic over `[0, pi/2]`.
fn kaist_axes(n_phi: usize, n_theta: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let phi = (0..n_phi)
        .map(|k| -PI + 2.0 * PI * k as f64 / (n_phi - 1) as f64)
        .collect();
    let t = |k: usize| k as f64 / (n_theta - 1) as f64;
    let theta_d = (0..n_theta).map(|k| FRAC_PI_2 * t(k)).collect();
    let theta_h = (0..n_theta).map(|k| FRAC_PI_2 * t(k) * t(k)).collect();
    (phi, theta_d, theta_h)
}

fn plastic() -> PolarizedPlastic {
    PolarizedPlastic::new(0.5, 1.5, 0.3).unwrap()
}

/// The largest absolute difference of two arrays.
fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

/// `|m - exact| / |exact|` in the Frobenius norm.
fn relative_error(m: &psh::polarized::PshMatrix, exact: &psh::polarized::PshMatrix) -> f64 {
    let sq = |v: &mut dyn Iterator<Item = f64>| v.map(|x| x * x).sum::<f64>().sqrt();
    sq(&mut m.data().iter().zip(exact.data()).map(|(a, b)| a - b))
        / sq(&mut exact.data().iter().copied())
}

fn table(n_phi: usize, n_theta: usize) -> TabulatedPbrdf {
    let (p, d, h) = kaist_axes(n_phi, n_theta);
    let model = plastic();
    TabulatedPbrdf::sample(&[&model], p, d, h, vec![550.0]).unwrap()
}

/// Written as a `.pbsdf` and read back, the table gives the model's Mueller matrices at
/// its samples (to `f32` storage), in psh's frames, for every pair of directions that the
/// samples name, at any azimuth of the half vector.
#[test]
fn a_sampled_table_reproduces_the_model_at_its_samples() {
    let dir = std::env::temp_dir().join(format!("psh-measured-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("plastic.pbsdf");
    let t = table(37, 10);
    psh::io::write_pbsdf(&path, &t).unwrap();
    let back = psh::io::read_pbsdf(&path).unwrap();
    assert_eq!(back.phi_d().len(), 37);
    let channel = back.channel(0).unwrap();
    let model = plastic();
    let mut worst = 0.0f64;
    for &pd in back.phi_d().iter().step_by(3) {
        for &td in back.theta_d() {
            for &th in back.theta_h() {
                let (i, o) = psh::optics::rusinkiewicz_directions(pd, td, th);
                if i[2] <= 1e-3 || o[2] <= 1e-3 {
                    continue;
                }
                // The same configuration turned about the normal: an isotropic table.
                let turn = nalgebra::Rotation3::from_axis_angle(&nalgebra::Vector3::z_axis(), 0.7);
                let (i, o) = (turn * i, turn * o);
                let (i, o) = ([i[0], i[1], i[2]], [o[0], o[1], o[2]]);
                let (fi, fo) = psh::optics::sp_frames(i, o).unwrap();
                let got = channel.matrix_in(&fi, &fo).unwrap().matrix();
                let want = model.matrix_in(&fi, &fo).unwrap().matrix();
                let scale = want.amax().max(1e-3);
                worst = worst.max((got - want).amax() / scale);
            }
        }
    }
    // f32 storage, and the interpolation weights of samples rounded to f32.
    assert!(worst < 2e-5, "largest relative difference {worst:e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Projected to PSH matrices, the table approaches the model's analytic projection as its
/// resolution grows (the interpolation error), and its matrix is isotropic.
#[test]
fn the_projection_of_a_table_converges_to_the_model_s() {
    let (lmax, grid) = (4, 11);
    let model = plastic();
    let exact = project_operator(&model, lmax, grid, SpinBlock22::ComplexPair).unwrap();
    let error = |n_phi, n_theta| {
        let t = table(n_phi, n_theta);
        let m =
            project_operator(&t.channel(0).unwrap(), lmax, grid, SpinBlock22::ComplexPair).unwrap();
        // Isotropic to the quadrature's aliasing of a piecewise-linear table.
        IsotropicMatrix::from_dense(&m, 1e-6).unwrap();
        relative_error(&m, &exact)
    };
    // Half, once, twice and four times the KAIST dataset's downsampled resolution.
    let curve: Vec<(usize, usize, f64)> = [(37, 10), (73, 19), (145, 37), (289, 73)]
        .iter()
        .map(|&(p, t)| (p, t, error(p, t)))
        .collect();
    for (p, t, e) in &curve {
        eprintln!("projection error at l = {lmax}, table {p} x {t} x {t}: {e:.3e}");
    }
    // Measured: 8.0e-2, 3.5e-2, 7.7e-3, 2.2e-3: towards second order in the step (linear
    // interpolation; factors 2.3, 4.5, 3.6). At least a factor 2 per halving, and 3e-3 at
    // the finest.
    for w in curve.windows(2) {
        assert!(w[1].2 < w[0].2 / 2.0, "{curve:?}");
    }
    assert!(curve[3].2 < 3e-3, "{curve:?}");
}

/// The KAIST dataset's own per-sample Stokes frames against psh's reading of a table
/// (`psh verify`'s `pbrdf.kaist_frames`; skipped without the shared data): psh's angles
/// and the table frames of `proofs/tabulated-pbrdf-frames.md` are the dataset's.
#[test]
fn kaist_frames_are_psh_s_table_frames() {
    let results = psh::verify::run(Some("pbrdf.kaist_frames"));
    assert_eq!(results.len(), 1);
    let r = &results[0];
    eprintln!("{}: {:e} (skipped: {:?})", r.id, r.max_error, r.skipped);
    assert!(r.passed, "{r:?}");
}

/// `C(t)` of a frame turned by `t` about the ray: `s1 + i s2` times `e^{-2 i t}`.
fn turn(t: f64) -> nalgebra::Matrix4<f64> {
    let (s, c) = (2.0 * t).sin_cos();
    nalgebra::Matrix4::new(
        1.0, 0.0, 0.0, 0.0, 0.0, c, s, 0.0, 0.0, -s, c, 0.0, 0.0, 0.0, 0.0, 1.0,
    )
}

/// The KAIST layout: a model sampled at the dataset's angles (`73 x 19 x 19`), its
/// matrices written in frames of an info file turned by a different angle per sample and
/// side about each frame's `z` (each configuration also turned about the normal, as the
/// dataset turns `w_o` to azimuth 0), as two MAT-files. Read with the info file, the table
/// is the model's again (to `f32` storage); its projection is the model's to the
/// interpolation error; read with the info file of another sampling, an error.
#[test]
fn a_kaist_layout_file_in_turned_frames_reads_as_the_model() {
    use nalgebra::{Rotation3, Vector3};
    let dir = std::env::temp_dir().join(format!("psh-kaist-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (pd, td, th) = kaist_axes(73, 19);
    let convention = table(73, 19);
    let (mut data, mut xyzi, mut xyzo) = (Vec::new(), Vec::new(), Vec::new());
    let nan = Vector3::repeat(f64::NAN);
    let (mut undefined, mut s) = (0, 0usize);
    for &p in &pd {
        for &d in &td {
            for &h in &th {
                let (i, o) = psh::optics::rusinkiewicz_directions(p, d, h);
                let spin = Rotation3::from_axis_angle(&Vector3::z_axis(), 0.37 * s as f64);
                let (i, o) = (spin * i, spin * o);
                let (zi, zo) = (-i, o);
                let x = i.cross(&o);
                let (ti, to) = (0.3 + 0.011 * s as f64, -1.1 + 0.007 * s as f64);
                let at = s * 16;
                let m = nalgebra::Matrix4::from_row_slice(&convention.values()[at..at + 16]);
                let (fi, fo, m) = if x.norm() < 1e-9 || d == FRAC_PI_2 {
                    // The dataset leaves x, y undefined where w_i = w_o and on the horizon.
                    undefined += 1;
                    ([nan, nan, zi], [nan, nan, zo], m)
                } else {
                    let x = x.normalize();
                    // The file's x is the convention's turned by t about z.
                    let frame = |z: Vector3<f64>, t: f64| {
                        let xf = x * t.cos() + z.cross(&x) * t.sin();
                        [xf, z.cross(&xf), z]
                    };
                    (frame(zi, ti), frame(zo, to), turn(to) * m * turn(-ti))
                };
                data.extend(m.transpose().iter());
                xyzi.extend(fi.iter().flat_map(|v| v.iter().copied()));
                xyzo.extend(fo.iter().flat_map(|v| v.iter().copied()));
                s += 1;
            }
        }
    }
    let angles = |th: &[f64]| {
        vec![
            ("phi_d", vec![1, 73], pd.clone()),
            ("theta_d", vec![1, 19], td.clone()),
            ("theta_h", vec![1, 19], th.to_vec()),
        ]
    };
    let (data_path, info_path) = (dir.join("plastic_pbrdf.mat"), dir.join("info.mat"));
    let mut vars = angles(&th);
    vars.push(("pbrdf_T_f", vec![73, 19, 19, 1, 4, 4], data));
    vars.push(("wvls", vec![1, 1], vec![550.0]));
    std::fs::write(&data_path, mat::compressed(&vars)).unwrap();
    let mut info = angles(&th);
    info.push(("xyzi_T", vec![73, 19, 19, 3, 3], xyzi.clone()));
    info.push(("xyzo_T", vec![73, 19, 19, 3, 3], xyzo.clone()));
    std::fs::write(&info_path, mat::file(&info)).unwrap();

    let read = psh::io::read_measured_pbrdf(&data_path, Some(&info_path)).unwrap();
    assert_eq!(read.undefined_frames, undefined);
    assert_eq!(read.turned + undefined, 73 * 19 * 19);
    // The turns of the file's frames, as written (largest 89.9 degrees modulo 180).
    assert!(read.largest_turn > 1.5, "{}", read.largest_turn);
    let scale = convention
        .values()
        .iter()
        .fold(0.0f64, |a, x| a.max(x.abs()));
    let worst = largest_difference(read.table.values(), convention.values());
    assert!(
        worst < 1e-6 * scale,
        "largest difference {worst:e} of {scale:e}"
    );

    // Projected, as the model's analytic projection (the bound of the .pbsdf test).
    let (lmax, grid) = (4, 11);
    let exact = project_operator(&plastic(), lmax, grid, SpinBlock22::ComplexPair).unwrap();
    let m = project_operator(
        &read.table.channel(0).unwrap(),
        lmax,
        grid,
        SpinBlock22::ComplexPair,
    )
    .unwrap();
    let e = relative_error(&m, &exact);
    assert!(e < 0.05, "{e:e}");

    // Without the info file the turned matrices are read as if in the convention: wrong.
    let bare = psh::io::read_measured_pbrdf(&data_path, None).unwrap();
    let off = largest_difference(bare.table.values(), convention.values());
    assert!(off > 1e-2 * scale, "{off:e}");

    // The info file of another sampling (theta_h uniform): named.
    let uniform: Vec<f64> = td.clone();
    let mut other = angles(&uniform);
    other.push(("xyzi_T", vec![73, 19, 19, 3, 3], xyzi));
    other.push(("xyzo_T", vec![73, 19, 19, 3, 3], xyzo));
    let other_path = dir.join("other_info.mat");
    std::fs::write(&other_path, mat::file(&other)).unwrap();
    let e = psh::io::read_measured_pbrdf(&data_path, Some(&other_path)).unwrap_err();
    assert!(e.to_string().contains("another sampling"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
