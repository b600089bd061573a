//! The isotropic GGX (Trowbridge-Reitz) microfacet distribution and its Smith
//! masking-shadowing function (height-correlated or separable), in the local shading frame
//! (normal `+z`).

use crate::error::{Error, Result};
use nalgebra::Vector3;

/// Smallest accepted roughness `alpha` (Mitsuba 3 clamps to the same value): below it
/// `alpha^2` approaches the range where `D` at the normal, `1/(pi alpha^2)`, loses its
/// meaning as a finite lobe.
pub const MIN_ROUGHNESS: f64 = 1e-4;

/// Largest accepted roughness `alpha` (`D` at grazing microfacets is `alpha^2/pi`).
pub const MAX_ROUGHNESS: f64 = 1e4;

/// The form of Smith's masking-shadowing function `G2` built from `Lambda` (Heitz 2014,
/// "Understanding the masking-shadowing function in microfacet-based BRDFs", JCGT 3(2),
/// Sec. 6): both agree with `G1` when one direction is the normal, and differ at grazing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Masking {
    /// `G2 = 1/(1 + Lambda(w_i) + Lambda(w_o))` (Heitz 2014 (99)): a point hidden from one
    /// direction is likelier hidden from the other (psh's default).
    #[default]
    HeightCorrelated,
    /// `G2 = G1(w_i) G1(w_o)`, `G1 = 1/(1 + Lambda)` (Heitz 2014 (98); Walter et al. 2007
    /// (23)): masking and shadowing independent, as Mitsuba 3's microfacet BSDFs.
    Separable,
}

crate::named_enum!(Masking, "masking", {
    HeightCorrelated => "height-correlated",
    Separable => "separable",
});

/// The isotropic GGX distribution of microfacet normals with roughness `alpha`
/// (Walter et al. 2007, "Microfacet models for refraction through rough surfaces", (33)),
/// with a form of Smith's masking-shadowing function ([`Masking`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    alpha: f64,
    masking: Masking,
}

impl Ggx {
    /// GGX with roughness `alpha` in `[MIN_ROUGHNESS, MAX_ROUGHNESS]`. Error
    /// ([`Error::InvalidArgument`] naming the value): NaN, infinite, negative or out of
    /// that range.
    pub fn new(alpha: f64) -> Result<Self> {
        if !(MIN_ROUGHNESS..=MAX_ROUGHNESS).contains(&alpha) {
            return Err(Error::invalid(
                "roughness alpha",
                format!("{alpha}"),
                format!("must be in [{MIN_ROUGHNESS:e}, {MAX_ROUGHNESS:e}]"),
            ));
        }
        Ok(Self {
            alpha,
            masking: Masking::default(),
        })
    }

    /// This distribution with the masking-shadowing form `masking`.
    pub fn with_masking(self, masking: Masking) -> Self {
        Self { masking, ..self }
    }

    /// The roughness `alpha`.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// The masking-shadowing form.
    pub fn masking(&self) -> Masking {
        self.masking
    }

    /// The distribution of normals `D(h)` for a unit `h` (Walter et al. 2007 (33)):
    /// `D = alpha^2 / (pi cos^4 theta_h (alpha^2 + tan^2 theta_h)^2)`
    /// `  = alpha^2 / (pi (alpha^2 h_z^2 + h_x^2 + h_y^2)^2)` for `h_z > 0`, `0` otherwise.
    /// Normalized: `int D(h) cos theta_h dh = 1`.
    pub fn d(&self, h: &Vector3<f64>) -> f64 {
        if h[2] <= 0.0 {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        let t = a2 * h[2] * h[2] + h[0] * h[0] + h[1] * h[1];
        a2 / (std::f64::consts::PI * t * t)
    }

    /// `L(w) = sqrt(cos^2 theta + alpha^2 sin^2 theta)` for a unit `w`: Smith's
    /// `Lambda(w) = (L(w)/cos theta - 1)/2` for GGX (Walter et al. 2007 (34) written as
    /// `G1 = 1/(1 + Lambda)`; Heitz 2014, "Understanding the masking-shadowing function
    /// in microfacet-based BRDFs", JCGT 3(2), the GGX `Lambda`).
    pub fn smith_l(&self, w: &Vector3<f64>) -> f64 {
        let sin2 = w[0] * w[0] + w[1] * w[1];
        (w[2] * w[2] + self.alpha * self.alpha * sin2).sqrt()
    }

    /// Smith's masking-shadowing function `G2(w_i, w_o)` in the form [`Self::masking`], for
    /// `w_i`, `w_o` in the upper hemisphere and microfacets facing both (always true for the
    /// half vector of two upper-hemisphere directions); `0` if either is at or below the
    /// horizon. Symmetric in its arguments. `G2 = 4 c_i c_o` [`Self::g2_over_4co`]` / c_i`.
    pub fn g2(&self, wi: &Vector3<f64>, wo: &Vector3<f64>) -> f64 {
        if wi[2] <= 0.0 || wo[2] <= 0.0 {
            return 0.0;
        }
        4.0 * wo[2] * self.g2_over_4co(wi, wo)
    }

    /// `G2(w_i, w_o) / (4 cos theta_o)`, the factor of `F D` in the cosine-weighted
    /// microfacet pBRDF `P = f cos theta_i = F D G2 / (4 cos theta_o)`, written with
    /// `L` ([`Self::smith_l`]) so that it stays finite at grazing `w_o` (since
    /// `1 + Lambda = (L/c + 1)/2`):
    ///
    /// ```text
    /// height-correlated:  c_i / (2 (c_o L_i + c_i L_o))    (1 + Lambda_i + Lambda_o = (L_i/c_i + L_o/c_o)/2)
    /// separable:          c_i / ((c_i + L_i)(c_o + L_o))   (G1 = 2 c / (c + L))
    /// ```
    ///
    /// `0` if `w_i` is at or below the horizon or `w_o` below it.
    pub fn g2_over_4co(&self, wi: &Vector3<f64>, wo: &Vector3<f64>) -> f64 {
        let (ci, co) = (wi[2], wo[2]);
        if ci <= 0.0 || co < 0.0 {
            return 0.0;
        }
        let (li, lo) = (self.smith_l(wi), self.smith_l(wo));
        match self.masking {
            Masking::HeightCorrelated => ci / (2.0 * (co * li + ci * lo)),
            Masking::Separable => ci / ((ci + li) * (co + lo)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation() {
        for a in [-0.1, 0.0, f64::NAN, f64::INFINITY, 1e-5, 1e5] {
            let e = Ggx::new(a).unwrap_err().to_string();
            assert!(e.contains("roughness"), "{e}");
        }
        assert!(Ggx::new(0.3).is_ok());
    }

    #[test]
    fn d_is_normalized() {
        // int D(h) cos theta_h dh = 2 pi int_0^1 D(mu) mu dmu, by the midpoint rule in
        // mu^2 (D depends on mu^2 only): substitute t = mu^2, dt = 2 mu dmu.
        for alpha in [0.1, 0.5, 1.0, 2.0] {
            let g = Ggx::new(alpha).unwrap();
            let n = 200_000;
            let mut sum = 0.0;
            for i in 0..n {
                let t = (i as f64 + 0.5) / n as f64;
                let mu = t.sqrt();
                let h = Vector3::new((1.0 - t).sqrt(), 0.0, mu);
                sum += g.d(&h) / n as f64;
            }
            let total = std::f64::consts::PI * sum;
            assert!((total - 1.0).abs() < 1e-4, "alpha {alpha}: {total}");
        }
    }

    #[test]
    fn g2_limits() {
        let g = Ggx::new(0.5).unwrap();
        let n = Vector3::new(0.0, 0.0, 1.0);
        assert!((g.g2(&n, &n) - 1.0).abs() < 1e-15);
        let graze = Vector3::new(1.0, 0.0, 0.0);
        assert_eq!(g.g2(&graze, &n), 0.0);
        let w = Vector3::new(0.6, 0.0, 0.8);
        assert_eq!(g.g2(&w, &n), g.g2(&n, &w));
        // Against 1/(1 + Lambda_i + Lambda_o) with Lambda = (sqrt(1 + a^2 tan^2) - 1)/2.
        let lambda = |c: f64| {
            let t2 = (1.0 - c * c) / (c * c);
            ((1.0 + 0.25 * t2).sqrt() - 1.0) / 2.0
        };
        let expect = 1.0 / (1.0 + lambda(0.8) + lambda(1.0));
        assert!((g.g2(&w, &n) - expect).abs() < 1e-15);
    }

    /// The separable form against `G1(w_i) G1(w_o)` with `G1 = 1/(1 + Lambda)` and
    /// `Lambda = (sqrt(1 + a^2 tan^2) - 1)/2` (Heitz 2014 (98), (86)), written from the
    /// angles; never above the height-correlated form (`1 + a + b <= (1 + a)(1 + b)`), equal
    /// to it when one direction is the normal.
    #[test]
    fn separable_is_the_product_of_g1() {
        let alpha = 0.3;
        let g = Ggx::new(alpha).unwrap().with_masking(Masking::Separable);
        let hc = Ggx::new(alpha).unwrap();
        let lambda = |theta: f64| ((1.0 + (alpha * theta.tan()).powi(2)).sqrt() - 1.0) / 2.0;
        let dir = |theta: f64, phi: f64| {
            Vector3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            )
        };
        for (ti, to) in [(0.2, 1.1), (1.5, 0.4), (1.55, 1.56), (0.0, 0.9)] {
            let (wi, wo) = (dir(ti, 0.3), dir(to, 2.0));
            let expect = 1.0 / ((1.0 + lambda(ti)) * (1.0 + lambda(to)));
            assert!((g.g2(&wi, &wo) - expect).abs() < 1e-14, "{ti} {to}");
            assert!(g.g2(&wi, &wo) <= hc.g2(&wi, &wo) + 1e-15);
            let ratio = g.g2_over_4co(&wi, &wo) * 4.0 * wo[2] / g.g2(&wi, &wo);
            assert!((ratio - 1.0).abs() < 1e-13);
        }
        let n = Vector3::new(0.0, 0.0, 1.0);
        let w = dir(1.2, 0.5);
        assert!((g.g2(&w, &n) - hc.g2(&w, &n)).abs() < 1e-15);
        assert!(Masking::from_name("smith")
            .unwrap_err()
            .to_string()
            .contains("separable"));
        for m in Masking::ALL {
            assert_eq!(Masking::from_name(m.name()).unwrap(), m);
        }
    }
}
