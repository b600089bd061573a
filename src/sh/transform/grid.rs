//! Exact quadrature on the sphere: Gauss-Legendre nodes in `cos theta` times a uniform
//! grid in `phi`.
//!
//! With `n` rings and `n_phi` meridians the rule integrates exactly every
//! `P(cos theta) e^{i m phi}` with `deg P <= 2n - 1` and `|m| < n_phi`. A product of two
//! functions band-limited to `L` has degree `2L` in `cos theta` (times `sin^{|m|}`, an even
//! polynomial times the `e^{i m phi}` factor pairing) and orders `|m| <= 2L`, so
//! `n = L + 1`, `n_phi = 2L + 1` integrate it exactly: this is what makes analysis
//! (PSH (3)) exact for band-limited inputs. Derivation in `proofs/quadrature.md`.

use crate::error::{Error, Result};
use std::f64::consts::PI;

/// Gauss-Legendre nodes `x_j = cos theta_j` (theta increasing from the north pole) and
/// weights `w_j` (summing to 2), by Newton's method on `P_n(cos theta)` in the variable
/// `theta` (no loss of accuracy near the poles).
#[derive(Clone, Debug)]
pub struct GaussLegendre {
    /// Polar angles `theta_j`, increasing.
    pub theta: Vec<f64>,
    /// `cos theta_j`.
    pub cos_theta: Vec<f64>,
    /// `sin theta_j`.
    pub sin_theta: Vec<f64>,
    /// Weights `w_j`.
    pub weights: Vec<f64>,
}

impl GaussLegendre {
    /// The `n`-point rule (`n >= 1`).
    pub fn new(n: usize) -> Result<Self> {
        if n == 0 {
            return Err(Error::GridTooSmall {
                reason: "a Gauss-Legendre rule needs at least one node".into(),
            });
        }
        let mut theta = vec![0.0; n];
        let mut weights = vec![0.0; n];
        let nf = n as f64;
        for k in 0..n.div_ceil(2) {
            // Tricomi's initial guess (DLMF 18.16.6 asymptotics), then Newton in theta.
            let mut t = PI * (4.0 * k as f64 + 3.0) / (4.0 * nf + 2.0);
            let mut dp = 0.0;
            for _ in 0..100 {
                let (p, dpt) = legendre_p_and_dtheta(n, t);
                dp = dpt;
                let dt = p / dpt;
                t -= dt;
                if dt.abs() < 1e-16 * t.max(1e-300) {
                    let (_, dpt) = legendre_p_and_dtheta(n, t);
                    dp = dpt;
                    break;
                }
            }
            // w = 2 / ((1 - x^2) P_n'(x)^2) = 2 / (dP_n/dtheta)^2.
            let w = 2.0 / (dp * dp);
            theta[k] = t;
            weights[k] = w;
            theta[n - 1 - k] = PI - t;
            weights[n - 1 - k] = w;
        }
        if n % 2 == 1 {
            theta[n / 2] = PI / 2.0;
        }
        let cos_theta = theta.iter().map(|t| t.cos()).collect();
        let sin_theta = theta.iter().map(|t| t.sin()).collect();
        Ok(Self {
            theta,
            cos_theta,
            sin_theta,
            weights,
        })
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.theta.len()
    }

    /// Never empty.
    pub fn is_empty(&self) -> bool {
        false
    }
}

/// `P_n(cos t)` and `d/dt P_n(cos t) = n (cos t P_n - P_{n-1}) / sin t` (DLMF 18.9.17).
///
/// Within `pi/3` of the north pole, Bonnet's recurrence runs in Reinsch's difference form
/// in `u = 1 - cos t = 2 sin^2(t/2)` (`proofs/quadrature.md`, "Nodes near the poles"):
/// `delta_{k+1} = (k delta_k - (2k+1) u P_k) / (k+1)`, `P_{k+1} = P_k + delta_{k+1}`,
/// which keeps what `cos t` rounded to a double would lose (an error `eps / sin t` in the
/// angle of the root). Elsewhere [`crate::sh::recursion::legendre::legendre_polynomials`], whose loss
/// `eps / sin t` is at most `1.2 eps` there.
fn legendre_p_and_dtheta(n: usize, t: f64) -> (f64, f64) {
    if n == 0 {
        return (1.0, 0.0);
    }
    let (s, x) = t.sin_cos();
    if t < PI / 3.0 {
        let h = (0.5 * t).sin();
        let u = 2.0 * h * h;
        let (mut p, mut delta) = (1.0, 0.0);
        for k in 0..n {
            let kf = k as f64;
            delta = (kf * delta - (2.0 * kf + 1.0) * u * p) / (kf + 1.0);
            p += delta;
        }
        // x P_n - P_{n-1} = delta_n - u P_n.
        return (p, n as f64 * (delta - u * p) / s);
    }
    let mut p = vec![0.0; n + 1];
    crate::sh::recursion::legendre::legendre_polynomials(x, &mut p, None);
    // (x^2 - 1) = -sin^2 t, written so to keep its relative accuracy near the poles.
    (p[n], n as f64 * (x * p[n] - p[n - 1]) / s)
}

/// The product grid: Gauss-Legendre rings times `n_phi` equispaced meridians
/// `phi_k = 2 pi k / n_phi`. Points are stored ring-major: index `j * n_phi + k`.
#[derive(Clone, Debug)]
pub struct SphereGrid {
    /// The rings.
    pub rings: GaussLegendre,
    /// Number of meridians.
    pub n_phi: usize,
}

impl SphereGrid {
    /// `n_theta` rings by `n_phi` meridians.
    pub fn new(n_theta: usize, n_phi: usize) -> Result<Self> {
        if n_phi == 0 {
            return Err(Error::GridTooSmall {
                reason: "n_phi must be at least 1".into(),
            });
        }
        Ok(Self {
            rings: GaussLegendre::new(n_theta)?,
            n_phi,
        })
    }

    /// The smallest grid that integrates products of two functions of band limit `lmax`
    /// exactly: `lmax + 1` rings, `2 lmax + 2` meridians (even, for the FFT).
    pub fn for_band_limit(lmax: usize) -> Result<Self> {
        crate::sh::check_lmax(lmax)?;
        Self::new(lmax + 1, 2 * lmax + 2)
    }

    /// Checks that the grid is exact for analysis at band limit `lmax`.
    pub fn check_band_limit(&self, lmax: usize) -> Result<()> {
        if self.rings.len() < lmax + 1 || self.n_phi < 2 * lmax + 1 {
            return Err(Error::GridTooSmall {
                reason: format!(
                    "{} rings x {} meridians cannot resolve band limit {lmax} \
                     (need at least {} x {})",
                    self.rings.len(),
                    self.n_phi,
                    lmax + 1,
                    2 * lmax + 1
                ),
            });
        }
        Ok(())
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.rings.len() * self.n_phi
    }

    /// Never empty.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Longitude of meridian `k`.
    pub fn phi(&self, k: usize) -> f64 {
        2.0 * PI * k as f64 / self.n_phi as f64
    }

    /// Quadrature weight `w_j 2 pi / n_phi` of the points of ring `j` (0 past the last ring).
    pub fn weight(&self, j: usize) -> f64 {
        self.rings
            .weights
            .get(j)
            .map_or(0.0, |w| w * 2.0 * PI / self.n_phi as f64)
    }

    /// Quadrature weight of point `i` (ring-major; 0 past the last point).
    pub fn point_weight(&self, i: usize) -> f64 {
        self.weight(i / self.n_phi.max(1))
    }

    /// `(theta, phi)` of point `i` (ring-major), or an error past the last point.
    pub fn angles(&self, i: usize) -> Result<(f64, f64)> {
        let j = i / self.n_phi.max(1);
        match self.rings.theta.get(j) {
            Some(&t) => Ok((t, self.phi(i % self.n_phi.max(1)))),
            None => Err(Error::invalid(
                "grid point",
                i.to_string(),
                format!("the grid has {} points", self.len()),
            )),
        }
    }

    /// Unit direction of point `i`, or an error past the last point.
    pub fn direction(&self, i: usize) -> Result<[f64; 3]> {
        let (t, p) = self.angles(i)?;
        Ok(crate::geometry::direction(t, p))
    }

    /// Integral of sampled values (ring-major) by the rule.
    pub fn integrate(&self, values: &[f64]) -> Result<f64> {
        crate::error::check_len("grid values", self.len(), values.len())?;
        Ok(values
            .chunks_exact(self.n_phi)
            .enumerate()
            .map(|(j, ring)| self.weight(j) * ring.iter().sum::<f64>())
            .sum())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rule_integrates_polynomials_exactly() {
        for n in [1usize, 2, 5, 16, 101, 1000] {
            let g = GaussLegendre::new(n).unwrap();
            let total: f64 = g.weights.iter().sum();
            assert!((total - 2.0).abs() < 1e-13, "n {n}: {total}");
            // integral of x^(2k) over [-1, 1] is 2/(2k+1), exact for 2k <= 2n - 1.
            for k in [1.min(n - 1), n - 1] {
                let s: f64 = g
                    .cos_theta
                    .iter()
                    .zip(&g.weights)
                    .map(|(x, w)| w * x.powi(2 * k as i32))
                    .sum();
                let expect = 2.0 / (2 * k + 1) as f64;
                assert!((s - expect).abs() < 1e-13, "n {n} k {k}: {s} vs {expect}");
            }
        }
    }

    /// Every node within 4 eps of a root of `P_n(cos theta)`, next to the poles too
    /// (`crate::testing::gauss_legendre_pole_distance`). The former nodes (Newton on `P_n`
    /// of `cos theta` rounded to a double) were 3.8e-14 off at `n = 2048`.
    #[test]
    fn nodes_are_within_four_eps_of_the_roots_at_the_poles() {
        for n in [2048usize, 8192] {
            let e = crate::testing::gauss_legendre_pole_distance(n).unwrap();
            assert!(e < 4.0, "n {n}: {e} eps");
        }
    }

    #[test]
    fn empty_grids_are_errors() {
        assert!(GaussLegendre::new(0).is_err());
        assert!(SphereGrid::new(3, 0).is_err());
        let g = SphereGrid::new(4, 6).unwrap();
        assert!(g.check_band_limit(3).is_err());
        assert!(g.check_band_limit(2).is_ok());
    }
}
