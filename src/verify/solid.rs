//! Checks of the SH gradients and Hessians via solid harmonics (`psh::sh::evaluation::solid`, SHH
//! Sec. 3.3 and 4).

use super::Check;
use crate::error::Result;
use crate::geometry::{direction, direction_angles};
use crate::sh::evaluation::harmonics::sh_real;
use crate::sh::evaluation::solid::{hessian_index, SolidHarmonics};

pub fn checks() -> Vec<Check> {
    vec![
        Check {
            id: "solid.values_sh_real",
            source: "SHH (10)-(14)",
            description: "values of the solid-harmonic recurrences at unit directions vs psh's real SH (double-double Legendre path), l <= 64, poles included",
            tolerance: 1e-13,
            proof: Some("proofs/sh-hessian.md"),
            run: values_sh_real,
        },
        Check {
            id: "solid.gradient_fd",
            source: "SHH (17), (18)",
            description: "SH gradients vs central differences (step 1e-5) of the SH values, l <= 16, 26 directions incl. poles (absolute)",
            tolerance: 1e-6,
            proof: Some("proofs/sh-hessian.md"),
            run: gradient_fd,
        },
        Check {
            id: "solid.hessian_fd",
            source: "SHH (19), Sec. 4.2",
            description: "SH Hessians vs central differences (step 1e-5) of the SH gradients, l <= 16, 26 directions incl. poles (absolute)",
            tolerance: 1e-5,
            proof: Some("proofs/sh-hessian.md"),
            run: hessian_fd,
        },
        Check {
            id: "solid.euler",
            source: "SHH Sec. 4.2",
            description: "degree-0 homogeneity: w . grad Y = 0 and H w = -grad Y, l <= 200, relative to (l+1)^2",
            tolerance: 1e-13,
            proof: Some("proofs/sh-hessian.md"),
            run: euler,
        },
        Check {
            id: "solid.hessian_table1",
            source: "SHH Table 1",
            description: "mean squared error of the Hessians of bands l = 4, 8, 12, 16, 20, 30, 50 vs the 20-digit oracle fixture (explicit polynomial + automatic differentiation in MPFR), 8 directions incl. poles; max over the bands",
            tolerance: 1e-20,
            proof: Some("proofs/sh-hessian.md"),
            run: table1,
        },
    ]
}

/// 26 directions: a spiral, both poles, a point 1e-8 from the north pole.
pub(crate) fn test_directions() -> Vec<[f64; 3]> {
    let mut d: Vec<[f64; 3]> = (0..23)
        .map(|i| {
            direction(
                std::f64::consts::PI * (i as f64 + 0.5) / 23.0,
                0.9 * i as f64 - 2.0,
            )
        })
        .collect();
    d.extend([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], direction(1e-8, 0.3)]);
    d
}

type Eval = (Vec<f64>, Vec<[f64; 3]>, Vec<[f64; 6]>);

fn eval(sh: &SolidHarmonics, w: [f64; 3]) -> Result<Eval> {
    let n = sh.len();
    let mut out = (vec![0.0; n], vec![[0.0; 3]; n], vec![[0.0; 6]; n]);
    sh.eval(w, &mut out.0, &mut out.1, &mut out.2)?;
    Ok(out)
}

fn values_sh_real() -> Result<f64> {
    let sh = SolidHarmonics::new(64)?;
    let mut worst = 0.0f64;
    for w in test_directions() {
        let (v, _, _) = eval(&sh, w)?;
        let (t, p) = direction_angles(w)?;
        let r = sh_real(64, t, p)?;
        for (a, b) in v.iter().zip(&r) {
            worst = worst.max((a - b).abs());
        }
    }
    Ok(worst)
}

/// The derivatives of `p -> Y(p / |p|)` at a non-unit point `p`: those at `p / |p|`
/// divided by `|p|` (gradient) and `|p|^2` (Hessian).
fn eval_off_sphere(sh: &SolidHarmonics, p: [f64; 3]) -> Result<Eval> {
    let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    let (v, g, h) = eval(sh, [p[0] / r, p[1] / r, p[2] / r])?;
    let g = g.iter().map(|g| g.map(|x| x / r)).collect();
    let h = h.iter().map(|h| h.map(|x| x / (r * r))).collect();
    Ok((v, g, h))
}

/// Max over directions, axes and functions of |central difference - analytic|, for the
/// gradient (`second = false`) or the Hessian (`second = true`).
fn finite_differences(second: bool) -> Result<f64> {
    let sh = SolidHarmonics::new(16)?;
    let step = 1e-5;
    let mut worst = 0.0f64;
    for w in test_directions() {
        let (_, g0, h0) = eval(&sh, w)?;
        for i in 0..3 {
            let (mut a, mut b) = (w, w);
            a[i] += step;
            b[i] -= step;
            let (va, ga, _) = eval_off_sphere(&sh, a)?;
            let (vb, gb, _) = eval_off_sphere(&sh, b)?;
            for k in 0..sh.len() {
                if second {
                    for j in 0..3 {
                        let fd = (ga[k][j] - gb[k][j]) / (2.0 * step);
                        worst = worst.max((fd - h0[k][hessian_index(i, j)]).abs());
                    }
                } else {
                    let fd = (va[k] - vb[k]) / (2.0 * step);
                    worst = worst.max((fd - g0[k][i]).abs());
                }
            }
        }
    }
    Ok(worst)
}

fn gradient_fd() -> Result<f64> {
    finite_differences(false)
}

fn hessian_fd() -> Result<f64> {
    finite_differences(true)
}

fn euler() -> Result<f64> {
    let lmax = 200;
    let sh = SolidHarmonics::new(lmax)?;
    let mut worst = 0.0f64;
    for w in test_directions() {
        let (_, g, h) = eval(&sh, w)?;
        for l in 0..=lmax {
            let scale = ((l + 1) * (l + 1)) as f64;
            for k in l * l..(l + 1) * (l + 1) {
                let dot: f64 = (0..3).map(|i| g[k][i] * w[i]).sum();
                worst = worst.max(dot.abs() / scale);
                for i in 0..3 {
                    let hw: f64 = (0..3).map(|j| h[k][hessian_index(i, j)] * w[j]).sum();
                    worst = worst.max((hw + g[k][i]).abs() / scale);
                }
            }
        }
    }
    Ok(worst)
}

fn table1() -> Result<f64> {
    let rows = super::oracle::sh_hessian_table1()?;
    if rows.is_empty() {
        return Err(crate::error::Error::malformed(
            "tests/fixtures/sh_hessian.json",
            "no bands",
        ));
    }
    Ok(rows.iter().map(|r| r.1).fold(0.0, f64::max))
}
