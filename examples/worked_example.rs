//! A worked example of the scalar SH core (see `docs/worked-example.md`).
//!
//! 1. Project an exactly band-limited function onto real SH (PSH (12)) on the exact
//!    Gauss-Legendre grid (PSH (3)) and check the expansion PSH (2) away from the grid.
//! 2. Rotate its coefficients with the real Wigner D matrices (PSH (13)) and compare with
//!    the projection of the rotated function `f(R^-1 w)` (PSH (8)).
//! 3. Convolve it with a zonal kernel by Funk-Hecke (PSH (11)) and compare with the
//!    angular-domain integral PSH (10).
//! 4. Project the same function from cube-map images of several resolutions: the error is
//!    that of the midpoint rule per texel, not zero.
//!
//! Steps 1-3 are equivalences that hold exactly in exact arithmetic; each is required to
//! hold to `1e-13` relative to the largest compared magnitude, and the program exits with
//! an error otherwise. Step 4 only reports its error.
//!
//! Run with `cargo run --release --example worked_example`. Only the public API is used.

use nalgebra::Vector3;
use psh::geometry::direction;
use psh::geometry::rotation_from_rotvec;
use psh::geometry::{CubeCross, PixelGrid};
use psh::sh::project_real;
use psh::sh::RealWignerD;
use psh::sh::ShEvaluator;
use psh::sh::ShTransform;
use psh::sh::SphereGrid;
use psh::sh::{funk_hecke, zonal_coefficients};
use psh::sh::{lm_index, num_coeffs};
use std::f64::consts::PI;

/// Band limit of the test function.
const L: usize = 8;
/// Sharpness of the lobe.
const KAPPA: f64 = 3.0;
/// Sharpness of the convolution kernel `k(theta) = exp(KERNEL_KAPPA (cos theta - 1))`.
const KERNEL_KAPPA: f64 = 6.0;

/// The lobe axis (unit).
fn axis() -> [f64; 3] {
    let v: [f64; 3] = [0.3, -0.2, 0.9];
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|c| c / n)
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The test function: `exp(KAPPA n.w)` truncated to its Taylor polynomial of degree `L`
/// in `t = n.w`. A polynomial of degree `L` in `(x, y, z)` restricted to the sphere has
/// no SH component above degree `L`, so `f` is exactly band-limited to `L`.
fn f(w: [f64; 3]) -> f64 {
    let t = KAPPA * dot(axis(), w);
    let (mut term, mut sum) = (1.0, 1.0);
    for k in 1..=L {
        term *= t / k as f64;
        sum += term;
    }
    sum
}

/// The convolution kernel as a function of `cos theta`.
fn kernel_of_cos(c: f64) -> f64 {
    (KERNEL_KAPPA * (c - 1.0)).exp()
}

/// Largest absolute difference of two slices.
fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

/// Value of a real SH expansion at a direction (PSH (2) truncated at `L`).
fn evaluate(ev: &ShEvaluator, coeffs: &[f64], w: [f64; 3]) -> psh::Result<f64> {
    let mut y = vec![0.0; ev.len()];
    ev.real_batch(&[w], &mut y)?;
    Ok(y.iter().zip(coeffs).map(|(a, b)| a * b).sum())
}

/// A few fixed test directions off the quadrature grid.
fn test_directions() -> Vec<[f64; 3]> {
    [
        (0.0, 0.0),
        (0.37, 1.1),
        (1.2, -2.5),
        (PI / 2.0, 0.4),
        (2.3, 2.9),
        (PI - 1e-9, -0.7),
    ]
    .iter()
    .map(|&(t, p)| direction(t, p))
    .collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut failures = Vec::new();
    // Passes when the largest absolute error is at most `relative` times `scale` (the
    // largest magnitude of the compared quantity).
    let mut check = |name: &str, error: f64, scale: f64, relative: f64| {
        let ok = error <= relative * scale;
        println!(
            "  {name:<57} max error {error:8.2e} = {:7.1e} x {scale:.3}  {}",
            error / scale,
            if ok { "ok" } else { "FAILED" }
        );
        if !ok {
            failures.push(name.to_string());
        }
    };

    // ------------------------------------------------------------------ 1. projection
    let t = ShTransform::new(L)?;
    let grid = t.grid();
    println!(
        "f(w) = sum_(k<={L}) (kappa n.w)^k / k!, kappa = {KAPPA}, n = ({:.4}, {:.4}, {:.4})",
        axis()[0],
        axis()[1],
        axis()[2]
    );
    println!(
        "exact grid for L = {L}: {} Gauss-Legendre rings x {} meridians = {} points",
        grid.rings.len(),
        grid.n_phi,
        grid.len()
    );
    let grid_dirs = (0..grid.len())
        .map(|i| grid.direction(i))
        .collect::<psh::Result<Vec<[f64; 3]>>>()?;
    let values: Vec<f64> = grid_dirs.iter().map(|&w| f(w)).collect();
    let mut c = vec![0.0; num_coeffs(L)];
    t.analysis_real(&values, &mut c)?;
    println!(
        "real SH coefficients (PSH (12)): f_00 = {:.12}, f_1,-1 = {:.12}, f_10 = {:.12}, f_11 = {:.12}",
        c[lm_index(0, 0)],
        c[lm_index(1, -1)],
        c[lm_index(1, 0)],
        c[lm_index(1, 1)]
    );
    // The real SH carry the Condon-Shortley sign: Y^R_1,-1 = -sqrt(3/4pi) y,
    // Y^R_10 = sqrt(3/4pi) z, Y^R_11 = -sqrt(3/4pi) x. The lobe points to +x, -y, +z, so
    // f_11 < 0, f_1,-1 > 0 and f_10 > 0.
    println!("   (Condon-Shortley sign: n_x > 0 gives f_11 < 0, n_y < 0 gives f_1,-1 > 0)");
    let ev = ShEvaluator::new(L)?;
    let (mut worst, mut largest) = (0.0f64, 0.0f64);
    for w in test_directions() {
        worst = worst.max((evaluate(&ev, &c, w)? - f(w)).abs());
        largest = largest.max(f(w).abs());
    }
    println!("1. projection on the exact grid (PSH (3)), expansion PSH (2) at 6 off-grid points:");
    check("sum_lm f_lm Y^R_lm(w) vs f(w)", worst, largest, 1e-13);

    // ------------------------------------------------------------------ 2. rotation
    let r = rotation_from_rotvec([0.4, -1.2, 0.9])?;
    let d = RealWignerD::new(&r, L)?;
    let rotated = d.rotate(&c)?;
    let rotated_values: Vec<f64> = grid_dirs
        .iter()
        .map(|&w| {
            let v = r.inverse_transform_vector(&Vector3::from(w));
            f([v.x, v.y, v.z])
        })
        .collect();
    let mut projected = vec![0.0; num_coeffs(L)];
    t.analysis_real(&rotated_values, &mut projected)?;
    println!(
        "2. rotation by the rotation vector (0.4, -1.2, 0.9) (|v| = {:.4} rad):",
        r.angle()
    );
    let largest = projected.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    check(
        "RealWignerD.rotate(f_lm) vs projection of f(R^-1 w)",
        max_diff(&rotated, &projected),
        largest,
        1e-13,
    );

    // ------------------------------------------------------------------ 3. convolution
    let k = zonal_coefficients(|theta: f64| kernel_of_cos(theta.cos()), L)?;
    let conv = funk_hecke(&k, &c)?;
    // Angular domain, PSH (10): integrate k(acos(w.w')) f(w') on an exact grid for band 64;
    // the kernel's ZH coefficients fall below 1e-30 by l = 40, so the integrand is
    // band-limited to rounding and the rule integrates it exactly.
    let fine = SphereGrid::for_band_limit(64)?;
    let fine_dirs = (0..fine.len())
        .map(|i| fine.direction(i))
        .collect::<psh::Result<Vec<[f64; 3]>>>()?;
    let fine_f: Vec<f64> = fine_dirs.iter().map(|&w| f(w)).collect();
    let mut worst = 0.0f64;
    let mut largest = 0.0f64;
    for w in test_directions() {
        let direct: f64 = fine_dirs
            .iter()
            .zip(&fine_f)
            .enumerate()
            .map(|(i, (&v, &fv))| fine.point_weight(i) * kernel_of_cos(dot(w, v)) * fv)
            .sum();
        let freq = evaluate(&ev, &conv, w)?;
        worst = worst.max((direct - freq).abs());
        largest = largest.max(direct.abs());
    }
    println!(
        "3. convolution with k(theta) = exp({KERNEL_KAPPA} (cos theta - 1)): k_0 = {:.12}, k_{L} = {:.3e}",
        k.coeffs[0], k.coeffs[L]
    );
    println!(
        "   direct integral on the exact grid for band 64 ({} x {} points)",
        fine.rings.len(),
        fine.n_phi
    );
    check(
        "Funk-Hecke PSH (11) vs direct integral PSH (10), 6 points",
        worst,
        largest,
        1e-13,
    );

    // ------------------------------------------------------------------ 4. cube map
    println!("4. projection of cube-map images (3e x 4e cross, exact texel solid angles):");
    let mut previous: Option<f64> = None;
    for edge in [16usize, 32, 64, 128] {
        let cube = CubeCross::new(edge)?;
        let total: f64 = (0..cube.len()).map(|i| cube.solid_angle(i)).sum();
        let image: Vec<f64> = (0..cube.len())
            .map(|i| {
                if cube.solid_angle(i) > 0.0 {
                    f(cube.direction(i))
                } else {
                    0.0
                }
            })
            .collect();
        let from_image = project_real(&cube, &image, L)?;
        let err = max_diff(&from_image, &c);
        let ratio = previous.map_or(String::new(), |p| {
            format!("  (previous / this = {:.2})", p / err)
        });
        println!(
            "  edge {edge:>3}: sum of solid angles - 4 pi = {:9.2e}, max |f_lm(image) - f_lm| = {err:.3e}{ratio}",
            total - 4.0 * PI
        );
        previous = Some(err);
    }
    println!("  (midpoint rule per texel: the error falls like 1/edge^2, it does not vanish)");

    if failures.is_empty() {
        println!("all comparisons within tolerance");
        Ok(())
    } else {
        Err(format!("comparisons out of tolerance: {failures:?}").into())
    }
}
