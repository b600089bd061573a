//! Point evaluation of PSH coefficient vectors PSH (30) with the basis tables built once:
//! the real SH PSH (12) by the Legendre recursion and the spin-2 SH PSH (26)-(27) by the
//! Wigner-d recursion of [`crate::swsh::SpinEvaluator`], both `O(lmax^2)` per direction, for
//! hot loops that evaluate many vectors of one band limit (a renderer's vertices).

use super::PshVector;
use crate::error::{Error, Result};
use crate::geometry::direction_angles;
use crate::geometry::frame::{FrameField, ThetaPhiFrameField};
use crate::sh::harmonics::ShEvaluator;
use crate::sh::num_coeffs;
use crate::stokes::{StokesComponents, StokesVector};
use crate::swsh::SpinEvaluator;
use num_complex::Complex64;

/// Evaluates PSH vectors of band limit up to `lmax` at single directions (reuse one per
/// thread: it keeps its basis buffers).
#[derive(Clone, Debug)]
pub struct PshEvaluator {
    scalar: ShEvaluator,
    /// `None` below `lmax = 2` (no spin-2 coefficients).
    spin: Option<SpinEvaluator>,
    yr: Vec<f64>,
    y2: Vec<Complex64>,
}

impl PshEvaluator {
    /// Tables for `l <= lmax`. Error: `lmax` out of the SH range.
    pub fn new(lmax: usize) -> Result<Self> {
        let spin = if lmax >= 2 {
            Some(SpinEvaluator::new(2, lmax)?)
        } else {
            None
        };
        Ok(Self {
            scalar: ShEvaluator::new(lmax)?,
            spin,
            yr: vec![0.0; num_coeffs(lmax)],
            y2: vec![Complex64::default(); num_coeffs(lmax)],
        })
    }

    /// The largest degree.
    pub fn lmax(&self) -> usize {
        self.scalar.lmax()
    }

    /// The real SH PSH (12) and spin-2 SH PSH (26) of all `l <= lmax` at the unit
    /// direction `w` (flat order; the spin-2 values are zero for `l < 2`), whose PSH basis
    /// Stokes vectors PSH (29) are in the theta-phi frame at `w`. Error: `w` not a unit
    /// vector.
    pub fn basis(&mut self, w: [f64; 3]) -> Result<(&[f64], &[Complex64])> {
        self.fill(w, true)?;
        Ok((&self.yr, &self.y2))
    }

    /// Fills the real SH at `w`, and the spin-2 SH when `spin` (zero otherwise).
    fn fill(&mut self, w: [f64; 3], spin: bool) -> Result<()> {
        let (t, p) = direction_angles(w)?;
        self.scalar.real(t, p, &mut self.yr)?;
        match (&self.spin, spin) {
            (Some(s), true) => s.values(t, p, &mut self.y2),
            _ => {
                self.y2.fill(Complex64::default());
                Ok(())
            }
        }
    }

    /// The Stokes vectors of every channel of `v` at the unit direction `w` by PSH (30),
    /// in the theta-phi frame there (PSH (28)). Errors: `v` above this evaluator's band
    /// limit, `w` not a unit vector.
    pub fn evaluate_all(&mut self, v: &PshVector, w: [f64; 3]) -> Result<Vec<StokesVector>> {
        if v.lmax() > self.lmax() {
            return Err(Error::InvalidArgument {
                name: "PSH vector lmax",
                value: v.lmax().to_string(),
                reason: format!("the evaluator's band limit is {}", self.lmax()),
            });
        }
        // Scalar SH needs no spin-2 basis.
        self.fill(w, v.codomain().has_spin2())?;
        let frame = ThetaPhiFrameField::new().frame(w)?;
        let comps = v.codomain().components();
        let np = comps.len();
        // The slot of each Stokes component in a coefficient's entries (absent: none).
        let slot = |p: usize| comps.iter().position(|&q| q == p);
        let (k0, k1, k2, k3) = (slot(0), slot(1), slot(2), slot(3));
        let n = num_coeffs(v.lmax());
        v.data()
            .chunks_exact(n * np)
            .map(|x| {
                let mut s = [0.0; 4];
                for ((xj, &yr), &y2) in x.chunks_exact(np).zip(&self.yr).zip(&self.y2) {
                    let at = |k: Option<usize>| k.map_or(0.0, |k| xj[k]);
                    // f_lm1 2Y_lm + i f_lm2 2Y_lm = s1 + i s2 (PSH (29)-(30)).
                    let (a, b) = (at(k1), at(k2));
                    s[0] += at(k0) * yr;
                    s[1] += a * y2.re - b * y2.im;
                    s[2] += a * y2.im + b * y2.re;
                    s[3] += at(k3) * yr;
                }
                Ok(StokesVector::new(StokesComponents::new(s)?, frame))
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polarized::Codomain;
    use crate::sh::harmonics::sh_real;
    use crate::swsh::swsh;
    use crate::testing::{random_directions, random_psh};

    /// Against the sum PSH (30) with the real SH and the spin-2 SH by Risbo's recursion
    /// ([`crate::swsh::swsh`], an independent `O(lmax^3)` path), poles included; to
    /// `1e-14` times the sum of the terms' magnitudes (the condition of the sum).
    #[test]
    fn matches_the_basis_sum() {
        for lmax in [0, 1, 2, 9, 40] {
            let v = random_psh(lmax, Codomain::Full, 2, lmax as u64).unwrap();
            let mut eval = PshEvaluator::new(lmax + 3).unwrap();
            let mut dirs = random_directions(20, 7);
            dirs.extend([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]]);
            for w in dirs {
                let (t, p) = direction_angles(w).unwrap();
                let yr = sh_real(lmax, t, p).unwrap();
                let y2 = swsh(2, lmax, t, p).unwrap();
                let got = eval.evaluate_all(&v, w).unwrap();
                for (c, s) in got.iter().enumerate() {
                    let mut want = [0.0; 4];
                    let (mut z, mut scale) = (Complex64::default(), 1.0);
                    for j in 0..num_coeffs(lmax) {
                        let (l, m) = crate::sh::lm_of_index(j);
                        want[0] += v.get(c, l, m, 0).unwrap() * yr[j];
                        want[3] += v.get(c, l, m, 3).unwrap() * yr[j];
                        z += Complex64::new(v.get(c, l, m, 1).unwrap(), v.get(c, l, m, 2).unwrap())
                            * y2[j];
                        scale += (0..4)
                            .map(|q| v.get(c, l, m, q).unwrap().abs())
                            .sum::<f64>()
                            * (yr[j].abs() + y2[j].norm());
                    }
                    (want[1], want[2]) = (z.re, z.im);
                    let got = s.components().to_array();
                    for q in 0..4 {
                        assert!(
                            (got[q] - want[q]).abs() < 1e-14 * scale,
                            "lmax {lmax}, w {w:?}, component {q}: {} vs {}",
                            got[q],
                            want[q]
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn refuses_a_vector_above_its_band_limit() {
        let v = random_psh(5, Codomain::Full, 1, 1).unwrap();
        let err = PshEvaluator::new(4)
            .unwrap()
            .evaluate_all(&v, [0.0, 0.0, 1.0])
            .unwrap_err();
        assert!(err.to_string().contains('5'), "{err}");
    }
}
