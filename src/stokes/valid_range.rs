//! The physically valid range of Stokes vectors, PSH (70): `s0 >= |(s1, s2, s3)|`, a
//! second-order (Lorentz) cone in `R^4`; and the nearest valid vector, the Euclidean
//! projection onto that cone (`proofs/stokes-valid-range.md`), which PSH Fig. 22 applies
//! to a rendered image: `s0` grows, `|(s1, s2, s3)|` shrinks to it, the direction of
//! polarization (AoLP and the sign of `s3`) is kept.

use super::StokesComponents;
use nalgebra::Vector4;

impl StokesComponents {
    /// Whether PSH (70) holds: `s0 >= sqrt(s1^2 + s2^2 + s3^2)`.
    pub fn is_physical(&self) -> bool {
        self.s0() >= self.polarized_intensity()
    }

    /// `sqrt(s1^2 + s2^2 + s3^2)`, the polarized part's intensity.
    pub fn polarized_intensity(&self) -> f64 {
        self.s1().hypot(self.s2()).hypot(self.s3())
    }

    /// The nearest (Euclidean) Stokes vector satisfying PSH (70): itself when valid; zero
    /// when `s0 <= -p` (`p = |(s1, s2, s3)|`); else `a (1, v / p)` with
    /// `a = (s0 + p) / 2`, fully polarized in the same direction
    /// (`proofs/stokes-valid-range.md`). The result satisfies [`Self::is_physical`]
    /// exactly (its `s0` rounded up by at most an ulp).
    pub fn nearest_physical(&self) -> StokesComponents {
        let (s0, p) = (self.s0(), self.polarized_intensity());
        if s0 >= p {
            *self
        } else if s0 <= -p {
            StokesComponents::zero()
        } else {
            // Halves first: no overflow near the f64 limit.
            let a = 0.5 * s0 + 0.5 * p;
            let k = a / p;
            let v = [self.s1() * k, self.s2() * k, self.s3() * k];
            // On the cone's boundary to rounding: s0 raised by the ulp that |v| may exceed
            // a by, so that `is_physical` holds exactly.
            let s0 = a.max(v[0].hypot(v[1]).hypot(v[2]));
            Self::from_vector_unchecked(Vector4::new(s0, v[0], v[1], v[2]))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn valid_vectors_stay_and_invalid_ones_meet_the_cone() {
        let ok = StokesComponents::new([1.0, 0.3, -0.4, 0.5]).unwrap();
        assert_eq!(ok.nearest_physical(), ok);
        let neg = StokesComponents::new([-2.0, 0.3, -0.4, 1.2]).unwrap();
        assert_eq!(neg.nearest_physical(), StokesComponents::zero());
        // p = 5, s0 = 1: a = 3, (3, 3 * 3/5, 3 * 4/5, 0); AoLP kept, DoP 1.
        let over = StokesComponents::new([1.0, 3.0, 4.0, 0.0]).unwrap();
        let q = over.nearest_physical();
        assert!(q.approx_eq(&StokesComponents::new([3.0, 1.8, 2.4, 0.0]).unwrap(), 1e-15));
        assert!((q.degree_of_polarization().unwrap() - 1.0).abs() < 1e-15);
        let (a, b) = (
            q.angle_of_linear_polarization().unwrap(),
            over.angle_of_linear_polarization().unwrap(),
        );
        assert!((a - b).abs() < 1e-15, "{a} {b}");
    }
}
