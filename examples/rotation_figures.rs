//! PSH Figs. 10 and 11 reproduced numerically, with PNG plots (`docs/worked-example.md`):
//!
//! ```text
//! cargo run --release --example rotation_figures -- [output directory, default target/figures]
//! ```
//!
//! Fig. 10: the coefficient matrix of a rotation (l <= 6) under (a) scalar SH on a scalar
//! field, (b) scalar SH on Stokes components in the theta-phi frame field, (c) spin-2 SH;
//! (b) is not block diagonal, (a) and (c) are.
//! Fig. 11: a real environment map (`sponza_64` from the shared data; a synthetic
//! band-limited map when the data is absent) band-limited to l <= 16, rotated in the
//! frequency domain (PSH (35)-(37)) and reconstructed, against the same band-limited map
//! rotated in the angular domain (PSH (25)); and the naive rotation of (b).

#[path = "common/sponza.rs"]
mod sponza;
use psh::apps::figure10::{off_block_fraction, rotation_coefficient_matrix, LinearBasis};
use psh::geometry::rotation_from_rotvec;
use psh::geometry::Rotated;
use psh::geometry::ThetaPhiFrameField;
use psh::geometry::{Equirect, PixelGrid};
use psh::io::{
    diverging, tick_label, write_map_pngs, write_matrix_png, write_png_with_legend, Legend,
};
use psh::map::{MapLayout, StokesMap};
use psh::polarized::{reconstruct_image, PshRotation, PshTransform, PshVector};
use psh::sh::RealWignerD;
use psh::sh::ShEvaluator;
use psh::sh::ShTransform;
use psh::sh::{lm_of_index, num_coeffs};
use sponza::sponza_or_synthetic;
use std::path::{Path, PathBuf};

/// Band limit of Fig. 10's matrices and of Fig. 11's map.
const FIG10_LMAX: usize = 6;
const FIG11_LMAX: usize = 16;
/// The paper's rotation vector for Fig. 10.
const ROTVEC: [f64; 3] = [10.0, 0.1, 0.2];

fn main() -> psh::Result<()> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "target/figures".into()),
    );
    std::fs::create_dir_all(&out).map_err(|e| psh::Error::Io {
        path: out.clone(),
        source: e,
    })?;
    let r = rotation_from_rotvec(ROTVEC)?;
    figure10(&out, &r)?;
    figure11(&out, &r)?;
    println!("pictures written to {}", out.display());
    Ok(())
}

fn figure10(out: &Path, r: &nalgebra::Rotation3<f64>) -> psh::Result<()> {
    let lmax = FIG10_LMAX;
    let n = num_coeffs(lmax);
    println!("Fig. 10: coefficient matrices of the rotation with rotation vector {ROTVEC:?}, l <= {lmax}");
    // (a) Scalar SH on a scalar field: the real Wigner D blocks (PSH (13)).
    let d = RealWignerD::new(r, lmax)?;
    let mut a = vec![0.0; n * n];
    for i in 0..n {
        let (l, m) = lm_of_index(i);
        let b = d.block(l)?;
        for mp in -(l as i64)..=l as i64 {
            let j = psh::sh::lm_index(l, mp);
            a[i * n + j] = b[(m + l as i64) as usize * (2 * l + 1) + (mp + l as i64) as usize];
        }
    }
    let off_a = {
        let c: Vec<num_complex::Complex64> = a.iter().map(|&x| x.into()).collect();
        off_block_fraction(&c, lmax)
    };
    // (b), (c): projected on the exact grid of band 48 (the naive matrix is not band
    // limited; 48 resolves it to the digits shown).
    let b = rotation_coefficient_matrix(LinearBasis::ScalarThetaPhi, r, lmax, 48)?;
    let c = rotation_coefficient_matrix(LinearBasis::Spin2, r, lmax, lmax)?;
    for (name, label, abs, frac) in [
        (
            "fig10a_scalar.png",
            "(a) scalar SH, scalar field",
            a.clone(),
            off_a,
        ),
        (
            "fig10b_scalar_theta_phi.png",
            "(b) scalar SH, theta-phi Stokes components",
            b.iter().map(|z| z.norm()).collect(),
            off_block_fraction(&b, lmax),
        ),
        (
            "fig10c_spin2.png",
            "(c) spin-2 SH",
            c.iter().map(|z| z.norm()).collect(),
            off_block_fraction(&c, lmax),
        ),
    ] {
        write_matrix_png(out.join(name), &abs, n, 8, true)?;
        println!("  {label:<45} off-block share of |M|^2: {frac:.3e}   -> {name}");
    }
    Ok(())
}

fn figure11(out: &Path, r: &nalgebra::Rotation3<f64>) -> psh::Result<()> {
    let lmax = FIG11_LMAX;
    let (v, source) = sponza_or_synthetic(FIG11_LMAX)?;
    println!("Fig. 11: {source}, band-limited to l <= {lmax}, rotated by {ROTVEC:?}");
    let layout = MapLayout::from_image_size(128, 256)?;
    let MapLayout::Equirect(grid) = layout.clone() else {
        unreachable!("128 x 256 is equirectangular")
    };
    let field = ThetaPhiFrameField::new();
    // Frequency domain: rotate the coefficients, reconstruct.
    let rotated = PshRotation::new(r, lmax)?.rotate(&v)?;
    let freq = StokesMap::reconstruct(&rotated, layout.clone())?;
    // Angular domain: the band-limited field at R^-1 w_i, frames R^-1 F(w_i) (PSH (25)).
    let q = r.inverse();
    let angular = StokesMap::new(
        layout.clone(),
        reconstruct_image(&v, &Rotated::new(grid.clone(), q), &Rotated::new(field, q))?,
    )?;
    let naive = StokesMap::new(layout.clone(), naive_rotation(&v, r, &grid)?)?;
    let scale = max_abs(&angular);
    let err_psh = max_diff(&freq, &angular) / scale;
    let err_naive = max_diff(&naive, &angular) / scale;
    println!("  PSH rotation vs angular rotation:   max |difference| / max |s| = {err_psh:.2e}");
    println!("  naive rotation vs angular rotation: max |difference| / max |s| = {err_naive:.2e}");
    for (name, map) in [("angular", &angular), ("psh", &freq), ("naive", &naive)] {
        write_map_pngs(map, out.join(format!("fig11_{name}")))?;
    }
    for (name, map) in [("psh", &freq), ("naive", &naive)] {
        for p in [1, 2] {
            let rgb: Vec<[u8; 3]> = (0..grid.len())
                .map(|i| {
                    let d = map.channels()[1][i][p] - angular.channels()[1][i][p];
                    diverging(d / (0.1 * scale))
                })
                .collect();
            let path = out.join(format!("fig11_{name}_minus_angular_s{p}.png"));
            let bar = |t: f64| diverging(2.0 * t - 1.0);
            let ticks = [-1.0, 0.0, 1.0]
                .map(|k| (0.5 + 0.5 * k, tick_label(0.1 * k * scale)))
                .to_vec();
            let legend = Legend::bar(
                format!("s{p} ({name}) - s{p} (angular), green channel"),
                &bar,
                ticks,
            );
            write_png_with_legend(&path, &legend, grid.width, grid.height, &rgb)?;
        }
    }
    println!("  pictures: fig11_{{angular,psh,naive}}_{{s0,s1,s2,s3,dop,aop}}.png, differences (green channel, +-10% of max |s|) fig11_{{psh,naive}}_minus_angular_s{{1,2}}.png");
    if err_psh > 1e-12 || err_naive < 1e-2 {
        return Err(psh::Error::InvalidArgument {
            name: "Fig. 11 comparison",
            value: format!("PSH {err_psh:.2e}, naive {err_naive:.2e}"),
            reason: "expected PSH <= 1e-12 and naive >= 1e-2".into(),
        });
    }
    Ok(())
}

/// PSH Fig. 11's naive approach: `s1`, `s2` in the theta-phi frame field projected on
/// scalar SH (exact grid of band `lmax`), each rotated by the real Wigner D matrices as if
/// scalar, and read back as theta-phi components at the rotated directions; `s0`, `s3`
/// rotated as the scalars they are.
fn naive_rotation(
    v: &PshVector,
    r: &nalgebra::Rotation3<f64>,
    grid: &Equirect,
) -> psh::Result<Vec<Vec<[f64; 4]>>> {
    let lmax = v.lmax();
    let exact = PshTransform::new(lmax)?;
    let scalar = ShTransform::new(lmax)?;
    let d = RealWignerD::new(r, lmax)?;
    let eval = ShEvaluator::new(lmax)?;
    let dirs: Vec<[f64; 3]> = (0..grid.len()).map(|i| grid.direction(i)).collect();
    let n = num_coeffs(lmax);
    let mut basis = vec![0.0; dirs.len() * n];
    eval.real_batch(&dirs, &mut basis)?;
    let mut out = Vec::new();
    for c in 0..v.channels() {
        let field = exact.reconstruct(v, c)?;
        let mut img = vec![[0.0; 4]; grid.len()];
        for p in 0..4 {
            let values: Vec<f64> = field.iter().map(|s| s[p]).collect();
            let mut coeffs = vec![0.0; n];
            scalar.analysis_real(&values, &mut coeffs)?;
            let rot = d.rotate(&coeffs)?;
            for (i, px) in img.iter_mut().enumerate() {
                px[p] = basis[i * n..(i + 1) * n]
                    .iter()
                    .zip(&rot)
                    .map(|(y, f)| y * f)
                    .sum();
            }
        }
        out.push(img);
    }
    Ok(out)
}

fn max_abs(m: &StokesMap) -> f64 {
    m.channels()
        .iter()
        .flatten()
        .flatten()
        .fold(0.0f64, |a, x| a.max(x.abs()))
}

fn max_diff(a: &StokesMap, b: &StokesMap) -> f64 {
    a.channels()
        .iter()
        .flatten()
        .zip(b.channels().iter().flatten())
        .flat_map(|(x, y)| (0..4).map(move |p| (x[p] - y[p]).abs()))
        .fold(0.0f64, f64::max)
}
