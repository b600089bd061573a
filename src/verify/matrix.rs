//! Checks of PSH coefficient matrices (`psh::polarized::matrix`).

use super::Check;
use crate::error::Result;
use crate::polarized::{
    apply_angular, in_index_set, project_operator, Codomain, MatrixKernel, PshTransform,
    SpinBlock22,
};
use crate::stokes::MuellerField;
use crate::testing::{random_psh, random_psh_matrix};

pub fn checks() -> Vec<Check> {
    vec![
        Check {
            id: "matrix.projection_exact",
            source: "PSH (40), (51)",
            description: "a random band-limited Mueller transform field (L = 3) projected on the exact grid with the complex-pair 2-to-2 block recovers its coefficient matrix (max |difference|)",
            tolerance: 1e-12,
            proof: Some("proofs/coefficient-matrices.md"),
            run: projection_exact,
        },
        Check {
            id: "matrix.band_limit_residual",
            source: "PSH (40); Parseval",
            description: "the band-limit residual psh pbrdf project reports, sqrt(1 - |P_L|^2 / |P|^2) from the grid's norm of the operator: a random operator of degree 5 projected to degree 3 on the grid of band 5 against the share of its matrix entries above degree 3 (|difference|)",
            tolerance: 1e-12,
            proof: Some("proofs/band-limit-residual.md"),
            run: band_limit_residual,
        },
        Check {
            id: "matrix.angular_vs_frequency",
            source: "PSH (39), (41)",
            description: "band-limited operator applied in the angular domain on the exact grid and projected vs the matrix-vector product, L = 3 (relative)",
            tolerance: 1e-12,
            proof: Some("proofs/coefficient-matrices.md"),
            run: angular_vs_frequency,
        },
        Check {
            id: "matrix.complex_pair_vs_four_integrals",
            source: "PSH (44)-(51)",
            description: "coefficient matrix of a polarized plastic pBRDF (L = 4, grid 8): two complex integrals vs four real integrals for the spin 2-to-2 block (relative)",
            tolerance: 1e-13,
            proof: Some("proofs/coefficient-matrices.md"),
            run: complex_pair_vs_four_integrals,
        },
        Check {
            id: "matrix.isotropic_sparsity",
            source: "PSH (52)-(53)",
            description: "coefficient matrix of an isotropic pBRDF (polarized plastic, L = 4, grid 8): largest entry PSH (52)-(53) require to vanish relative to the largest entry, and the sparse isotropic product vs the dense one (relative)",
            tolerance: 1e-13,
            proof: None,
            run: isotropic_sparsity,
        },
        Check {
            id: "matrix.rotation_to_normal",
            source: "PSH (59), (35)-(37)",
            description: "rotated coefficient matrix D P D^T vs the projection of the rotated Mueller field R_M[P(R^-1 w_i, R^-1 w_o)], band-limited P, L = 3 (relative)",
            tolerance: 1e-12,
            proof: Some("proofs/psh-rotation.md"),
            run: rotation_to_normal,
        },
        Check {
            id: "matrix.spin_blocks",
            source: "PSH (42)",
            description: "coefficient matrix of a polarized plastic, a rough gold pBRDF and a random band-limited operator (all nine blocks non-zero; L = 3, grid 5) computed block by spin (PSH (42)-(43), complex-pair 2-to-2 block) vs the defining double integral PSH (40) with the full 4 x 4 Mueller matrix between the full-Stokes basis functions, on the same grid (relative to the largest entry)",
            // The same quadrature summed in two orders: rounding of ~G = 60 terms per
            // integral twice; measured 8.9e-16, tolerance 45 ulps.
            tolerance: 1e-14,
            proof: Some("proofs/coefficient-matrices.md"),
            run: spin_blocks,
        },
    ]
}

/// PSH (40) as printed: `sum_b sum_a w_b w_a Y_{j_o p_o}(w_b) . M(a, b) Y_{j_i p_i}(w_a)`
/// with the full 4 x 4 matrix `M(a, b) = [P(w_a, w_b)]^{F(w_a) -> F(w_b)}` (theta-phi
/// frames), on the exact grid of band `grid_lmax`: no split into spin blocks.
fn brute_force_matrix(
    field: &(impl MuellerField + ?Sized),
    lmax: usize,
    grid_lmax: usize,
) -> Result<Vec<f64>> {
    use crate::geometry::frame::{FrameField, ThetaPhiFrameField};
    use crate::polarized::PshVector;
    use crate::sh::num_coeffs;
    let t = PshTransform::new(grid_lmax)?;
    let grid = t.grid();
    let (np, n, big) = (grid.len(), num_coeffs(lmax), num_coeffs(grid_lmax));
    // basis[j * 4 + p]: the basis function Y_{jp} on the grid (zero outside PSH (31)).
    let mut basis = vec![vec![[0.0; 4]; np]; n * 4];
    for j in 0..n {
        for p in 0..4 {
            if !in_index_set(j, p) {
                continue;
            }
            let mut data = vec![0.0; big * 4];
            data[j * 4 + p] = 1.0;
            basis[j * 4 + p] = t.reconstruct(
                &PshVector::from_data(grid_lmax, Codomain::Full, 1, data)?,
                0,
            )?;
        }
    }
    let tp = ThetaPhiFrameField::new();
    let frames = (0..np)
        .map(|i| tp.frame(grid.direction(i)?))
        .collect::<Result<Vec<_>>>()?;
    let mut out = vec![0.0; n * n * 16];
    for b in 0..np {
        let wb = grid.point_weight(b);
        // inner[k][p_o] = sum_a w_a (M(a, b) Y_k(w_a))_{p_o}, k = j_i * 4 + p_i.
        let mut inner = vec![[0.0; 4]; n * 4];
        for a in 0..np {
            let m = field.matrix_in(&frames[a], &frames[b])?.matrix();
            let wa = grid.point_weight(a);
            for (acc, y) in inner.iter_mut().zip(&basis) {
                let v = m * nalgebra::Vector4::from(y[a]);
                for po in 0..4 {
                    acc[po] += wa * v[po];
                }
            }
        }
        for jo in 0..n {
            for po in 0..4 {
                let yo = basis[jo * 4 + po][b];
                for (k, acc) in inner.iter().enumerate() {
                    let dot: f64 = (0..4).map(|q| yo[q] * acc[q]).sum();
                    out[((jo * n + k / 4) * 4 + po) * 4 + k % 4] += wb * dot;
                }
            }
        }
    }
    Ok(out)
}

/// PSH (42): the coefficient matrix computed block by spin equals PSH (40) with the full
/// Mueller matrix.
fn spin_blocks() -> Result<f64> {
    let plastic = crate::optics::PolarizedPlastic::new(0.3, 1.5, 0.5)?;
    let gold = crate::optics::Conductor::new(0.4, 0.18, 3.4)?;
    // Fresnel-based models have M03 = M30 = 0 in every frame; the random band-limited
    // operator fills all nine blocks.
    let random = random_psh_matrix(3, 97)?;
    let kernel = MatrixKernel(&random);
    let (lmax, grid_lmax) = (3, 5);
    let mut worst = 0.0f64;
    for field in [&plastic as &dyn MuellerField, &gold, &kernel] {
        let blocks = project_operator(field, lmax, grid_lmax, SpinBlock22::ComplexPair)?;
        let full = brute_force_matrix(field, lmax, grid_lmax)?;
        worst = worst.max(max_diff(blocks.data(), &full) / max_abs(&full));
    }
    Ok(worst)
}

/// `R_M[P(R^-1 w_i, R^-1 w_o)]` (PSH (59)).
struct Rotated<'a, F>(&'a F, nalgebra::Rotation3<f64>);

impl<F: MuellerField> MuellerField for Rotated<'_, F> {
    fn transform(&self, wi: [f64; 3], wo: [f64; 3]) -> Result<crate::stokes::MuellerTransform> {
        let back = |w: [f64; 3]| {
            let v = self.1.inverse() * nalgebra::Vector3::from(w);
            [v.x, v.y, v.z]
        };
        self.0.transform(back(wi), back(wo))?.rotate(&self.1)
    }
}

fn rotation_to_normal() -> Result<f64> {
    let m = random_psh_matrix(3, 89)?;
    let r = crate::geometry::rotation_from_rotvec([0.4, -1.3, 0.8])?;
    let rotated = m.rotated(&r)?;
    let direct = project_operator(
        &Rotated(&MatrixKernel(&m), r),
        3,
        3,
        SpinBlock22::ComplexPair,
    )?;
    Ok(max_diff(rotated.data(), direct.data()) / max_abs(direct.data()))
}

fn isotropic_sparsity() -> Result<f64> {
    use crate::polarized::{isotropy_defect, IsotropicMatrix};
    let plastic = crate::optics::PolarizedPlastic::new(0.3, 1.5, 0.5)?;
    let m = project_operator(&plastic, 4, 8, SpinBlock22::ComplexPair)?;
    let defect = isotropy_defect(&m);
    let sparse = IsotropicMatrix::from_dense(&m, 1e-12)?;
    let f = random_psh(4, Codomain::Full, 3, 83)?;
    let (a, b) = (sparse.apply(&f)?, m.apply(&f)?);
    Ok(defect.max(max_diff(a.data(), b.data()) / max_abs(b.data())))
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

fn projection_exact() -> Result<f64> {
    let m = random_psh_matrix(3, 71)?;
    let p = project_operator(&MatrixKernel(&m), 3, 3, SpinBlock22::ComplexPair)?;
    Ok(max_diff(p.data(), m.data()))
}

fn band_limit_residual() -> Result<f64> {
    let m = random_psh_matrix(5, 73)?;
    let (p, norm_sq) = crate::polarized::project_operator_normed(
        &MatrixKernel(&m),
        3,
        5,
        SpinBlock22::ComplexPair,
        &crate::progress::Silent,
    )?;
    let got = crate::polarized::band_limit_residual(norm_sq, &p);
    Ok((got - crate::testing::share_above(&m, 3)).abs())
}

fn angular_vs_frequency() -> Result<f64> {
    let lmax = 3;
    let m = random_psh_matrix(lmax, 73)?;
    let t = PshTransform::new(lmax)?;
    let f = random_psh(lmax, Codomain::Full, 1, 79)?;
    let field = t.reconstruct(&f, 0)?;
    let out = apply_angular(&MatrixKernel(&m), &t, &field)?;
    let angular = t.project(&out, Codomain::Full)?;
    let freq = m.apply(&f)?;
    Ok(max_diff(angular.data(), freq.data()) / max_abs(freq.data()))
}

fn complex_pair_vs_four_integrals() -> Result<f64> {
    let plastic = crate::optics::PolarizedPlastic::new(0.3, 1.5, 0.5)?;
    let a = project_operator(&plastic, 4, 8, SpinBlock22::ComplexPair)?;
    let b = project_operator(&plastic, 4, 8, SpinBlock22::FourIntegrals)?;
    Ok(max_diff(a.data(), b.data()) / max_abs(b.data()))
}
