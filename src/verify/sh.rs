//! Checks of the scalar SH core (`psh::sh`).

use super::Check;
use crate::error::Result;
use crate::geometry::rotation_from_rotvec;
use crate::geometry::{direction, direction_angles};
use crate::random::pseudo_random;
use crate::sh::evaluation::harmonics::{sh_complex, sh_real, ShEvaluator};
use crate::sh::evaluation::zonal::{funk_hecke, rotated_zonal_real, zonal_coefficients};
use crate::sh::recursion::legendre::{legendre_all, tri_index, zonal_legendre, Legendre, Polar};
use crate::sh::rotation::wigner_d::{for_each_block, RealWignerD, WignerD};
use crate::sh::transform::grid::SphereGrid;
use crate::sh::transform::sht::ShTransform;
use crate::sh::{gaunt, real_gaunt};
use crate::sh::{lm_index, num_coeffs};
use nalgebra::{Rotation3, Vector3};
use num_complex::Complex64;
use std::f64::consts::PI;

/// The polar angles of the stress checks: poles, 1e-300 and 1e-8 from them, generic.
pub const STRESS_THETAS: [f64; 7] = [0.0, 1e-300, 1e-8, 0.3, PI / 2.0, PI - 1e-8, PI];

pub fn checks() -> Vec<Check> {
    vec![
        Check {
            id: "sh.orthonormality",
            source: "PSH (3)",
            description: "Gram matrix of real SH l <= 24 on the exact Gauss-Legendre grid vs identity",
            tolerance: 1e-13,
            proof: Some("proofs/quadrature.md"),
            run: orthonormality,
        },
        Check {
            id: "sh.real_complex",
            source: "PSH (12)",
            description: "real SH vs their complex form, and Y_l,-m = (-1)^m conj(Y_lm), l <= 64",
            tolerance: 1e-14,
            proof: None,
            run: real_complex,
        },
        Check {
            id: "sh.addition_theorem",
            source: "DLMF 14.30.9",
            description: "sum_m Y_lm(a) Y_lm(b) vs (2l+1)/(4pi) P_l(a.b), l <= 300, random pairs (relative)",
            tolerance: 1e-13,
            proof: None,
            run: addition_theorem,
        },
        Check {
            id: "sh.band_norm_l2048",
            source: "DLMF 14.30.9",
            description: "sum_m |Y_lm|^2 = (2l+1)/(4pi) for every l <= 2048 at theta = 0, 1e-300, 1e-8, 0.3, pi/2, pi-1e-8, pi (relative)",
            tolerance: 1e-12,
            proof: Some("proofs/legendre-recursion.md"),
            run: band_norm_l2048,
        },
        Check {
            id: "sh.legendre_oracle",
            source: "PSH (1)",
            description: "Pbar_lm vs 40-digit oracle, every m of l in {0..12, 100, 1023, 2048} at theta = 0, 1e-300, 1e-8, 0.3, pi/2, pi-1e-8, pi (relative to band max)",
            tolerance: 1e-12,
            proof: Some("proofs/exact-oracles.md"),
            run: super::oracle::legendre,
        },
        Check {
            id: "sh.fast_vs_accurate",
            source: "PSH (12)",
            description: "vectorized f64 batch real SH vs the double-double path, l <= 200, poles included (relative to band max)",
            tolerance: 1e-12,
            proof: Some("proofs/legendre-recursion.md"),
            run: fast_vs_accurate,
        },
        Check {
            id: "sh.pixel_projection",
            source: "PSH (3), (12)",
            description: "texel projection summed order by order (real coefficients from the complex sums, m >= 0) vs the texel-major sum with sh_real, cube cross 8, l <= 100",
            tolerance: 1e-13,
            proof: Some("proofs/pixel-solid-angles.md"),
            run: pixel_projection,
        },
        Check {
            id: "sh.fast_path_l2048",
            source: "PSH (1)",
            description: "f64 table path (transforms, batch SH) vs the double-double path, every l <= 2048 at the poles, 1e-300, 1e-12, 1e-8, 1e-4 from them and generic angles, in units of l eps relative to sqrt((2l+1)/(4pi))",
            tolerance: 10.0,
            proof: Some("proofs/legendre-recursion.md"),
            run: fast_path_l2048,
        },
        Check {
            id: "wigner.definition",
            source: "PSH (9)",
            description: "D^l_mm' vs <Y_lm, R_F[Y_l'm']> projected on the exact grid, l <= 8 (in-block entries)",
            tolerance: 1e-13,
            proof: Some("proofs/wigner-recursion.md"),
            run: || Ok(wigner_projection()?.0),
        },
        Check {
            id: "wigner.edge_rotations",
            source: "PSH (9)",
            description: "D^1 of tiny turns about axes near z, tilted and horizontal, near half turns and the identity vs the Cayley-Klein form (units of eps), and D^100 vs the product of the blocks of the rotations' factorization about y and z (units of l eps)",
            tolerance: 10.0,
            proof: Some("proofs/euler-angles.md"),
            run: || {
                let e = crate::testing::cayley_klein_error()?;
                Ok(e.max(crate::testing::factorization_error(100)?))
            },
        },
        Check {
            id: "sh.gauss_legendre_poles",
            source: "PSH (3)",
            description: "Gauss-Legendre polar angles of n = 2048 and 8192 rings: distance to the root of P_n (double-double) of the 40 nodes next to each pole and 6 at the equator, in units of eps",
            tolerance: 4.0,
            proof: Some("proofs/quadrature.md"),
            run: gauss_legendre_poles,
        },
        Check {
            id: "wigner.block_diagonal",
            source: "PSH (9)",
            description: "largest |<Y_lm, R_F[Y_l'm']>| with l != l' on the exact grid, l <= 8",
            tolerance: 1e-13,
            proof: None,
            run: || Ok(wigner_projection()?.1),
        },
        Check {
            id: "wigner.unitarity_l1000",
            source: "PSH (9)",
            description: "D D^H = I for every block l <= 1000 of a generic rotation (full for l <= 64, sampled rows above)",
            tolerance: 1e-12,
            proof: Some("proofs/wigner-recursion.md"),
            run: unitarity_l1000,
        },
        Check {
            id: "wigner.oracle_l100",
            source: "PSH (9)",
            description: "d^l_mm'(beta) vs 40-digit oracle (Wigner's sum), full blocks l <= 6 and 206 entries at l = 100, beta = 0.3, 1.1, pi/2",
            tolerance: 1e-13,
            proof: Some("proofs/exact-oracles.md"),
            run: || super::oracle::wigner_d(0..=100),
        },
        Check {
            id: "wigner.oracle_l1000",
            source: "PSH (9)",
            description: "d^1000_mm'(beta) vs 40-digit oracle, 306 entries incl. m, m' = +-l, 0, beta = 0.3, 1.1, pi/2",
            tolerance: 1e-12,
            proof: Some("proofs/exact-oracles.md"),
            run: || super::oracle::wigner_d(1000..=1000),
        },
        Check {
            id: "wigner.composition",
            source: "PSH (8)-(9)",
            description: "D(R1 R2) = D(R1) D(R2), l <= 40",
            tolerance: 1e-13,
            proof: None,
            run: composition,
        },
        Check {
            id: "wigner.real",
            source: "PSH (13)",
            description: "real blocks: Y^R_lm'(R^-1 w) = sum_m Y^R_lm(w) D^R_mm'(R), l <= 20",
            tolerance: 1e-13,
            proof: Some("proofs/wigner-recursion.md"),
            run: real_wigner,
        },
        Check {
            id: "transform.round_trip_512",
            source: "PSH (2)-(3)",
            description: "real synthesis then analysis on the exact grid, L = 512 (relative to max |f_lm|)",
            tolerance: 1e-12,
            proof: Some("proofs/quadrature.md"),
            run: round_trip_512,
        },
        Check {
            id: "zonal.funk_hecke",
            source: "PSH (11)",
            description: "Funk-Hecke product vs angular convolution PSH (10) by quadrature, k = exp(2 cos theta), L = 10 (relative to max |k * f|)",
            tolerance: 1e-13,
            proof: Some("proofs/zonal.md"),
            run: funk_hecke_check,
        },
        Check {
            id: "zonal.rotated",
            source: "DLMF 14.30.9",
            description: "rotated ZH by the addition theorem vs projection of k(n.w) on the exact grid, L = 10",
            tolerance: 1e-13,
            proof: Some("proofs/zonal.md"),
            run: rotated_zonal,
        },
        Check {
            id: "gaunt.quadrature",
            source: "DLMF 34.3.22",
            description: "complex and real Gaunt coefficients vs integrals of three SH on the exact grid, l <= 6",
            tolerance: 1e-14,
            proof: Some("proofs/wigner3j-recursion.md"),
            run: || Ok(gaunt_by_quadrature()?.0),
        },
        Check {
            id: "gaunt.oracle",
            source: "DLMF 34.3.22",
            description: "3j symbols and complex, product-form and real Gaunt coefficients vs 40-digit exact values (Racah), l1, l2 <= 50 (relative)",
            tolerance: 1e-14,
            proof: Some("proofs/wigner3j-recursion.md"),
            run: super::oracle::gaunt_coefficients,
        },
        Check {
            id: "gaunt.selection_rules",
            source: "DLMF 34.3.22",
            description: "largest integral of three real SH whose Gaunt coefficient the selection rules set to 0, l <= 6",
            tolerance: 1e-14,
            proof: Some("proofs/wigner3j-recursion.md"),
            run: || Ok(gaunt_by_quadrature()?.1),
        },
    ]
}

/// Samples of all real SH `l <= lmax` on an exact grid: `(grid, values[point][lm])`.
pub(super) fn real_sh_on_grid(lmax: usize, grid_lmax: usize) -> Result<(SphereGrid, Vec<f64>)> {
    let g = SphereGrid::for_band_limit(grid_lmax)?;
    let ev = ShEvaluator::new(lmax)?;
    let dirs = (0..g.len())
        .map(|i| g.direction(i))
        .collect::<Result<Vec<_>>>()?;
    let mut y = vec![0.0; dirs.len() * ev.len()];
    ev.real_batch(&dirs, &mut y)?;
    Ok((g, y))
}

fn orthonormality() -> Result<f64> {
    let lmax = 24;
    let n = num_coeffs(lmax);
    let (g, y) = real_sh_on_grid(lmax, lmax)?;
    let mut gram = vec![0.0; n * n];
    for p in 0..g.len() {
        let w = g.point_weight(p);
        let row = &y[p * n..(p + 1) * n];
        for i in 0..n {
            let wi = w * row[i];
            for j in i..n {
                gram[i * n + j] += wi * row[j];
            }
        }
    }
    let mut worst = 0.0f64;
    for i in 0..n {
        for j in i..n {
            let expect = if i == j { 1.0 } else { 0.0 };
            worst = worst.max((gram[i * n + j] - expect).abs());
        }
    }
    Ok(worst)
}

fn real_complex() -> Result<f64> {
    let lmax = 64;
    let r = pseudo_random(40, 7);
    let mut worst = 0.0f64;
    for k in 0..20 {
        let theta = (r[2 * k] + 1.0) * 0.5 * PI;
        let phi = r[2 * k + 1] * PI;
        let yc = sh_complex(lmax, theta, phi)?;
        let yr = sh_real(lmax, theta, phi)?;
        for l in 0..=lmax {
            for m in -(l as i64)..=l as i64 {
                let sign = if m % 2 == 0 { 1.0 } else { -1.0 };
                let y = yc[lm_index(l, m)];
                let ym = yc[lm_index(l, -m)];
                worst = worst.max((ym - sign * y.conj()).norm());
                let expect = match m.signum() {
                    1 => (y + sign * ym) / 2f64.sqrt(),
                    0 => y,
                    _ => Complex64::i() * (sign * y - ym) / 2f64.sqrt(),
                };
                worst = worst.max((yr[lm_index(l, m)] - expect.re).abs());
                worst = worst.max(expect.im.abs());
            }
        }
    }
    Ok(worst)
}

fn addition_theorem() -> Result<f64> {
    let lmax = 300;
    let r = pseudo_random(40, 11);
    let mut worst = 0.0f64;
    for k in 0..10 {
        let a = direction((r[4 * k] + 1.0) * 0.5 * PI, r[4 * k + 1] * PI);
        let b = direction((r[4 * k + 2] + 1.0) * 0.5 * PI, r[4 * k + 3] * PI);
        let (ta, pa) = direction_angles(a)?;
        let (tb, pb) = direction_angles(b)?;
        let ya = sh_real(lmax, ta, pa)?;
        let yb = sh_real(lmax, tb, pb)?;
        let cos_g = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]).clamp(-1.0, 1.0);
        let p = zonal_legendre(lmax, cos_g.acos());
        for l in 0..=lmax {
            let s: f64 = (l * l..(l + 1) * (l + 1)).map(|i| ya[i] * yb[i]).sum();
            // P_l(cos g) = sqrt(4 pi / (2l+1)) Pbar_l0(g).
            let scale = (2 * l + 1) as f64 / (4.0 * PI);
            let expect = scale.sqrt() * p[l];
            worst = worst.max((s - expect).abs() / scale);
        }
    }
    Ok(worst)
}

fn band_norm_l2048() -> Result<f64> {
    let lmax = 2048;
    let mut worst = 0.0f64;
    for theta in STRESS_THETAS {
        let p = legendre_all(lmax, theta)?;
        for l in 0..=lmax {
            let mut s = p[tri_index(l, 0)].powi(2);
            for m in 1..=l {
                s += 2.0 * p[tri_index(l, m)].powi(2);
            }
            let expect = (2 * l + 1) as f64 / (4.0 * PI);
            worst = worst.max(((s - expect) / expect).abs());
        }
    }
    Ok(worst)
}

fn fast_vs_accurate() -> Result<f64> {
    let lmax = 200;
    let fast = ShEvaluator::new(lmax)?;
    let r = pseudo_random(64, 13);
    let mut dirs: Vec<[f64; 3]> = (0..32)
        .map(|k| direction((r[2 * k] + 1.0) * 0.5 * PI, r[2 * k + 1] * PI))
        .collect();
    dirs.extend([
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
        [1e-9, 0.0, 1.0],
        [0.0, 1.0, 0.0],
    ]);
    let n = fast.len();
    let mut y = vec![0.0; dirs.len() * n];
    fast.real_batch(&dirs, &mut y)?;
    let mut worst = 0.0f64;
    for (k, &w) in dirs.iter().enumerate() {
        let (t, p) = direction_angles(w)?;
        let exact = sh_real(lmax, t, p)?;
        for l in 0..=lmax {
            let band = ((2 * l + 1) as f64 / (4.0 * PI)).sqrt();
            for i in l * l..(l + 1) * (l + 1) {
                worst = worst.max((y[k * n + i] - exact[i]).abs() / band);
            }
        }
    }
    Ok(worst)
}

fn pixel_projection() -> Result<f64> {
    use crate::geometry::image_grid::{CubeCross, PixelGrid};
    let lmax = 100;
    let g = CubeCross::new(8)?;
    let v = pseudo_random(g.len(), 29);
    let got = crate::sh::project_real(&g, &v, lmax)?;
    let mut want = vec![0.0; num_coeffs(lmax)];
    for i in (0..g.len()).filter(|&i| g.solid_angle(i) > 0.0) {
        let (t, p) = direction_angles(g.direction(i))?;
        for (x, y) in want.iter_mut().zip(sh_real(lmax, t, p)?) {
            *x += g.solid_angle(i) * v[i] * y;
        }
    }
    Ok(got
        .iter()
        .zip(&want)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs())))
}

fn fast_path_l2048() -> Result<f64> {
    let lmax = 2048;
    let table = Legendre::new(lmax)?;
    let mut worst = 0.0f64;
    let thetas = STRESS_THETAS.into_iter().chain([1e-12, 1e-4, PI - 1e-4]);
    for theta in thetas {
        let exact = legendre_all(lmax, theta)?;
        table.for_each_column(Polar::from_theta(theta), |m, col| {
            for (k, &v) in col.iter().enumerate() {
                let l = m + k;
                let bound = ((2 * l + 1) as f64 / (4.0 * PI)).sqrt();
                let e = (v - exact[tri_index(l, m)]).abs() / bound;
                worst = worst.max(e / (l.max(1) as f64 * f64::EPSILON));
            }
        });
    }
    Ok(worst)
}

fn gauss_legendre_poles() -> Result<f64> {
    let a = crate::testing::gauss_legendre_pole_distance(2048)?;
    Ok(a.max(crate::testing::gauss_legendre_pole_distance(8192)?))
}

fn generic_rotation() -> Result<Rotation3<f64>> {
    rotation_from_rotvec([0.3, -1.1, 0.7])
}

/// `(max in-block error, max off-block magnitude)` of D from its definition PSH (9).
fn wigner_projection() -> Result<(f64, f64)> {
    let lmax = 8;
    let r = generic_rotation()?;
    let d = WignerD::new(&r, lmax)?;
    let t = ShTransform::new(lmax)?;
    let ev = ShEvaluator::new(lmax)?;
    let n = num_coeffs(lmax);
    let npts = t.grid().len();
    let mut values = vec![Complex64::default(); npts * n];
    let mut y = vec![Complex64::default(); n];
    for i in 0..npts {
        let v = r.inverse() * Vector3::from(t.grid().direction(i)?);
        let (th, ph) = direction_angles([v.x, v.y, v.z])?;
        ev.complex(th, ph, &mut y)?;
        values[i * n..(i + 1) * n].copy_from_slice(&y);
    }
    let (mut in_block, mut off_block) = (0.0f64, 0.0f64);
    let mut col = vec![Complex64::default(); npts];
    let mut coeffs = vec![Complex64::default(); n];
    for lp in 0..=lmax {
        for mp in -(lp as i64)..=lp as i64 {
            let j = lm_index(lp, mp);
            for i in 0..npts {
                col[i] = values[i * n + j];
            }
            t.analysis_complex(&col, &mut coeffs)?;
            for l in 0..=lmax {
                for m in -(l as i64)..=l as i64 {
                    let got = coeffs[lm_index(l, m)];
                    if l == lp {
                        let nb = 2 * l + 1;
                        let e =
                            d.block(l)?[(m + l as i64) as usize * nb + (mp + l as i64) as usize];
                        in_block = in_block.max((got - e).norm());
                    } else {
                        off_block = off_block.max(got.norm());
                    }
                }
            }
        }
    }
    Ok((in_block, off_block))
}

fn unitarity_l1000() -> Result<f64> {
    let r = generic_rotation()?;
    let mut worst = 0.0f64;
    for_each_block(&r, 1000, |l, b| {
        let n = 2 * l + 1;
        let rows: Vec<usize> = if l <= 64 {
            (0..n).collect()
        } else {
            vec![0, 1, l / 3, l, l + 1, 2 * l - 1, 2 * l]
        };
        for &i in &rows {
            for &k in &rows {
                let s: Complex64 = (0..n).map(|j| b[i * n + j] * b[k * n + j].conj()).sum();
                let expect = if i == k { 1.0 } else { 0.0 };
                worst = worst.max((s - expect).norm());
            }
        }
    })?;
    Ok(worst)
}

fn composition() -> Result<f64> {
    let lmax = 40;
    let r1 = generic_rotation()?;
    let r2 = rotation_from_rotvec([-2.0, 0.4, 0.9])?;
    let (d1, d2, d12) = (
        WignerD::new(&r1, lmax)?,
        WignerD::new(&r2, lmax)?,
        WignerD::new(&(r1 * r2), lmax)?,
    );
    let mut worst = 0.0f64;
    for l in 0..=lmax {
        let n = 2 * l + 1;
        let (a, b, c) = (d1.block(l)?, d2.block(l)?, d12.block(l)?);
        for i in 0..n {
            for k in 0..n {
                let s: Complex64 = (0..n).map(|j| a[i * n + j] * b[j * n + k]).sum();
                worst = worst.max((s - c[i * n + k]).norm());
            }
        }
    }
    Ok(worst)
}

fn real_wigner() -> Result<f64> {
    let lmax = 20;
    let r = generic_rotation()?;
    let dr = RealWignerD::new(&r, lmax)?;
    let ev = ShEvaluator::new(lmax)?;
    let pts = pseudo_random(20, 17);
    let mut worst = 0.0f64;
    let (mut y0, mut y1) = (vec![0.0; ev.len()], vec![0.0; ev.len()]);
    for k in 0..10 {
        let w = Vector3::from(direction(
            (pts[2 * k] + 1.0) * 0.5 * PI,
            pts[2 * k + 1] * PI,
        ));
        let v = r.inverse() * w;
        let (t0, p0) = direction_angles([w.x, w.y, w.z])?;
        let (t1, p1) = direction_angles([v.x, v.y, v.z])?;
        ev.real(t0, p0, &mut y0)?;
        ev.real(t1, p1, &mut y1)?;
        for l in 0..=lmax {
            let n = 2 * l + 1;
            for mp in 0..n {
                let b = dr.block(l)?;
                let s: f64 = (0..n).map(|m| y0[l * l + m] * b[m * n + mp]).sum();
                worst = worst.max((s - y1[l * l + mp]).abs());
            }
        }
    }
    Ok(worst)
}

fn round_trip_512() -> Result<f64> {
    let lmax = 512;
    let t = ShTransform::new(lmax)?;
    let c = pseudo_random(num_coeffs(lmax), 19);
    let mut f = vec![0.0; t.grid().len()];
    t.synthesis_real(&c, &mut f)?;
    let mut back = vec![0.0; c.len()];
    t.analysis_real(&f, &mut back)?;
    let scale = c.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    Ok(c.iter()
        .zip(&back)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
        / scale)
}

fn funk_hecke_check() -> Result<f64> {
    let lmax = 10;
    let kernel = |t: f64| (2.0 * t.cos()).exp();
    let k = zonal_coefficients(kernel, lmax)?;
    let f = pseudo_random(num_coeffs(lmax), 23);
    let conv = funk_hecke(&k, &f)?;
    // Angular domain PSH (10): integrate k(angle(w, w')) f(w') over an exact grid fine
    // enough for the smooth kernel (its ZH coefficients fall below 1e-30 by l = 40).
    let fine = ShTransform::new(60)?;
    let mut f_padded = vec![0.0; num_coeffs(60)];
    f_padded[..f.len()].copy_from_slice(&f);
    let mut f_fine = vec![0.0; fine.grid().len()];
    fine.synthesis_real(&f_padded, &mut f_fine)?;
    let ev = ShEvaluator::new(lmax)?;
    let mut y = vec![0.0; ev.len()];
    let pts = pseudo_random(12, 29);
    let (mut worst, mut scale) = (0.0f64, 0.0f64);
    for k6 in 0..6 {
        let (t0, p0) = ((pts[2 * k6] + 1.0) * 0.5 * PI, pts[2 * k6 + 1] * PI);
        let w = direction(t0, p0);
        let mut direct = 0.0;
        for i in 0..fine.grid().len() {
            let v = fine.grid().direction(i)?;
            let c = (w[0] * v[0] + w[1] * v[1] + w[2] * v[2]).clamp(-1.0, 1.0);
            direct += fine.grid().point_weight(i) * kernel(c.acos()) * f_fine[i];
        }
        ev.real(t0, p0, &mut y)?;
        let freq: f64 = y.iter().zip(&conv).map(|(a, b)| a * b).sum();
        worst = worst.max((direct - freq).abs());
        scale = scale.max(direct.abs());
    }
    Ok(worst / scale)
}

fn rotated_zonal() -> Result<f64> {
    let lmax = 10;
    // A polynomial of degree 7 in cos(theta): band-limited, so the grid projection is exact.
    let poly = |c: f64| 0.3 + c - 0.7 * c.powi(3) + 0.25 * c.powi(7);
    let k = zonal_coefficients(|t: f64| poly(t.cos()), lmax)?;
    let n = [0.48, -0.6, 0.64];
    let coeffs = rotated_zonal_real(&k, n)?;
    let t = ShTransform::new(lmax)?;
    let vals: Vec<f64> = (0..t.grid().len())
        .map(|i| {
            let v = t.grid().direction(i)?;
            Ok(poly(n[0] * v[0] + n[1] * v[1] + n[2] * v[2]))
        })
        .collect::<Result<_>>()?;
    let mut proj = vec![0.0; num_coeffs(lmax)];
    t.analysis_real(&vals, &mut proj)?;
    Ok(coeffs
        .iter()
        .zip(&proj)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs())))
}

/// `(max |Gaunt - quadrature|, max |quadrature| where the rules give 0)`, complex and
/// real, all `l1, l2, l3 <= 6`.
fn gaunt_by_quadrature() -> Result<(f64, f64)> {
    let lmax = 6;
    let n = num_coeffs(lmax);
    // Products of three functions of band 6 have band 18: a grid for band 9 integrates
    // products of two functions of band 9, i.e. band 18 exactly.
    let (g, y) = real_sh_on_grid(lmax, 9)?;
    let ev = ShEvaluator::new(lmax)?;
    let mut yc = vec![Complex64::default(); g.len() * n];
    for p in 0..g.len() {
        let (t, ph) = g.angles(p)?;
        ev.complex(t, ph, &mut yc[p * n..(p + 1) * n])?;
    }
    let (mut value_err, mut rule_err) = (0.0f64, 0.0f64);
    let lm = |i: usize| crate::sh::lm_of_index(i);
    for i in 0..n {
        for j in i..n {
            for k in j..n {
                let (mut qr, mut qc) = (0.0, Complex64::default());
                for p in 0..g.len() {
                    let w = g.point_weight(p);
                    qr += w * y[p * n + i] * y[p * n + j] * y[p * n + k];
                    qc += w * yc[p * n + i] * yc[p * n + j] * yc[p * n + k];
                }
                let ((l1, m1), (l2, m2), (l3, m3)) = (lm(i), lm(j), lm(k));
                let gr = real_gaunt(l1, m1, l2, m2, l3, m3)?;
                let gc = gaunt(l1, m1, l2, m2, l3, m3)?;
                value_err = value_err.max((gr - qr).abs()).max((gc - qc).norm());
                if gr == 0.0 {
                    rule_err = rule_err.max(qr.abs());
                }
                if gc == 0.0 {
                    rule_err = rule_err.max(qc.norm());
                }
            }
        }
    }
    Ok((value_err, rule_err))
}
