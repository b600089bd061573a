//! A smooth sphere of a PF Table 1 material under a constant, unpolarized white sky,
//! photographed through an ideal linear polarizer (PF Sec. 4.2, Fig. 8 and 9), rendered
//! two ways:
//!
//! - full Mueller calculus: per pixel, the Fresnel Mueller matrix (PF (7)) from the sky
//!   direction `w_i` into the view `v`, in the `s`/`p` frames, then the polarizer
//!   (PF (8)) in the camera frame, composed by psh's `MuellerTransform`s
//!   (`optics::filter::mueller_filtered_reflection`); the pixel is `2 s0` (the factor 2
//!   of Malus's law, PF Sec. 3.3, keeps the unfiltered brightness);
//! - the PF approximation: the unfiltered specular term `(F_perp + F_par)/2` times
//!   `Omega(R_0, theta, varphi)` (PF (17)), `R_0` by PF (3) from the table's `n`, `k`,
//!   `varphi` from camera and surface by PF (18) (Listing 4), `h = normalize(v + l)` and
//!   `cos theta = l . h` as in Listing 3.
//!
//! The camera is orthographic, looking along `-z` with up `+y`, so `v = +z` and the
//! camera's `x` axis (Listing 5: `normalize(up x v)`) is `+x`; the filter's angle `omega`
//! is counterclockwise from it (90 degrees: a vertical filter, as in PF Fig. 8).
//!
//! Writes `sphere_<material>.png`: four panels, left to right: unfiltered, Mueller,
//! `Omega`, and `0.5 + 10 (Omega - Mueller)` (PF Fig. 8's exaggerated difference, in
//! linear units before sRGB encoding). The first three share one exposure (the largest
//! Mueller value maps to white). Prints the largest and mean difference per channel.
//!
//! Fails (non-zero exit) unless the specular term through the exact filter,
//! `(F_perp + F_par)/2 Omega_IOR` (PF (12)), equals the Mueller result to `1e-12` on every
//! pixel. Pixels with `n . v < 0.01` (the outermost `5e-5` of the radius) are left black:
//! there `w_i` is within 1.2 degrees of `-v`, and the plane of incidence given by the
//! floating-point directions is determined only to `eps / sin 2 theta`.
//!
//! Run: `cargo run --release --example polarizing_filter_sphere -- [MATERIAL|all]
//! [OMEGA_DEGREES] [OUT_DIR]` (defaults: all, 90, `target/polarizing_filter_sphere`).

use nalgebra::Vector3;
use psh::io::{srgb8, tick_label, write_png_with_legend, Legend};
use psh::optics::metalness;
use psh::optics::{filter_angle, mueller_filtered_reflection, omega, omega_ior, Incidence};
use psh::optics::{Channel, FresnelCoefficients, Material};
use std::path::PathBuf;
use std::process::ExitCode;

/// Image size of one panel in pixels.
const SIZE: usize = 192;
/// Pixels with `n . v` below this are background.
const MIN_COS_VIEW: f64 = 0.01;
/// Required agreement of `(F_perp + F_par)/2 Omega_IOR` with the Mueller calculus.
const TOLERANCE: f64 = 1e-12;

/// One rendered sphere: per pixel and channel, `None` off the sphere.
struct Render {
    unfiltered: Vec<Option<[f64; 3]>>,
    mueller: Vec<Option<[f64; 3]>>,
    approx: Vec<Option<[f64; 3]>>,
    /// Largest `|A Omega_IOR - Mueller|`.
    exact_error: f64,
}

fn render(material: Material, omega_rad: f64) -> psh::Result<Render> {
    let v = Vector3::new(0.0, 0.0, 1.0);
    let camera_x = [1.0, 0.0, 0.0];
    let arr = |w: &Vector3<f64>| [w[0], w[1], w[2]];
    let n_px = SIZE * SIZE;
    let mut r = Render {
        unfiltered: vec![None; n_px],
        mueller: vec![None; n_px],
        approx: vec![None; n_px],
        exact_error: 0.0,
    };
    for j in 0..SIZE {
        for i in 0..SIZE {
            let x = (i as f64 + 0.5) / SIZE as f64 * 2.0 - 1.0;
            let y = 1.0 - (j as f64 + 0.5) / SIZE as f64 * 2.0;
            let z2 = 1.0 - x * x - y * y;
            if z2 < MIN_COS_VIEW * MIN_COS_VIEW {
                continue;
            }
            let normal = Vector3::new(x, y, z2.sqrt()).normalize();
            // The mirror direction towards the sky, and the facet as Listing 3 sees it.
            let wi = (normal * (2.0 * normal.dot(&v)) - v).normalize();
            let h = (v + wi).normalize();
            let theta = Incidence::from_cos(wi.dot(&h).min(1.0))?;
            let varphi = filter_angle(camera_x, arr(&h), arr(&v), omega_rad)?;
            let (mut u, mut m, mut a) = ([0.0; 3], [0.0; 3], [0.0; 3]);
            for c in Channel::ALL {
                let ior = material.ior(c);
                let fresnel = FresnelCoefficients::new(theta.cos(), &ior)?.reflectance();
                let k = c.index();
                u[k] = fresnel;
                m[k] = 2.0
                    * mueller_filtered_reflection(
                        &ior,
                        arr(&wi),
                        arr(&v),
                        camera_x,
                        omega_rad,
                        1.0,
                    )?
                    .s0();
                let r0 = ior.normal_reflectance();
                a[k] = fresnel * omega(r0, theta, varphi, metalness(material))?;
                let exact = fresnel * omega_ior(&ior, theta, varphi)?;
                r.exact_error = r.exact_error.max((exact - m[k]).abs());
            }
            let p = j * SIZE + i;
            r.unfiltered[p] = Some(u);
            r.mueller[p] = Some(m);
            r.approx[p] = Some(a);
        }
    }
    Ok(r)
}

/// The four panels side by side, and the intensity shown white.
fn picture(r: &Render) -> (Vec<[u8; 3]>, f64) {
    let white = r
        .mueller
        .iter()
        .flatten()
        .flat_map(|c| c.iter().copied())
        .fold(0.0f64, f64::max)
        .max(f64::MIN_POSITIVE);
    let width = 4 * SIZE;
    let mut rgb = vec![[0u8; 3]; width * SIZE];
    for j in 0..SIZE {
        for i in 0..SIZE {
            let p = j * SIZE + i;
            let (Some(u), Some(m), Some(a)) = (r.unfiltered[p], r.mueller[p], r.approx[p]) else {
                continue;
            };
            let row = j * width;
            rgb[row + i] = u.map(|x| srgb8(x / white));
            rgb[row + SIZE + i] = m.map(|x| srgb8(x / white));
            rgb[row + 2 * SIZE + i] = a.map(|x| srgb8(x / white));
            rgb[row + 3 * SIZE + i] = [0, 1, 2].map(|k| srgb8(0.5 + 10.0 * (a[k] - m[k]) / white));
        }
    }
    (rgb, white)
}

/// Largest and mean `|Omega - Mueller|` per channel over the sphere.
fn differences(r: &Render) -> ([f64; 3], [f64; 3]) {
    let (mut max, mut sum, mut count) = ([0.0f64; 3], [0.0f64; 3], 0usize);
    for (a, m) in r.approx.iter().zip(&r.mueller) {
        if let (Some(a), Some(m)) = (a, m) {
            for k in 0..3 {
                let d = (a[k] - m[k]).abs();
                max[k] = max[k].max(d);
                sum[k] += d;
            }
            count += 1;
        }
    }
    (max, sum.map(|s| s / count.max(1) as f64))
}

fn run() -> Result<bool, Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let materials = match args.first().map(String::as_str) {
        None | Some("all") => Material::ALL.to_vec(),
        Some(name) => vec![Material::from_name(name)?],
    };
    let omega_deg: f64 = match args.get(1) {
        Some(s) => s
            .parse()
            .map_err(|_| format!("OMEGA_DEGREES: not a number: {s}"))?,
        None => 90.0,
    };
    let out = PathBuf::from(
        args.get(2)
            .map_or("target/polarizing_filter_sphere", String::as_str),
    );
    std::fs::create_dir_all(&out)?;
    println!(
        "filter at {omega_deg} degrees from the camera's x axis; |Omega - Mueller| on the specular term (R, G, B)"
    );
    let mut ok = true;
    for m in materials {
        let r = render(m, omega_deg.to_radians())?;
        let path = out.join(format!("sphere_{}.png", m.name().to_ascii_lowercase()));
        let (rgb, white) = picture(&r);
        let grey = |t: f64| [srgb8(t); 3];
        let legend = Legend::bar(
            "intensity (linear; the fourth panel 0.5 + 10 (Omega - Mueller) / white)",
            &grey,
            vec![(0.0, "0".into()), (1.0, tick_label(white))],
        )
        .panels(&[
            "no filter",
            "filter: Mueller",
            "filter: Omega (PF)",
            "difference x10",
        ]);
        write_png_with_legend(&path, &legend, 4 * SIZE, SIZE, &rgb)?;
        let (max, mean) = differences(&r);
        let pass = r.exact_error <= TOLERANCE;
        ok &= pass;
        println!(
            "{:<9} max {:.1e} {:.1e} {:.1e}  mean {:.1e} {:.1e} {:.1e}  |A Omega_IOR - Mueller| {:.1e} {}  {}",
            m.name(),
            max[0],
            max[1],
            max[2],
            mean[0],
            mean[1],
            mean[2],
            r.exact_error,
            if pass { "ok" } else { "FAILED" },
            path.display()
        );
    }
    Ok(ok)
}

fn main() -> ExitCode {
    match run() {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => {
            eprintln!("Omega_IOR does not match the Mueller calculus");
            ExitCode::FAILURE
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
