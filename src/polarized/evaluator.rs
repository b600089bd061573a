//! Point evaluation of PSH coefficient vectors PSH (30) with the basis tables built once:
//! the real SH PSH (12) by the Legendre recursion and the spin-2 SH PSH (26)-(27) by the
//! Wigner-d recursion of [`crate::swsh::SpinEvaluator`], both `O(lmax^2)` per direction, for
//! hot loops that evaluate many vectors of one band limit (a renderer's vertices).

use super::PshVector;
use crate::error::{check_len, Error, Result};
use crate::geometry::direction_angles;
use crate::geometry::frame::{Frame, FrameField, ThetaPhiFrameField};
use crate::lanes::F64x4;
use crate::sh::evaluation::harmonics::ShEvaluator;
use crate::sh::num_coeffs;
use crate::stokes::StokesVector;
use crate::swsh::SpinEvaluator;
use multiversion::multiversion;
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
    /// The basis weights of [`PshEvaluator::evaluate_into`], per coefficient.
    weights: Vec<[[f64; 4]; 2]>,
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
            weights: Vec::with_capacity(num_coeffs(lmax)),
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
        let mut s = vec![[0.0; 4]; v.channels()];
        let frame = self.evaluate_into(v, w, &mut s)?;
        StokesVector::all_in_frame(&s, frame)
    }

    /// [`PshEvaluator::evaluate_all`] without allocating, for hot loops: the components
    /// `s0..s3` of every channel of `v` at `w` into `out` (one per channel), and the
    /// theta-phi frame at `w` they are measured in (PSH (28)). Errors: as
    /// [`PshEvaluator::evaluate_all`], and `out` not one per channel.
    pub fn evaluate_into(
        &mut self,
        v: &PshVector,
        w: [f64; 3],
        out: &mut [[f64; 4]],
    ) -> Result<Frame> {
        if v.lmax() > self.lmax() {
            return Err(Error::invalid(
                "PSH vector lmax",
                v.lmax().to_string(),
                format!("the evaluator's band limit is {}", self.lmax()),
            ));
        }
        check_len("Stokes components per channel", v.channels(), out.len())?;
        // Scalar SH needs no spin-2 basis.
        self.fill(w, v.codomain().has_spin2())?;
        let frame = ThetaPhiFrameField::new().frame(w)?;
        let comps = v.codomain().components();
        let np = comps.len();
        let n = num_coeffs(v.lmax());
        // Per coefficient, the basis weights of PSH (29)-(30) on `x = (f0, f1, f2, f3)`:
        // `a = x * (Y, Re 2Y, Re 2Y, Y)`, `b = x * (0, Im 2Y, Im 2Y, 0)` summed, then
        // `s1 + i s2 = (f1 + i f2) 2Y` is `(a1 - b2, a2 + b1)`: four lanes per coefficient.
        self.weights.clear();
        self.weights.extend(
            self.yr[..n]
                .iter()
                .zip(&self.y2[..n])
                .map(|(&y, z)| [[y, z.re, z.re, y], [0.0, z.im, z.im, 0.0]]),
        );
        let full = comps == [0, 1, 2, 3];
        for (x, s) in v.data().chunks_exact(n * np).zip(out.iter_mut()) {
            let [a, b] = if full {
                crate::lanes::dispatch!(weighted_sums_simd | weighted_sums(x, &self.weights))
            } else {
                let mut ab = [F64x4::ZERO; 2];
                for (xj, w) in x.chunks_exact(np).zip(&self.weights) {
                    // The components of the codomain in their Stokes slots, zero elsewhere.
                    let mut full_x = [0.0; 4];
                    for (&c, &p) in xj.iter().zip(comps) {
                        full_x[p] = c;
                    }
                    accumulate(&mut ab, full_x, w);
                }
                ab
            };
            let (a, b) = (a.to_array(), b.to_array());
            *s = [a[0], a[1] - b[2], a[2] + b[1], a[3]];
        }
        Ok(frame)
    }
}

/// `[a, b] += [x * wa, x * wb]`, lane by lane (the sums of [`PshEvaluator::evaluate_into`]).
#[inline(always)]
fn accumulate(ab: &mut [F64x4; 2], x: [f64; 4], [wa, wb]: &[[f64; 4]; 2]) {
    let x = F64x4::new(x);
    ab[0] = x.mul_add(F64x4::new(*wa), ab[0]);
    ab[1] = x.mul_add(F64x4::new(*wb), ab[1]);
}

/// The sums `a`, `b` of [`PshEvaluator::evaluate_into`] over the coefficients `x` of one
/// channel (all four Stokes components, in coefficient order).
#[inline(always)]
fn weighted_sums(x: &[f64], weights: &[[[f64; 4]; 2]]) -> [F64x4; 2] {
    let mut ab = [F64x4::ZERO; 2];
    for (xj, w) in x.chunks_exact(4).zip(weights) {
        accumulate(&mut ab, [xj[0], xj[1], xj[2], xj[3]], w);
    }
    ab
}

/// [`weighted_sums`] compiled per instruction set ([`crate::lanes`]).
#[multiversion(targets = "simd")]
fn weighted_sums_simd(x: &[f64], weights: &[[[f64; 4]; 2]]) -> [F64x4; 2] {
    weighted_sums(x, weights)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polarized::Codomain;
    use crate::sh::evaluation::harmonics::sh_real;
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
