//! Checks of the isotropic spherical decomposition (`psh::isd`, ISD (6)-(19), (33)-(34)).

use super::Check;
use crate::error::Result;
use crate::geometry::direction_angles;
use crate::geometry::rotation_from_rotvec;
use crate::isd::filter::{sh_rotate_dot, spherical_light};
use crate::isd::{pi_l, DirectionSet, Isd, Pattern, PreConvolved, Profile, Sharing};
use crate::lights::source::Order;
use crate::lights::spherical::{SphericalLight, SphericalLights};
use crate::random::pseudo_random;
use crate::sh::evaluation::harmonics::sh_real;
use crate::sh::num_coeffs;
use crate::sh::transform::sht::ShTransform;
use crate::testing::random_directions;

/// The checks of the isotropic spherical decomposition, in `psh verify`'s order.
pub fn checks() -> Vec<Check> {
    vec![
        Check {
            id: "isd.reconstruction",
            source: "ISD (12), Fig. 3",
            description: "ISD (RZH and Legendre profiles, Halton per-band and Fibonacci shared directions, L = 16) of random band-limited kernels evaluated in the angular domain vs their SH expansion at 500 random directions (relative to the largest |k|)",
            tolerance: 1e-12,
            proof: None,
            run: reconstruction,
        },
        Check {
            id: "isd.filter_vs_wigner",
            source: "ISD (6), (11), (13)",
            description: "filtered signal by ISD (all five profiles, per-band Fibonacci directions at L = 8; RZH and Legendre shared at L = 16) vs Wigner D rotation of the kernel's SH coefficients and dot product, 8 random rotations each (relative to |c| |f|)",
            tolerance: 1e-10,
            proof: Some("proofs/isd.md"),
            run: filter_vs_wigner,
        },
        Check {
            id: "isd.transfer_matrix",
            source: "ISD (16), (17)",
            description: "SH projection (Gauss-Legendre grid of band 96) of the ISD function of Gaussian and Gauss-Legendre profiles (per-band Fibonacci, L = 6) vs the kernel's coefficients c (relative to the largest |c|)",
            tolerance: 1e-12,
            proof: Some("proofs/isd.md"),
            run: transfer_matrix,
        },
        Check {
            id: "isd.legendre_beta",
            source: "ISD (16), Sec. 7.2",
            description: "beta_ll' of the Legendre profile P_l by quadrature vs pi_l delta_ll', l, l' <= 24",
            tolerance: 1e-13,
            proof: Some("proofs/isd.md"),
            run: legendre_beta,
        },
        Check {
            id: "isd.preconvolution",
            source: "ISD (13), (14)",
            description: "pre-convolved signals fhat_l(w) (RZH, Legendre, Gaussian, Gauss-Legendre profiles, L = 6) vs the convolution integral of g_l(w . w') f(w') on a Gauss-Legendre grid of band 96, 20 random w (relative to |f|)",
            tolerance: 1e-12,
            proof: Some("proofs/isd.md"),
            run: preconvolution,
        },
        Check {
            id: "isd.spherical_light",
            source: "ISD (33), (34)",
            description: "a spherical light filtered by ISD (RZH shared, Gaussian per band; L = 10) vs the light's SH coefficients (SHH (2)) dotted with the Wigner-rotated kernel, 8 random rotations (relative to |c| |E|)",
            tolerance: 1e-10,
            proof: Some("proofs/isd.md"),
            run: light,
        },
        Check {
            id: "isd.rotated_zonal",
            source: "ISD (8)",
            description: "the RZH basis functions phi_l^m (Isd::evaluate on unit weights, Fibonacci per band and Halton shared directions, L = 8) vs y_l^0((R_l^m)^-1 w) with R_l^m an explicit rotation taking z to z_l^m, turned by a random angle about z (any such rotation), and the real SH of PSH (12), 64 random w (relative to max |y_l^0|)",
            // y_l^0 = sqrt((2l+1)/(4 pi)) P_l(t) with |P_l'| <= l(l+1)/2 = 36 at l = 8 and
            // |P_l| <= 1: the rounding of t = w . z_l^m (a few eps) becomes about
            // 36 x 4 eps = 3.2e-14 relative; measured 1.6e-14.
            tolerance: 5e-14,
            proof: Some("proofs/isd.md"),
            run: rotated_zonal,
        },
        Check {
            id: "isd.rzh_matrix",
            source: "ISD (10)",
            description: "the RZH transfer matrix M (blocks M_l, Fibonacci per band and shared, Halton per band, L = 8) vs <y_l'^m', y_l^0((R_l^m)^-1 .)> by quadrature on the exact grid of band 8 (explicit rotations), every entry including the zero off-diagonal blocks, and c = M Lambda for the weights of a random kernel with that M (relative to max |M| and to |c| |Lambda|)",
            // Exact quadrature of products of band-8 functions on the grid: measured
            // 1.9e-15, tolerance 45 ulps.
            tolerance: 1e-14,
            proof: Some("proofs/isd.md"),
            run: rzh_matrix,
        },
        Check {
            id: "isd.gaussian_profile",
            source: "ISD (19)",
            description: "ZH coefficients beta_ll' = <phi_l, y_l'^0> of the Gaussian profile phi_l = exp(-(1 - w.z) l^2) (Profile::Gaussian, by quadrature of its values), l, l' <= 12, vs the closed form sqrt(4 pi (2l' + 1)) e^{-l^2} i_l'(l^2) (modified spherical Bessel function, positive series; relative to max_l' |beta_ll'|)",
            // Adaptive Clenshaw-Curtis at 1e-15 per panel against a positive series
            // (1.6e-15 against mpmath): measured 1.7e-15, tolerance 45 ulps.
            tolerance: 1e-14,
            proof: Some("proofs/isd.md"),
            run: gaussian_profile,
        },
        Check {
            id: "isd.conditioning",
            source: "ISD Fig. 13",
            description: "2-norm condition numbers of M (RZH, Legendre, Gaussian; Fibonacci and Halton; per band and shared; L = 1, 2, 4, 6, 8 where cond <= 2e4) vs sqrt(cond(M^T M)) with M^T M = sum_l' beta_l(j)l' beta_l(k)l' P_l'(z_j . z_k) (addition theorem, closed-form Gaussian beta) by cyclic Jacobi eigenvalues (largest relative difference); ISD Sec. 7.2 at L = 8: sharing must raise cond by 1e3 or more for Phong, Gaussian and Gauss-Legendre and change it by less than 10^1.5 for RZH and Legendre (error 1 if not)",
            // The Gram route loses eps cond^2 (rounding of M^T M): at most 2.2e-16 (2e4)^2
            // = 9e-8; measured 2.1e-9, tolerance that bound.
            tolerance: 1e-7,
            proof: Some("proofs/isd.md"),
            run: conditioning,
        },
    ]
}

/// A rotation `R` with `R z = n`, turned first by `twist` about `z` (ISD (8) holds for
/// any such rotation; the footnote's construction is one of them).
fn rotation_to(n: [f64; 3], twist: f64) -> Result<nalgebra::Rotation3<f64>> {
    let align = crate::geometry::frame::Frame::from_z(n)?.rotation();
    Ok(align * nalgebra::Rotation3::from_axis_angle(&nalgebra::Vector3::z_axis(), twist))
}

/// `y_l^0(R^-1 w)` by the real SH (PSH (12)).
fn rotated_y_l0(l: usize, r: &nalgebra::Rotation3<f64>, w: [f64; 3]) -> Result<f64> {
    let v = r.inverse() * nalgebra::Vector3::from(w);
    let (t, p) = direction_angles([v.x, v.y, v.z])?;
    Ok(sh_real(l, t, p)?[crate::sh::lm_index(l, 0)])
}

/// The rotations `R_l^m` of a direction set, flat order `(l, m)`, with twists `twists`.
fn rotations(dirs: &DirectionSet, twists: &[f64]) -> Result<Vec<nalgebra::Rotation3<f64>>> {
    (0..num_coeffs(dirs.lmax()))
        .map(|j| {
            let (l, m) = crate::sh::lm_of_index(j);
            rotation_to(
                dirs.distinct()[dirs.index(l, m)],
                std::f64::consts::PI * twists[j],
            )
        })
        .collect()
}

/// ISD (8): `phi_l^m(w) = y_l^0((R_l^m)^-1 w)` for any rotation with `R_l^m z = z_l^m`.
fn rotated_zonal() -> Result<f64> {
    let lmax = 8;
    let n = num_coeffs(lmax);
    let mut worst = 0.0f64;
    for (pattern, sharing) in [
        (Pattern::Fibonacci, Sharing::PerBand),
        (Pattern::Halton, Sharing::Shared),
    ] {
        let isd = basis(Profile::Zonal, pattern, sharing, lmax)?;
        let rots = rotations(isd.directions(), &pseudo_random(n, 51))?;
        let (mut err, mut scale) = (0.0f64, 0.0f64);
        for w in random_directions(64, 52) {
            for (j, r) in rots.iter().enumerate() {
                let mut unit = vec![0.0; n];
                unit[j] = 1.0;
                let want = rotated_y_l0(crate::sh::lm_of_index(j).0, r, w)?;
                err = err.max((isd.evaluate(&unit, w)? - want).abs());
                scale = scale.max(want.abs());
            }
        }
        worst = worst.max(err / scale);
    }
    Ok(worst)
}

/// ISD (10): `(M_l)_ij = pi_l y_l^i(z_l^j)` are the SH coefficients of `phi_l^j`, and the
/// weights solve `c = M Lambda`.
fn rzh_matrix() -> Result<f64> {
    let lmax = 8;
    let n = num_coeffs(lmax);
    let (grid, y) = super::sh::real_sh_on_grid(lmax, lmax)?;
    let mut worst = 0.0f64;
    for (pattern, sharing) in [
        (Pattern::Fibonacci, Sharing::PerBand),
        (Pattern::Fibonacci, Sharing::Shared),
        (Pattern::Halton, Sharing::PerBand),
    ] {
        let isd = basis(Profile::Zonal, pattern, sharing, lmax)?;
        let rots = rotations(isd.directions(), &pseudo_random(n, 53))?;
        // m_ref[i][j] = sum_a w_a y_i(w_a) phi_j(w_a).
        let mut m_ref = nalgebra::DMatrix::<f64>::zeros(n, n);
        for a in 0..grid.len() {
            let w = grid.direction(a)?;
            let wt = grid.point_weight(a);
            for (j, r) in rots.iter().enumerate() {
                let phi = wt * rotated_y_l0(crate::sh::lm_of_index(j).0, r, w)?;
                for i in 0..n {
                    m_ref[(i, j)] += y[a * n + i] * phi;
                }
            }
        }
        let m = isd.matrix();
        worst = worst.max((m - &m_ref).amax() / m_ref.amax());
        // ISD (10): the weights solve c = M Lambda.
        let c = pseudo_random(n, 54);
        let lambda = nalgebra::DVector::from_vec(isd.weights(&c)?);
        let c = nalgebra::DVector::from_vec(c);
        worst = worst.max((&m_ref * &lambda - &c).amax() / (c.norm() * lambda.norm()));
    }
    Ok(worst)
}

/// `e^{-a} i_n(a)` for `n = 0..=nmax`, `i_n` the modified spherical Bessel function of the
/// first kind, by its power series `i_n(a) = a^n / (2n+1)!! sum_k (a^2/2)^k /
/// (k! (2n+3)(2n+5)...(2n+2k+1))`: all terms positive (no cancellation), the prefactor
/// `e^{-a} a^n / (2n+1)!!` a product of `n + 1` rounded factors (no logarithms, whose
/// absolute rounding would become relative). Against mpmath (50 digits) for
/// `a = l^2 <= 144`, `n <= 12`: relative error 1.6e-15 at most.
fn scaled_bessel_i(nmax: usize, a: f64) -> Vec<f64> {
    (0..=nmax)
        .map(|n| {
            if a == 0.0 {
                return if n == 0 { 1.0 } else { 0.0 };
            }
            let mut lead = (-a).exp();
            for k in 0..n {
                lead *= a / (2 * k + 3) as f64;
            }
            let (mut term, mut sum, mut k) = (1.0f64, 1.0f64, 0usize);
            loop {
                k += 1;
                term *= a * a / 2.0 / (k as f64 * (2 * n + 2 * k + 1) as f64);
                sum += term;
                if term < 1e-18 * sum && k as f64 > a {
                    break;
                }
            }
            lead * sum
        })
        .collect()
}

/// `beta_ll'` of the Gaussian profile of ISD (19) in closed form:
/// `2 pi sqrt((2l'+1)/(4 pi)) int e^{-(1-t) a} P_l'(t) dt = sqrt(4 pi (2l'+1)) e^{-a} i_l'(a)`,
/// `a = l^2` (`proofs/isd.md` §6).
fn gaussian_beta(lmax: usize) -> nalgebra::DMatrix<f64> {
    let mut beta = nalgebra::DMatrix::zeros(lmax + 1, lmax + 1);
    for l in 0..=lmax {
        let i = scaled_bessel_i(lmax, (l * l) as f64);
        for lp in 0..=lmax {
            beta[(l, lp)] = (4.0 * std::f64::consts::PI * (2 * lp + 1) as f64).sqrt() * i[lp];
        }
    }
    beta
}

/// ISD (19): the Gaussian profile through its ZH coefficients.
fn gaussian_profile() -> Result<f64> {
    let lmax = 12;
    let got = Profile::Gaussian.beta(lmax)?;
    let want = gaussian_beta(lmax);
    let mut worst = 0.0f64;
    for l in 0..=lmax {
        let scale = want.row(l).amax();
        worst = worst.max((got.row(l) - want.row(l)).amax() / scale);
    }
    Ok(worst)
}

/// The eigenvalues of a symmetric matrix by the cyclic Jacobi method.
fn jacobi_eigenvalues(mut a: nalgebra::DMatrix<f64>) -> Vec<f64> {
    let n = a.nrows();
    for _sweep in 0..100 {
        let off: f64 = (0..n)
            .flat_map(|i| (0..n).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[(i, j)] * a[(i, j)])
            .sum();
        let diag: f64 = (0..n).map(|i| a[(i, i)] * a[(i, i)]).sum();
        if off <= 1e-34 * diag {
            break;
        }
        for p in 0..n {
            for q in p + 1..n {
                if a[(p, q)] == 0.0 {
                    continue;
                }
                let theta = (a[(q, q)] - a[(p, p)]) / (2.0 * a[(p, q)]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..n {
                    let (akp, akq) = (a[(k, p)], a[(k, q)]);
                    a[(k, p)] = c * akp - s * akq;
                    a[(k, q)] = s * akp + c * akq;
                }
                for k in 0..n {
                    let (apk, aqk) = (a[(p, k)], a[(q, k)]);
                    a[(p, k)] = c * apk - s * aqk;
                    a[(q, k)] = s * apk + c * aqk;
                }
            }
        }
    }
    (0..n).map(|i| a[(i, i)]).collect()
}

/// `P_l(t)` for `l <= lmax`.
fn legendre(lmax: usize, t: f64) -> Vec<f64> {
    let mut p = vec![0.0; lmax + 1];
    crate::sh::recursion::legendre::legendre_polynomials(t, &mut p, None);
    p
}

/// `sqrt(cond(M^T M))` with `(M^T M)_jk = sum_l' beta_{l_j l'} beta_{l_k l'} P_l'(z_j . z_k)`
/// (`proofs/isd.md` §7): no SH evaluation.
fn gram_condition(beta: &nalgebra::DMatrix<f64>, dirs: &DirectionSet) -> f64 {
    let lmax = dirs.lmax();
    let n = num_coeffs(lmax);
    let z = |j: usize| {
        let (l, m) = crate::sh::lm_of_index(j);
        (l, dirs.distinct()[dirs.index(l, m)])
    };
    let g = nalgebra::DMatrix::from_fn(n, n, |j, k| {
        let ((lj, a), (lk, b)) = (z(j), z(k));
        let t = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]).clamp(-1.0, 1.0);
        let p = legendre(lmax, t);
        (0..=lmax)
            .map(|lp| beta[(lj, lp)] * beta[(lk, lp)] * p[lp])
            .sum()
    });
    let e = jacobi_eigenvalues(g);
    let (lo, hi) = e.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &x| {
        (lo.min(x), hi.max(x))
    });
    (hi / lo).sqrt()
}

/// ISD Fig. 13 (Sec. 7.2): condition numbers of `M`, and the effect of sharing directions.
fn conditioning() -> Result<f64> {
    use crate::isd::decomposition::{condition_number, transfer_matrix};
    let mut worst = 0.0f64;
    let betas =
        |profile: Profile, lmax: usize| -> Result<nalgebra::DMatrix<f64>> {
            Ok(match profile {
                Profile::Zonal => nalgebra::DMatrix::identity(lmax + 1, lmax + 1),
                Profile::Legendre => nalgebra::DMatrix::from_fn(lmax + 1, lmax + 1, |l, lp| {
                    if l == lp {
                        pi_l(l)
                    } else {
                        0.0
                    }
                }),
                _ => gaussian_beta(lmax),
            })
        };
    for profile in [Profile::Zonal, Profile::Legendre, Profile::Gaussian] {
        for pattern in [Pattern::Fibonacci, Pattern::Halton] {
            for sharing in [Sharing::PerBand, Sharing::Shared] {
                for lmax in [1, 2, 4, 6, 8] {
                    let dirs = DirectionSet::from_pattern(pattern, sharing, lmax)?;
                    let got = condition_number(&transfer_matrix(&profile.beta(lmax)?, &dirs)?);
                    if got > 2e4 {
                        continue;
                    }
                    let want = gram_condition(&betas(profile, lmax)?, &dirs);
                    worst = worst.max((got - want).abs() / want);
                }
            }
        }
    }
    // ISD Sec. 7.2 at L = 8: sharing ruins the local profiles, not the global ones.
    for pattern in [Pattern::Fibonacci, Pattern::Halton] {
        for profile in Profile::ALL {
            let cond = |sharing| -> Result<f64> {
                let dirs = DirectionSet::from_pattern(pattern, sharing, 8)?;
                Ok(condition_number(&transfer_matrix(
                    &profile.beta(8)?,
                    &dirs,
                )?))
            };
            let ratio = (cond(Sharing::Shared)? / cond(Sharing::PerBand)?).log10();
            let global = matches!(profile, Profile::Zonal | Profile::Legendre);
            let holds = if global {
                ratio.abs() < 1.5
            } else {
                ratio >= 3.0
            };
            if !holds {
                worst = worst.max(1.0);
            }
        }
    }
    Ok(worst)
}

/// `max |a_i - b_i| / scale`.
fn max_scaled_difference(a: &[f64], b: &[f64], scale: f64) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs() / scale))
}

/// Euclidean norm.
fn norm(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// A basis on a pattern's directions.
fn basis(profile: Profile, pattern: Pattern, sharing: Sharing, lmax: usize) -> Result<Isd> {
    Isd::new(profile, DirectionSet::from_pattern(pattern, sharing, lmax)?)
}

/// `|ISD - SH| / (|c| |f|)` of the filtered signal at the rotations given by rotation
/// vectors, for a random kernel and signal of seed `seed`.
pub fn filter_vs_wigner_error(isd: &Isd, rotvecs: &[[f64; 3]], seed: u64) -> Result<f64> {
    let n = num_coeffs(isd.lmax());
    let c = pseudo_random(n, seed);
    let f = pseudo_random(n, seed + 1);
    let lambda = isd.weights(&c)?;
    let rotations = rotvecs
        .iter()
        .map(|v| rotation_from_rotvec(*v))
        .collect::<Result<Vec<_>>>()?;
    let got = PreConvolved::new(isd, &f)?.filter(isd, &lambda, &rotations)?;
    let want = sh_rotate_dot(&c, &f, &rotations)?;
    Ok(max_scaled_difference(&got, &want, norm(&c) * norm(&f)))
}

fn rotvecs(n: usize, seed: u64) -> Vec<[f64; 3]> {
    let r = pseudo_random(3 * n, seed);
    (0..n)
        .map(|k| [3.0 * r[3 * k], 3.0 * r[3 * k + 1], 3.0 * r[3 * k + 2]])
        .collect()
}

/// Direction sets whose RZH weights stay small at `L = 16` (largest `|lambda|` about
/// 160 for `|c_i| <= 1`; the reconstruction error grows with it, `docs/isd.md`).
const WELL_CONDITIONED: [(Pattern, Sharing); 2] = [
    (Pattern::Halton, Sharing::PerBand),
    (Pattern::Fibonacci, Sharing::Shared),
];

fn reconstruction() -> Result<f64> {
    let lmax = 16;
    let mut worst = 0.0f64;
    for profile in [Profile::Zonal, Profile::Legendre] {
        for (pattern, sharing) in WELL_CONDITIONED {
            let isd = basis(profile, pattern, sharing, lmax)?;
            let c = pseudo_random(num_coeffs(lmax), 7);
            let lambda = isd.weights(&c)?;
            let (mut err, mut scale) = (0.0f64, 0.0f64);
            for w in random_directions(500, 8) {
                let (t, p) = direction_angles(w)?;
                let sh: f64 = sh_real(lmax, t, p)?
                    .iter()
                    .zip(&c)
                    .map(|(a, b)| a * b)
                    .sum();
                err = err.max((isd.evaluate(&lambda, w)? - sh).abs());
                scale = scale.max(sh.abs());
            }
            worst = worst.max(err / scale);
        }
    }
    Ok(worst)
}

fn filter_vs_wigner() -> Result<f64> {
    let mut worst = 0.0f64;
    for profile in Profile::ALL {
        let isd = basis(profile, Pattern::Fibonacci, Sharing::PerBand, 8)?;
        worst = worst.max(filter_vs_wigner_error(&isd, &rotvecs(8, 3), 11)?);
    }
    for profile in [Profile::Zonal, Profile::Legendre] {
        let isd = basis(profile, Pattern::Fibonacci, Sharing::Shared, 16)?;
        worst = worst.max(filter_vs_wigner_error(&isd, &rotvecs(8, 4), 12)?);
    }
    Ok(worst)
}

/// Band of the fine grid for non-band-limited mother functions at `L = 6`: the ZH
/// coefficients of the smooth ones beyond it are below 1e-16 of the largest (Gaussian
/// `exp(-36 (1 - t))`: about `18^96 / 96!`, `e^-65`).
const FINE_BAND: usize = 96;

/// The profiles whose angular-domain integrals the fine grid computes to rounding: not
/// Phong, whose kink at `t = 0` makes its ZH coefficients decay only like a power of
/// `l'` (its `M` and pre-convolution are checked by `isd.filter_vs_wigner`).
const SMOOTH: [Profile; 4] = [
    Profile::Zonal,
    Profile::Legendre,
    Profile::Gaussian,
    Profile::GaussLegendre,
];

fn transfer_matrix() -> Result<f64> {
    let lmax = 6;
    let t = ShTransform::new(FINE_BAND)?;
    let grid = t.grid();
    let mut worst = 0.0f64;
    for profile in [Profile::Gaussian, Profile::GaussLegendre] {
        let isd = basis(profile, Pattern::Fibonacci, Sharing::PerBand, lmax)?;
        let c = pseudo_random(num_coeffs(lmax), 21);
        let lambda = isd.weights(&c)?;
        let values = (0..grid.len())
            .map(|i| isd.evaluate(&lambda, grid.direction(i)?))
            .collect::<Result<Vec<_>>>()?;
        let mut proj = vec![0.0; num_coeffs(FINE_BAND)];
        t.analysis_real(&values, &mut proj)?;
        let scale = c.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (a, b) in proj.iter().zip(&c) {
            worst = worst.max((a - b).abs() / scale);
        }
    }
    Ok(worst)
}

fn legendre_beta() -> Result<f64> {
    let lmax = 24;
    let beta = Profile::Legendre.beta(lmax)?;
    let mut worst = 0.0f64;
    for l in 0..=lmax {
        for lp in 0..=lmax {
            let want = if l == lp { pi_l(l) } else { 0.0 };
            worst = worst.max((beta[(l, lp)] - want).abs());
        }
    }
    Ok(worst)
}

fn preconvolution() -> Result<f64> {
    let lmax = 6;
    let (grid, y) = super::sh::real_sh_on_grid(lmax, FINE_BAND)?;
    let points = (0..grid.len())
        .map(|i| grid.direction(i))
        .collect::<Result<Vec<_>>>()?;
    let f = pseudo_random(num_coeffs(lmax), 31);
    let fw: Vec<f64> = y
        .chunks_exact(num_coeffs(lmax))
        .map(|row| row.iter().zip(&f).map(|(a, b)| a * b).sum())
        .collect();
    let mut worst = 0.0f64;
    for profile in SMOOTH {
        let isd = basis(profile, Pattern::Fibonacci, Sharing::PerBand, lmax)?;
        let pre = PreConvolved::new(&isd, &f)?;
        let mut g = vec![0.0; lmax + 1];
        for w in random_directions(20, 32) {
            let got = pre.lookup(w)?;
            let mut want = vec![0.0; lmax + 1];
            for (i, p) in points.iter().enumerate() {
                profile.values(
                    (w[0] * p[0] + w[1] * p[1] + w[2] * p[2]).clamp(-1.0, 1.0),
                    &mut g,
                );
                let wt = grid.point_weight(i) * fw[i];
                for (acc, gl) in want.iter_mut().zip(&g) {
                    *acc += wt * gl;
                }
            }
            for (a, b) in got.iter().zip(&want) {
                worst = worst.max((a - b).abs() / norm(&f));
            }
        }
    }
    Ok(worst)
}

fn light() -> Result<f64> {
    let lmax = 10;
    let lamp = SphericalLight::new([0.3, -0.2, 2.0], 0.7, 1.5)?;
    let x = [0.1, 0.2, -0.1];
    let e = SphericalLights::new(vec![lamp], lmax)?
        .field(x, Order::Values)?
        .coefficients;
    let mut worst = 0.0f64;
    for (profile, sharing) in [
        (Profile::Zonal, Sharing::Shared),
        (Profile::Gaussian, Sharing::PerBand),
    ] {
        let isd = basis(profile, Pattern::Fibonacci, sharing, lmax)?;
        let c = pseudo_random(num_coeffs(lmax), 41);
        let lambda = isd.weights(&c)?;
        let rotations = rotvecs(8, 42)
            .iter()
            .map(|v| rotation_from_rotvec(*v))
            .collect::<Result<Vec<_>>>()?;
        let got = spherical_light(&isd, &lambda, &lamp, x, &rotations)?;
        let want = sh_rotate_dot(&c, &e[..c.len()], &rotations)?;
        worst = worst.max(max_scaled_difference(&got, &want, norm(&c) * norm(&e)));
    }
    Ok(worst)
}
