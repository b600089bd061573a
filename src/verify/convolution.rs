//! Checks of the polarized spherical convolution theorem (`psh::polarized::convolution`).

use super::{random_kernel, random_psh, random_psh_matrix, Check};
use crate::error::Result;
use crate::polarized::{
    apply_angular, convolve_angular, kernel_coefficients, project_operator, project_to_convolution,
    Codomain, ConvolutionKernel, KernelCoefficients, PshTransform, SpinBlock22,
};
use crate::sh::zonal::zonal_coefficients;

pub fn checks() -> Vec<Check> {
    vec![
        Check {
            id: "conv.kernel_coefficients",
            source: "PSH (68a)-(68e)",
            description: "a random band-limited kernel (all 16 entries non-zero, L = 8) synthesized in theta and its coefficients recovered by 1D Gauss-Legendre quadrature (relative)",
            tolerance: 1e-13,
            proof: Some("proofs/convolution.md"),
            run: coefficients_round_trip,
        },
        Check {
            id: "conv.matrix_form",
            source: "PSH (63), (69a)-(69c)",
            description: "the theorem's coefficient matrix of a random band-limited kernel (L = 5) vs the kernel's Mueller field (PSH (63)) projected on the exact grid by PSH (40) (relative)",
            tolerance: 1e-12,
            proof: Some("proofs/convolution.md"),
            run: matrix_form,
        },
        Check {
            id: "conv.angular_vs_frequency_random",
            source: "PSH Fig. 16, (69)",
            description: "random band-limited kernel (16 non-zero entries, L = 4) and field: angular-domain convolution on the exact grid, projected, vs the frequency-domain theorem (relative)",
            tolerance: 1e-10,
            proof: Some("proofs/convolution.md"),
            run: angular_vs_frequency_random,
        },
        Check {
            id: "conv.angular_vs_frequency_linear_zenith",
            source: "PSH Fig. 16, Sec. 6.4.3",
            description: "k = (pi - theta) I on a band-limited field (L = 5): PSH (63) by polar quadrature about each exact-grid point, projected, vs the theorem (relative)",
            tolerance: 1e-10,
            proof: Some("proofs/convolution.md"),
            run: angular_vs_frequency_linear_zenith,
        },
        Check {
            id: "conv.scalar_reduces_to_funk_hecke",
            source: "PSH (11), (69a)",
            description: "the spin 0-to-0 coefficients of a kernel (L = 40) vs the zonal Funk-Hecke factors sqrt(4 pi/(2l+1)) k_l of its (0, 0) entry (max |difference|)",
            tolerance: 1e-13,
            proof: Some("proofs/convolution.md"),
            run: scalar_reduces,
        },
        Check {
            id: "conv.projection_residual",
            source: "PSH Sec. 6.4.3",
            description: "a convolution's matrix projects onto the convolutions with zero residual and the same coefficients (max of residual and coefficient difference); a random matrix (L = 3) has residual above 0.5 (the check fails otherwise)",
            tolerance: 1e-13,
            proof: Some("proofs/convolution.md"),
            run: projection_residual,
        },
    ]
}

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |a, v| a.max(v.abs()))
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

fn forms(k: &KernelCoefficients) -> Vec<f64> {
    (0..=k.lmax())
        .flat_map(|l| k.real_form(l).expect("band").into_iter().flatten())
        .collect()
}

fn coefficients_round_trip() -> Result<f64> {
    let k = random_kernel(8, 101)?;
    let back = kernel_coefficients(&ConvolutionKernel::from_coefficients(k.clone()), 8)?;
    let (a, b) = (forms(&k), forms(&back));
    Ok(max_diff(&a, &b) / max_abs(&a))
}

fn matrix_form() -> Result<f64> {
    let k = random_kernel(5, 103)?;
    let field = ConvolutionKernel::from_coefficients(k.clone());
    let projected = project_operator(&field, 5, 10, SpinBlock22::ComplexPair)?;
    let theorem = k.to_matrix()?;
    Ok(max_diff(projected.data(), theorem.data()) / max_abs(theorem.data()))
}

fn angular_vs_frequency_random() -> Result<f64> {
    let lmax = 4;
    let k = random_kernel(lmax, 107)?;
    let f = random_psh(lmax, Codomain::Full, 1, 109)?;
    let t = PshTransform::new(lmax)?;
    let field = ConvolutionKernel::from_coefficients(k.clone());
    let angular = t.project(
        &apply_angular(&field, &t, &t.reconstruct(&f, 0)?)?,
        Codomain::Full,
    )?;
    let freq = k.convolve(&f)?;
    Ok(max_diff(angular.data(), freq.data()) / max_abs(freq.data()))
}

fn angular_vs_frequency_linear_zenith() -> Result<f64> {
    let lmax = 5;
    let kernel = ConvolutionKernel::linear_zenith();
    let f = random_psh(lmax, Codomain::Full, 1, 113)?;
    let t = PshTransform::new(lmax)?;
    let g = t.grid();
    let points = (0..g.len())
        .map(|i| g.direction(i))
        .collect::<Result<Vec<_>>>()?;
    let angular = t.project(
        &convolve_angular(&kernel, &f, 0, &points, 48)?,
        Codomain::Full,
    )?;
    let freq = kernel_coefficients(&kernel, lmax)?.convolve(&f)?;
    Ok(max_diff(angular.data(), freq.data()) / max_abs(freq.data()))
}

fn scalar_reduces() -> Result<f64> {
    let lmax = 40;
    let entry = |t: f64| (1.0 + t).ln() * (2.0 * t).cos() + 0.3;
    let kernel = ConvolutionKernel::from_fn(move |t| {
        let mut k = [[0.1 * t; 4]; 4];
        k[0][0] = entry(t);
        k
    });
    let k = kernel_coefficients(&kernel, lmax)?;
    let zonal = zonal_coefficients(entry, lmax)?.funk_hecke_factors();
    Ok((0..=lmax)
        .map(|l| (k.channel_matrix(l).expect("band")[0][0].re - zonal[l]).abs())
        .fold(0.0, f64::max))
}

fn projection_residual() -> Result<f64> {
    let k = random_kernel(5, 127)?;
    let (back, residual) = project_to_convolution(&k.to_matrix()?)?;
    let (a, b) = (forms(&k), forms(&back));
    let (_, random_residual) = project_to_convolution(&random_psh_matrix(3, 131)?)?;
    let penalty = if random_residual > 0.5 { 0.0 } else { 1.0 };
    Ok(residual.max(max_diff(&a, &b) / max_abs(&a)).max(penalty))
}
