//! Checks of the spin-weighted SH (`psh::swsh`).

use super::Check;
use crate::error::Result;
use crate::random::pseudo_random;
use crate::sh::transform::grid::SphereGrid;
use crate::sh::{lm_index, num_coeffs};
use crate::swsh::SpinTransform;
use crate::swsh::{spin2_closed_form, swsh};
use num_complex::Complex64;
use std::f64::consts::PI;

pub fn checks() -> Vec<Check> {
    vec![
        Check {
            id: "swsh.closed_form",
            source: "PSH (26)",
            description: "2Y_lm through Wigner d vs the closed form PSH (26a)-(26c), l <= 16, away from the poles",
            tolerance: 1e-12,
            proof: Some("proofs/swsh.md"),
            run: closed_form,
        },
        Check {
            id: "swsh.poles",
            source: "PSH (27)",
            description: "2Y_lm at both poles: only m = -2 (north) / m = 2 (south) non-zero, |value| = sqrt((2l+1)/(4pi)), l <= 64",
            tolerance: 1e-13,
            proof: Some("proofs/swsh.md"),
            run: poles,
        },
        Check {
            id: "swsh.orthonormality",
            source: "PSH (26)",
            description: "Gram matrix of 2Y_lm, l <= 10, on the exact Gauss-Legendre grid vs identity",
            tolerance: 1e-13,
            proof: Some("proofs/swsh.md"),
            run: orthonormality,
        },
        Check {
            id: "swsh.transform_round_trip_256",
            source: "PSH (32)",
            description: "spin-2 synthesis then analysis on the exact grid, L = 256 (relative to max |a_lm|)",
            tolerance: 1e-12,
            proof: Some("proofs/swsh.md"),
            run: transform_round_trip,
        },
        Check {
            id: "swsh.transform_vs_pointwise",
            source: "PSH (26)",
            description: "spin-2 synthesis by the l-recursion vs sum of Risbo-evaluated 2Y_lm at grid points incl. the rings nearest the poles, L = 64 (relative)",
            tolerance: 1e-12,
            proof: Some("proofs/swsh.md"),
            run: transform_vs_pointwise,
        },
        Check {
            id: "swsh.transform_round_trip_1024",
            source: "PSH (32)",
            description: "spin-2 synthesis then analysis on the exact grid, L = 1024 (relative to max |a_lm|; the rounding grows about linearly in L, 2e-13 at L = 256)",
            tolerance: 5e-12,
            proof: Some("proofs/swsh.md"),
            run: transform_round_trip_1024,
        },
        Check {
            id: "swsh.transform_negligible_512",
            source: "PSH (26)",
            description: "spin-2 synthesis, which leaves out values below 2^-64 near the poles, vs sums of every a_lm 2Y_lm from the evaluator on northern rings from the pole to the equator, L = 512 (relative to sum |a_lm 2Y_lm|, the scale of the rounding; the two recursions round differently, the transform's with fused multiply-adds, over up to 512 steps)",
            tolerance: 1e-14,
            proof: Some("proofs/swsh.md"),
            run: transform_negligible,
        },
        Check {
            id: "swsh.band_norm_l1024",
            source: "PSH (26)",
            description: "sum_m |2Y_lm|^2 = (2l+1)/(4pi) for every 2 <= l <= 1024 at theta = 1e-8, 0.3 (relative)",
            tolerance: 1e-12,
            proof: Some("proofs/swsh.md"),
            run: band_norm_l1024,
        },
    ]
}

fn closed_form() -> Result<f64> {
    let lmax = 16;
    let mut worst = 0.0f64;
    for &(t, p) in &[(0.2, 0.3), (1.3, -2.0), (2.9, 1.1)] {
        let y = swsh(2, lmax, t, p)?;
        for l in 2..=lmax {
            let scale = ((2 * l + 1) as f64 / (4.0 * PI)).sqrt();
            for m in -(l as i64)..=l as i64 {
                let e = spin2_closed_form(l, m, t, p)?;
                worst = worst.max((y[lm_index(l, m)] - e).norm() / scale);
            }
        }
    }
    Ok(worst)
}

fn poles() -> Result<f64> {
    let lmax = 64;
    let mut worst = 0.0f64;
    for (theta, keep) in [(0.0, -2i64), (PI, 2)] {
        let y = swsh(2, lmax, theta, 0.9)?;
        for l in 2..=lmax {
            let e = ((2 * l + 1) as f64 / (4.0 * PI)).sqrt();
            for m in -(l as i64)..=l as i64 {
                let v = y[lm_index(l, m)].norm();
                worst = worst.max(if m == keep { (v - e).abs() / e } else { v / e });
            }
        }
    }
    Ok(worst)
}

fn orthonormality() -> Result<f64> {
    let lmax = 10;
    let g = SphereGrid::for_band_limit(lmax)?;
    let n = num_coeffs(lmax);
    let mut vals = vec![Complex64::default(); g.len() * n];
    for p in 0..g.len() {
        let (t, ph) = g.angles(p)?;
        vals[p * n..(p + 1) * n].copy_from_slice(&swsh(2, lmax, t, ph)?);
    }
    let mut worst = 0.0f64;
    for i in 4..n {
        for j in i..n {
            let s: Complex64 = (0..g.len())
                .map(|p| g.point_weight(p) * vals[p * n + i].conj() * vals[p * n + j])
                .sum();
            let e = if i == j { 1.0 } else { 0.0 };
            worst = worst.max((s - e).norm());
        }
    }
    Ok(worst)
}

fn random_spin2_coeffs(lmax: usize, seed: u64) -> Vec<Complex64> {
    let re = pseudo_random(num_coeffs(lmax), seed);
    let im = pseudo_random(num_coeffs(lmax), seed + 1);
    (0..num_coeffs(lmax))
        .map(|i| {
            if i < 4 {
                Complex64::default()
            } else {
                Complex64::new(re[i], im[i])
            }
        })
        .collect()
}

fn transform_round_trip() -> Result<f64> {
    round_trip(256)
}

fn transform_round_trip_1024() -> Result<f64> {
    round_trip(1024)
}

/// Synthesis then analysis of random coefficients, relative to their largest.
fn round_trip(lmax: usize) -> Result<f64> {
    let t = SpinTransform::new(2, lmax)?;
    let c = random_spin2_coeffs(lmax, 31);
    let mut f = vec![Complex64::default(); t.grid().len()];
    t.synthesis(&c, &mut f)?;
    let mut back = vec![Complex64::default(); c.len()];
    t.analysis(&f, &mut back)?;
    let scale = c.iter().fold(0.0f64, |m, z| m.max(z.norm()));
    Ok(c.iter()
        .zip(&back)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).norm()))
        / scale)
}

fn transform_vs_pointwise() -> Result<f64> {
    let lmax = 64;
    let t = SpinTransform::new(2, lmax)?;
    let c = random_spin2_coeffs(lmax, 37);
    let mut f = vec![Complex64::default(); t.grid().len()];
    t.synthesis(&c, &mut f)?;
    let np = t.grid().n_phi;
    let rings = t.grid().rings.len();
    let mut worst = 0.0f64;
    for j in [0, 1, rings / 3, rings - 2, rings - 1] {
        for k in [0, np / 3] {
            let i = j * np + k;
            let (th, ph) = t.grid().angles(i)?;
            let y = swsh(2, lmax, th, ph)?;
            let v: Complex64 = y.iter().zip(&c).map(|(a, b)| a * b).sum();
            worst = worst.max((v - f[i]).norm() / v.norm().max(1.0));
        }
    }
    Ok(worst)
}

fn transform_negligible() -> Result<f64> {
    let lmax = 512;
    let t = SpinTransform::new(2, lmax)?;
    let c = random_spin2_coeffs(lmax, 41);
    let mut f = vec![Complex64::default(); t.grid().len()];
    t.synthesis(&c, &mut f)?;
    let (np, rings) = (t.grid().n_phi, t.grid().rings.len());
    let mut y = vec![Complex64::default(); c.len()];
    let mut worst = 0.0f64;
    // Northern rings only: a southern ring's polar angle is rounded apart from the exact
    // mirror the transform uses, which moves values of high order by far more than rounding.
    for j in [0, 1, 2, 5, 20, rings / 4, rings / 2] {
        for k in [0, np / 5] {
            let i = j * np + k;
            let (th, ph) = t.grid().angles(i)?;
            t.evaluator().values(th, ph, &mut y)?;
            let v: Complex64 = y.iter().zip(&c).map(|(a, b)| a * b).sum();
            let scale: f64 = y.iter().zip(&c).map(|(a, b)| (a * b).norm()).sum();
            worst = worst.max((v - f[i]).norm() / scale);
        }
    }
    Ok(worst)
}

fn band_norm_l1024() -> Result<f64> {
    let lmax = 1024;
    let mut worst = 0.0f64;
    for theta in [1e-8, 0.3] {
        let y = swsh(2, lmax, theta, 0.4)?;
        for l in 2..=lmax {
            let s: f64 = (l * l..(l + 1) * (l + 1)).map(|i| y[i].norm_sqr()).sum();
            let e = (2 * l + 1) as f64 / (4.0 * PI);
            worst = worst.max(((s - e) / e).abs());
        }
    }
    Ok(worst)
}
