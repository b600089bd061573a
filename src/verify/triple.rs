//! Checks of the shadowed transfer by triple products (`psh::polarized::triple`).

use super::Check;
use crate::error::Result;
use crate::polarized::{visibility_transfer, visibility_transfer_quadrature};
use crate::random::pseudo_random;

pub fn checks() -> Vec<Check> {
    vec![Check {
        id: "triple.visibility_transfer",
        source: "PSH (54)-(56)",
        description: "PSH matrix of f -> V f (L = 4) from a random visibility (l <= 5) by real and spin-2 triple products vs direct quadrature of PSH (54) on the exact grid (max |difference|)",
        tolerance: 1e-12,
        proof: Some("proofs/triple-products.md"),
        run: visibility_transfer_vs_quadrature,
    }]
}

fn visibility_transfer_vs_quadrature() -> Result<f64> {
    let (lv, lmax) = (5, 4);
    let v = crate::polarized::PshVector::scalar(lv, pseudo_random(crate::sh::num_coeffs(lv), 97))?;
    let a = visibility_transfer(&v, lmax)?;
    let b = visibility_transfer_quadrature(&v, lmax)?;
    Ok(a.data()
        .iter()
        .zip(b.data())
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs())))
}
