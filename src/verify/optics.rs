//! Checks of the optics models (`psh::optics`).

use super::Check;
use crate::error::Result;
use crate::optics::{fresnel, ComplexIor, Material};
use num_complex::Complex64;

pub fn checks() -> Vec<Check> {
    vec![
    Check {
        id: "optics.fresnel_gold",
        source: "PF (1)-(2)",
        description: "Fresnel reflectances R_s, R_p of gold (PF Table 1, 650 nm) at 0..85 degrees against the closed forms with complex sqrt(eta^2 - sin^2), and the Brewster zero of R_p for n = 1.5",
        tolerance: 1e-13,
        proof: Some("proofs/optics.md"),
        run: fresnel_gold,
    },
    Check {
        id: "optics.fresnel_mueller",
        source: "PF (7)",
        description: "Mueller matrix of a reflection in the travel frames (FresnelCoefficients::mueller_travel) vs tr(sigma_p J sigma_q J^H)/2 of the Jones matrix J = diag(r_s, r_p), and vs PF (7) written out with F_perp = |r_s|^2, F_par = |r_p|^2 and delta = arg r_p - arg r_s, every material and channel of PF Table 1, glass seen from inside (total internal reflection), 0..89 degrees (relative to A)",
        // Products of two amplitudes of modulus <= 1 in both: measured 8.5e-16, tolerance
        // 45 ulps.
        tolerance: 1e-14,
        proof: Some("proofs/coherency.md"),
        run: fresnel_mueller,
    }]
}

/// `tr(sigma_p J sigma_q J^H) / 2` for the 2 x 2 Jones matrix `j` (`proofs/coherency.md`
/// (7.1)), with `s2 + i s3 = 2 E_x conj(E_y)` (`proofs/optics.md` (2.1)).
fn jones_to_mueller(j: &nalgebra::Matrix2<Complex64>) -> nalgebra::Matrix4<f64> {
    let (o, i) = (Complex64::new(1.0, 0.0), Complex64::i());
    let z = Complex64::default();
    let sigma = [
        nalgebra::Matrix2::new(o, z, z, o),
        nalgebra::Matrix2::new(o, z, z, -o),
        nalgebra::Matrix2::new(z, o, o, z),
        nalgebra::Matrix2::new(z, i, -i, z),
    ];
    nalgebra::Matrix4::from_fn(|p, q| 0.5 * (sigma[p] * j * sigma[q] * j.adjoint()).trace().re)
}

/// PF (7): the Fresnel Mueller matrix against the Mueller matrix of its Jones matrix.
fn fresnel_mueller() -> Result<f64> {
    let mut iors: Vec<ComplexIor> = Material::ALL
        .iter()
        .flat_map(|m| crate::optics::Channel::ALL.map(|c| m.ior(c)))
        .collect();
    iors.push(ComplexIor::dielectric(1.0 / 1.51)?);
    let mut worst = 0.0f64;
    for ior in &iors {
        for deg in 0..90 {
            let f = fresnel((deg as f64).to_radians().cos(), ior)?;
            let got = f.mueller_travel().matrix();
            let (rs, rp) = (f.r_s(), f.r_p());
            let z = Complex64::default();
            let jones = jones_to_mueller(&nalgebra::Matrix2::new(rs, z, z, rp));
            // PF (7) as printed, delta the phase of r_p relative to r_s.
            let (fs, fp) = (rs.norm_sqr(), rp.norm_sqr());
            let (a, b) = (0.5 * (fs + fp), 0.5 * (fs - fp));
            let delta = rp.arg() - rs.arg();
            let (c, s) = (
                (fs * fp).sqrt() * delta.cos(),
                (fs * fp).sqrt() * delta.sin(),
            );
            let printed = nalgebra::Matrix4::new(
                a, b, 0.0, 0.0, //
                b, a, 0.0, 0.0, //
                0.0, 0.0, c, s, //
                0.0, 0.0, -s, c,
            );
            worst = worst
                .max((got - jones).amax() / a)
                .max((got - printed).amax() / a);
        }
    }
    Ok(worst)
}

fn fresnel_gold() -> Result<f64> {
    let gold = Material::from_name("gold")?.ior(crate::optics::Channel::Red);
    let eta = Complex64::new(gold.n(), gold.k());
    let mut worst = 0.0f64;
    for deg in (0..=85).step_by(5) {
        let (s, c) = (deg as f64).to_radians().sin_cos();
        let root = (eta * eta - s * s).sqrt();
        let rs = ((c - root) / (c + root)).norm_sqr();
        let rp = ((eta * eta * c - root) / (eta * eta * c + root)).norm_sqr();
        let f = fresnel(c, &gold)?;
        worst = worst
            .max((f.reflectance_s() - rs).abs())
            .max((f.reflectance_p() - rp).abs());
    }
    let glass = ComplexIor::dielectric(1.5)?;
    let brewster = 1.5f64.atan().cos();
    Ok(worst.max(fresnel(brewster, &glass)?.reflectance_p()))
}
