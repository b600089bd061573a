//! Checks of the optics models (`psh::optics`).

use super::Check;
use crate::error::Result;
use crate::optics::{fresnel, ComplexIor, Material};
use num_complex::Complex64;

pub fn checks() -> Vec<Check> {
    vec![Check {
        id: "optics.fresnel_gold",
        source: "PF (1)-(2)",
        description: "Fresnel reflectances R_s, R_p of gold (PF Table 1, 650 nm) at 0..85 degrees against the closed forms with complex sqrt(eta^2 - sin^2), and the Brewster zero of R_p for n = 1.5",
        tolerance: 1e-13,
        proof: Some("proofs/optics.md"),
        run: fresnel_gold,
    }]
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
