//! Checks of the polarized spherical convolution theorem (`psh::polarized::convolution`).

use super::Check;
use crate::error::Result;
use crate::polarized::{
    apply_angular, convolve_angular, kernel_coefficients, project_operator, project_to_convolution,
    rotation_average, Codomain, ConvolutionKernel, KernelCoefficients, PshMatrix, PshTransform,
    SpinBlock22,
};
use crate::sh::evaluation::zonal::zonal_coefficients;
use crate::testing::{random_kernel, random_psh, random_psh_matrix};

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
        Check {
            id: "conv.kernel_frames",
            source: "PSH (62)",
            description: "a kernel with 16 distinct non-zero entries as a Mueller transform field: K(z_g, w(theta, phi)) read between the theta-phi frames F(0, phi) -> F(theta, phi) written out here, and K(R z_g, R w) read between R F(0, phi) -> R F(theta, phi) for random rotations R (PSH (58)), vs k(theta), 400 random (theta, phi) with theta in [0.02, pi - 0.02] (max |difference| relative to max |k|, times sin theta)",
            // The great circle's normal w_i x w_o / sin theta carries eps / sin theta into
            // the frames (hence the weight sin theta), the slope |k'| <= 2.5 the rounding
            // of theta into k; two rotators on O(1) entries: measured 1.5e-15, tolerance
            // 45 ulps.
            tolerance: 1e-14,
            proof: Some("proofs/convolution.md"),
            run: kernel_frames,
        },
        Check {
            id: "conv.rotation_average",
            source: "PSH Fig. 17",
            description: "the rotation average (Euler grid of resolution n = L + 1, exact for band L) of a polarized plastic's coefficient matrix (L = 3) vs its orthogonal projection onto the convolutions (the Haar average of an orthogonal representation is that projection), vs the Schur closed form delta_ll' delta_mm' tr(M^l_pq)/(2l + 1) of its spin-0 blocks, and its own distance to the convolutions (relative to the largest entry); the residual must fall from n = 1 to n = L + 1 (error 1 if not)",
            // Sums of 2 n^3 = 128 rotated matrices, each O(lmax^5) rounded products;
            // measured 9.3e-16, tolerance 45 ulps. (The residuals at n = 1, 2, 3, 4 are
            // 0.74, 0.22, 0.046, 9.3e-16: Fig. 17(b)'s convergence, exact at n = L + 1.)
            tolerance: 1e-14,
            proof: Some("proofs/convolution.md"),
            run: rotation_average_check,
        },
        Check {
            id: "conv.windowed_band_limits",
            source: "PSH (35)-(37), (63), (69); Sloan 2008 (windowing)",
            description: "PshVector::windowed (Hann and Lanczos, L = 6, random full field) vs the angular-domain convolution PSH (63) with the kernel diag(K0, K2, K2, K0), K_s(theta) = sum_l w_l (2l+1)/(4 pi) d^l_ss(theta) written out here (Legendre and Jacobi closed forms), projected on the exact grid; and the window commuting with 3 random rotations and with two convolutions (linear zenith, a random 16-entry kernel), L = 12, 3 channels (relative)",
            // The angular route is conv.angular_vs_frequency's (48 polar nodes about each
            // grid point, the kernels polynomials of degree 6 in cos theta), the
            // commutations exact up to the rotations' and kernels' rounding: measured
            // 1.1e-15, tolerance 1e-13 (sums of
            // O(L^2) rounded terms).
            tolerance: 1e-13,
            proof: Some("proofs/windowed-band-limits.md"),
            run: windowed_band_limits,
        },
    ]
}

/// The theta-phi frame at `(theta, phi)` written out (`proofs/stokes-frames.md` §10):
/// `x` along increasing theta, `y` along increasing phi, `z` the direction; at
/// `theta = 0` its limit along the meridian `phi`.
fn theta_phi_frame(theta: f64, phi: f64) -> Result<crate::geometry::frame::Frame> {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    crate::geometry::frame::Frame::new(
        [ct * cp, ct * sp, -st],
        [-sp, cp, 0.0],
        [st * cp, st * sp, ct],
    )
}

/// A kernel whose 16 entries are distinct smooth functions of theta, with slopes
/// `|k'| <= 2.5` (the slope carries the rounding of theta into the entries).
fn test_kernel(t: f64) -> crate::polarized::KernelValue {
    std::array::from_fn(|p| {
        std::array::from_fn(|q| {
            0.2 + 0.1 * p as f64 - 0.07 * q as f64
                + (0.25 * (p + 2 * q + 1) as f64 * t + q as f64).cos()
        })
    })
}

/// PSH (62): `k(theta) = [K(z_g, w(theta, phi))]^{F(0, phi) -> F(theta, phi)}` for every
/// `phi`, and the same between rotated frames for the rotated pair (PSH (58)).
fn kernel_frames() -> Result<f64> {
    use crate::stokes::MuellerField;
    let kernel = ConvolutionKernel::from_fn(test_kernel);
    let rot = |v: &nalgebra::Vector3<f64>, r: &nalgebra::Rotation3<f64>| {
        let u = r * v;
        [u.x, u.y, u.z]
    };
    let mut worst = 0.0f64;
    for k in 0..400 {
        let r = crate::random::pseudo_random(5, 1300 + k);
        // theta away from the poles, where the great circle is not unique.
        let theta = 0.02 + (std::f64::consts::PI - 0.04) * 0.5 * (r[0] + 1.0);
        let phi = std::f64::consts::PI * r[1];
        let want = nalgebra::Matrix4::from_fn(|p, q| test_kernel(theta)[p][q]);
        let (f0, f1) = (theta_phi_frame(0.0, phi)?, theta_phi_frame(theta, phi)?);
        let got = kernel
            .transform(f0.direction(), f1.direction())?
            .matrix_in(&f0, &f1)?
            .matrix();
        // The kernel's frames come from the normal of the great circle, w_i x w_o / sin theta,
        // whose rounding grows like eps / sin theta: the error is weighed by sin theta.
        let weight = theta.sin() / want.amax();
        worst = worst.max((got - want).amax() * weight);
        let q = crate::geometry::rotation_from_rotvec([3.0 * r[2], 3.0 * r[3], 3.0 * r[4]])?;
        let (g0, g1) = (f0.rotated(&q)?, f1.rotated(&q)?);
        let got = kernel
            .transform(rot(&f0.z(), &q), rot(&f1.z(), &q))?
            .matrix_in(&g0, &g1)?
            .matrix();
        worst = worst.max((got - want).amax() * weight);
    }
    Ok(worst)
}

/// PSH Fig. 17: the rotation average of a pBRDF's matrix is a convolution.
fn rotation_average_check() -> Result<f64> {
    use crate::sh::{lm_index, num_coeffs};
    let lmax = 3;
    let plastic = crate::optics::PolarizedPlastic::new(0.3, 1.5, 0.5)?;
    let m = project_operator(&plastic, lmax, 6, SpinBlock22::ComplexPair)?;
    let scale = max_abs(m.data());
    let avg = rotation_average(&m, lmax + 1)?;
    // The orthogonal projection onto the convolutions (16 real parameters per band).
    let projected = project_to_convolution(&m)?.0.to_matrix()?;
    let mut worst = max_diff(avg.data(), projected.data()) / scale;
    // Schur: the spin-0 blocks of the average are tr(M^l_pq)/(2l + 1) times the identity.
    let n = num_coeffs(lmax);
    let schur = |jo: usize, ji: usize, po: usize, pi: usize| -> f64 {
        if jo != ji {
            return 0.0;
        }
        let l = crate::sh::lm_of_index(jo).0;
        let tr: f64 = (-(l as i64)..=l as i64)
            .map(|mm| m.get(lm_index(l, mm), lm_index(l, mm), po, pi))
            .sum();
        tr / (2 * l + 1) as f64
    };
    for jo in 0..n {
        for ji in 0..n {
            for po in [0, 3] {
                for pi in [0, 3] {
                    let d = (avg.get(jo, ji, po, pi) - schur(jo, ji, po, pi)).abs();
                    worst = worst.max(d / scale);
                }
            }
        }
    }
    // Fig. 17(b): the distance to the convolutions falls with the resolution.
    let residual = |a: &PshMatrix| -> Result<f64> { Ok(project_to_convolution(a)?.1) };
    let coarse = residual(&rotation_average(&m, 1)?)?;
    let exact = residual(&avg)?;
    worst = worst.max(exact);
    if coarse <= exact {
        worst = worst.max(1.0);
    }
    Ok(worst)
}

/// `conv.windowed_band_limits` (`proofs/windowed-band-limits.md`).
fn windowed_band_limits() -> Result<f64> {
    use crate::sh::Window;
    let mut worst = 0.0f64;
    // A window is the convolution with diag(K0, K2, K2, K0).
    let lmax = 6;
    let f = random_psh(lmax, Codomain::Full, 1, 271)?;
    let t = PshTransform::new(lmax)?;
    let g = t.grid();
    let points = (0..g.len())
        .map(|i| g.direction(i))
        .collect::<Result<Vec<_>>>()?;
    for window in [Window::Hann, Window::Lanczos] {
        let w = window.factors(lmax);
        let kernel = ConvolutionKernel::from_fn(move |theta| {
            let (k0, k2) = window_kernels(&w, theta);
            let mut k = [[0.0; 4]; 4];
            (k[0][0], k[1][1], k[2][2], k[3][3]) = (k0, k2, k2, k0);
            k
        });
        let angular = t.project(
            &convolve_angular(&kernel, &f, 0, &points, 48)?,
            Codomain::Full,
        )?;
        let windowed = f.windowed(window);
        worst = worst.max(max_diff(angular.data(), windowed.data()) / max_abs(windowed.data()));
    }
    // It commutes with rotations and convolutions.
    let lmax = 12;
    let f = random_psh(lmax, Codomain::Full, 3, 272)?;
    let scale = max_abs(f.data());
    let r = crate::random::pseudo_random(9, 273);
    let linear = kernel_coefficients(&ConvolutionKernel::linear_zenith(), lmax)?;
    let random = random_kernel(lmax, 274)?;
    for window in [Window::Hann, Window::Lanczos] {
        for v in r.chunks_exact(3) {
            let rot = nalgebra::Rotation3::from_scaled_axis(nalgebra::Vector3::new(
                3.0 * v[0],
                3.0 * v[1],
                3.0 * v[2],
            ));
            let a = f.rotated(&rot)?.windowed(window);
            let b = f.windowed(window).rotated(&rot)?;
            worst = worst.max(max_diff(a.data(), b.data()) / scale);
        }
        for k in [&linear, &random] {
            let a = k.convolve(&f)?.windowed(window);
            let b = k.convolve(&f.windowed(window))?;
            worst = worst.max(max_diff(a.data(), b.data()) / max_abs(a.data()));
        }
    }
    Ok(worst)
}

/// `K_0(theta) = sum_l w_l (2l+1)/(4 pi) P_l(cos theta)` and `K_2(theta) = sum_{l >= 2}
/// w_l (2l+1)/(4 pi) d^l_22(theta)` with `d^l_22 = cos^4(theta/2) P^(0,4)_{l-2}(cos theta)`
/// (Edmonds (4.1.23) in Jacobi form), the Jacobi polynomials by DLMF 18.9.1.
fn window_kernels(w: &[f64], theta: f64) -> (f64, f64) {
    let x = theta.cos();
    let mut p = vec![0.0; w.len()];
    crate::sh::legendre_polynomials(x, &mut p, None);
    let k0 = w
        .iter()
        .zip(&p)
        .enumerate()
        .map(|(l, (wl, pl))| wl * (2 * l + 1) as f64 * pl)
        .sum::<f64>();
    // P^(0,4)_n: (a, b) = (0, 4).
    let b = 4.0;
    let (mut prev, mut cur) = (0.0, 1.0);
    let c4 = (0.5 * theta).cos().powi(4);
    let mut k2 = 0.0;
    for (l, wl) in w.iter().enumerate().skip(2) {
        let n = (l - 2) as f64;
        if l > 2 {
            let next = if l == 3 {
                1.0 + (b + 2.0) * (x - 1.0) / 2.0
            } else {
                let s = 2.0 * n + b;
                ((s - 1.0) * (s * (s - 2.0) * x - b * b) * cur
                    - 2.0 * (n - 1.0) * (n + b - 1.0) * s * prev)
                    / (2.0 * n * (n + b) * (s - 2.0))
            };
            (prev, cur) = (cur, next);
        }
        k2 += wl * (2 * l + 1) as f64 * c4 * cur;
    }
    let four_pi = 4.0 * std::f64::consts::PI;
    (k0 / four_pi, k2 / four_pi)
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
