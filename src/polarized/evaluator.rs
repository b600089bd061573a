//! Point evaluation of PSH coefficient vectors PSH (30) with the basis tables built once:
//! the real SH PSH (12) by the Legendre recursion and the spin-2 SH PSH (26)-(27) by the
//! Wigner-d recursion of [`crate::swsh::SpinEvaluator`], both `O(lmax^2)` per direction, for
//! hot loops that evaluate many vectors of one band limit (a renderer's vertices).

use super::{Codomain, PshVector};
use crate::error::{check_len, Error, Result};
use crate::geometry::direction_angles;
use crate::geometry::frame::{Frame, FrameField, ThetaPhiFrameField};
use crate::lanes::F64x4;
use crate::sh::evaluation::harmonics::CisWalk;
use crate::sh::evaluation::harmonics::ShEvaluator;
use crate::sh::num_coeffs;
use crate::stokes::StokesVector;
use crate::swsh::evaluator::LanesScratch;
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
    /// The basis of [`PshEvaluator::evaluate_batch`] per coefficient: `Y`, `Re 2Y`,
    /// `Im 2Y` at four directions.
    lanes: Vec<[F64x4; 3]>,
    /// Its buffers: the real SH of four directions row by row, `Lambda_lm` and
    /// `(cos m phi, sin m phi)` in lanes, the spin recursion's.
    rows: Vec<f64>,
    lambda: Vec<[f64; 4]>,
    cis: Vec<[[f64; 2]; 4]>,
    spin_scratch: LanesScratch,
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
            lanes: Vec::with_capacity(num_coeffs(lmax)),
            rows: Vec::new(),
            lambda: Vec::new(),
            cis: Vec::new(),
            spin_scratch: LanesScratch::default(),
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

impl PshEvaluator {
    /// [`PshEvaluator::evaluate_into`] at many directions: the components of every channel
    /// of `v` at `dirs[d]` into `out[d * channels + c]`, in the theta-phi frame at
    /// `dirs[d]` (PSH (28)). Four directions at a time: their basis in lanes (the real SH
    /// by the Cartesian kernel, the spin-2 recursion for four polar angles) and the sums PSH (30) in lanes with independent partial
    /// sums (a single direction's sums wait on each addition in turn), so the values may
    /// differ from [`PshEvaluator::evaluate_into`]'s in the last bits. Errors: as
    /// [`PshEvaluator::evaluate_into`], and `out` not one per direction and channel.
    pub fn evaluate_batch(
        &mut self,
        v: &PshVector,
        dirs: &[[f64; 3]],
        out: &mut [[f64; 4]],
    ) -> Result<()> {
        if v.lmax() > self.lmax() {
            return Err(Error::invalid(
                "PSH vector lmax",
                v.lmax().to_string(),
                format!("the evaluator's band limit is {}", self.lmax()),
            ));
        }
        let nch = v.channels();
        check_len(
            "Stokes components per direction and channel",
            dirs.len().saturating_mul(nch),
            out.len(),
        )?;
        let spin = v.codomain().has_spin2();
        let expanded;
        let v = if v.codomain() == Codomain::Full {
            v
        } else {
            expanded = v.with_codomain(Codomain::Full);
            &expanded
        };
        let n = num_coeffs(v.lmax());
        for (block, outs) in dirs.chunks(4).zip(out.chunks_mut(4 * nch)) {
            self.basis_lanes(block, n, spin)?;
            // Lanes past the block's end repeat its last direction; their sums are not
            // read.
            for (c, x) in v.data().chunks_exact(4 * n).enumerate() {
                let s = crate::lanes::dispatch!(batch_sums_simd | batch_sums(x, &self.lanes));
                for (k, o) in outs.chunks_exact_mut(nch).enumerate() {
                    o[c] = [s[0].0[k], s[1].0[k], s[2].0[k], s[3].0[k]];
                }
            }
        }
        Ok(())
    }

    /// [`Self::lanes`] for the first `n` coefficients at the directions `block` (at most
    /// four; the last repeated): the real SH by the Cartesian kernel
    /// ([`ShEvaluator::real_batch`]), the spin-2 SH (zero unless `spin`) by the recursion in
    /// lanes ([`SpinEvaluator::lambda_lanes`]) times `e^{i m phi}` as
    /// [`SpinEvaluator::values`] walks it. Error: a direction that is not a unit vector.
    fn basis_lanes(&mut self, block: &[[f64; 3]], n: usize, spin: bool) -> Result<()> {
        let last = block[block.len() - 1];
        let dirs: [[f64; 3]; 4] = std::array::from_fn(|k| *block.get(k).unwrap_or(&last));
        let ne = num_coeffs(self.lmax());
        self.rows.resize(4 * ne, 0.0);
        self.scalar.real_batch(&dirs, &mut self.rows)?;
        self.lanes.clear();
        self.lanes.extend((0..n).map(|j| {
            let y = F64x4(std::array::from_fn(|k| self.rows[k * ne + j]));
            [y, F64x4::ZERO, F64x4::ZERO]
        }));
        let Some(evaluator) = self.spin.as_ref().filter(|_| spin) else {
            return Ok(());
        };
        let mut theta = [0.0; 4];
        let mut phi = [0.0; 4];
        for (k, &w) in dirs.iter().enumerate() {
            (theta[k], phi[k]) = direction_angles(w)?;
        }
        self.lambda.resize(ne, [0.0; 4]);
        evaluator.lambda_lanes(theta, &mut self.spin_scratch, &mut self.lambda);
        let mut walks = phi.map(CisWalk::new);
        self.cis.clear();
        self.cis.extend((0..=self.lmax()).map(|m| {
            std::array::from_fn(|k| {
                let (c, s) = walks[k].at(m);
                [c, s]
            })
        }));
        // Flat order: degree by degree, orders -l..=l.
        let orders = (0..).flat_map(|l: i64| -l..=l);
        for ((basis, lambda), m) in self.lanes.iter_mut().zip(&self.lambda).zip(orders) {
            let cis = &self.cis[m.unsigned_abs() as usize];
            let sign = m.signum() as f64;
            basis[1] = F64x4(std::array::from_fn(|k| cis[k][0] * lambda[k]));
            basis[2] = F64x4(std::array::from_fn(|k| sign * cis[k][1] * lambda[k]));
        }
        Ok(())
    }
}

/// Lane by lane `a + b`.
#[inline(always)]
fn lanes_add(a: F64x4, b: F64x4) -> F64x4 {
    F64x4(std::array::from_fn(|i| a.0[i] + b.0[i]))
}

/// Lane by lane `a - b`.
#[inline(always)]
fn lanes_sub(a: F64x4, b: F64x4) -> F64x4 {
    F64x4(std::array::from_fn(|i| a.0[i] - b.0[i]))
}

/// PSH (30) at four directions: `[s0, s1, s2, s3]`, each over the lanes, of one channel's
/// coefficients `x` (all four Stokes components, in coefficient order) with the basis
/// `lanes` (`Y`, `Re 2Y`, `Im 2Y`). Six sums per parity of the coefficient's index (twelve
/// chains of additions that do not wait on each other): `f0 Y`, `f3 Y`, `f1 Re`, `f2 Im`,
/// `f1 Im`, `f2 Re`; then `s1 + i s2 = (f1 + i f2) 2Y` is `(f1 Re - f2 Im, f1 Im + f2 Re)`.
#[inline(always)]
fn batch_sums(x: &[f64], lanes: &[[F64x4; 3]]) -> [F64x4; 4] {
    let mut acc = [[F64x4::ZERO; 6]; 2];
    let pairs = x.chunks_exact(8).zip(lanes.chunks_exact(2));
    for (f, l) in pairs {
        batch_step(&mut acc[0], &f[..4], &l[0]);
        batch_step(&mut acc[1], &f[4..], &l[1]);
    }
    if lanes.len() % 2 == 1 {
        let j = lanes.len() - 1;
        batch_step(&mut acc[0], &x[4 * j..4 * j + 4], &lanes[j]);
    }
    let t: [F64x4; 6] = std::array::from_fn(|k| lanes_add(acc[0][k], acc[1][k]));
    [t[0], lanes_sub(t[2], t[3]), lanes_add(t[4], t[5]), t[1]]
}

/// One coefficient's terms of [`batch_sums`] added to the sums `a` (a function, not a
/// closure: a closure may be compiled once outside the dispatched kernel).
#[inline(always)]
fn batch_step(a: &mut [F64x4; 6], f: &[f64], [y, re, im]: &[F64x4; 3]) {
    let s = |k: usize| F64x4::splat(f[k]);
    a[0] = s(0).mul_add(*y, a[0]);
    a[1] = s(3).mul_add(*y, a[1]);
    a[2] = s(1).mul_add(*re, a[2]);
    a[3] = s(2).mul_add(*im, a[3]);
    a[4] = s(1).mul_add(*im, a[4]);
    a[5] = s(2).mul_add(*re, a[5]);
}

/// [`batch_sums`] compiled per instruction set ([`crate::lanes`]).
#[multiversion(targets = "simd")]
fn batch_sums_simd(x: &[f64], lanes: &[[F64x4; 3]]) -> [F64x4; 4] {
    batch_sums(x, lanes)
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

    /// The batch equals the evaluator direction by direction to `1e-15` of the sum of
    /// the terms' magnitudes: band limits 0 to 40 (the real SH by the Cartesian kernel up
    /// to 24, by the polar one above), the poles, counts that leave a partial
    /// block of lanes, and codomains without `s1, s2` or `s3`.
    #[test]
    fn batch_matches_one_direction_at_a_time() {
        for (lmax, codomain) in [
            (0, Codomain::Full),
            (1, Codomain::Full),
            (2, Codomain::Full),
            (9, Codomain::Linear),
            (19, Codomain::Full),
            (24, Codomain::Intensity),
            (40, Codomain::Full),
        ] {
            let v = random_psh(lmax, codomain, 3, 11 + lmax as u64).unwrap();
            let mut dirs = random_directions(9, 4);
            dirs.extend([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]]);
            let mut eval = PshEvaluator::new(lmax + 1).unwrap();
            let mut out = vec![[0.0; 4]; dirs.len() * 3];
            eval.evaluate_batch(&v, &dirs, &mut out).unwrap();
            let scale: f64 = v.data().iter().map(|x| x.abs()).sum::<f64>() + 1.0;
            let mut one = vec![[0.0; 4]; 3];
            for (d, &w) in dirs.iter().enumerate() {
                eval.evaluate_into(&v, w, &mut one).unwrap();
                for c in 0..3 {
                    for p in 0..4 {
                        let (got, want) = (out[d * 3 + c][p], one[c][p]);
                        assert!(
                            (got - want).abs() <= 1e-15 * scale,
                            "l {lmax} dir {d} c {c} p {p}: {got} vs {want}"
                        );
                    }
                }
            }
            assert!(eval.evaluate_batch(&v, &dirs, &mut out[1..]).is_err());
        }
    }

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
