//! Rotation of PSH coefficient vectors PSH (35)-(37).
//!
//! The coefficient matrix of a rotation `R_F` on Stokes fields (PSH (25)) in the PSH basis
//! is block diagonal in `l` (derived in `proofs/psh-rotation.md`, the lost PSH (36)):
//!
//! - `p = 0, 3` (spin 0): the real Wigner blocks `D^{l,R}(R)` of PSH (13);
//! - `p = 1, 2` (spin 2): `[f'_lm1; f'_lm2] = sum_m' R^{2x2}(D^l_mm'(R)) [f_lm'1; f_lm'2]`
//!   with the complex Wigner blocks of PSH (9) and `R^{2x2}(x + iy) = [[x, -y], [y, x]]`
//!   (PSH (37)), i.e. `a'_lm = sum_m' D^l_mm' a_lm'` for `a = f_1 + i f_2`;
//! - no coupling between spin 0 and spin 2, nor between different `l`.
//!
//! [`PshRotation`] stores the blocks for repeated use (memory `~(4/3) lmax^3` numbers,
//! checked against [`crate::budget`]); [`PshVector::rotated`] streams them one degree at
//! a time (memory `O(lmax^2)`), with the same result to the bit.

use super::{Codomain, PshVector};
use crate::error::{Error, Result};
use crate::sh::wigner::{check_block_memory, for_each_block, real_block};
use nalgebra::Rotation3;
use num_complex::Complex64;
use wide::f64x4;

/// The blocks of one degree: real (PSH (13)) and, for spin 2, complex (PSH (9)).
#[derive(Clone, Debug)]
struct Degree {
    real: Vec<f64>,
    complex: Option<Vec<Complex64>>,
}

/// The PSH coefficient matrix of one rotation, up to a band limit.
#[derive(Clone, Debug)]
pub struct PshRotation {
    degrees: Vec<Degree>,
}

impl PshRotation {
    /// The blocks of rotation `r` for `l <= lmax`.
    pub fn new(r: &Rotation3<f64>, lmax: usize) -> Result<Self> {
        Self::for_codomain(r, lmax, Codomain::Full)
    }

    /// The blocks that act on `codomain`: the spin-2 blocks only when it has `s1, s2`
    /// (scalar SH needs the real Wigner blocks alone). Error: the blocks' memory
    /// (`sum (2l+1)^2` numbers) over the budget ([`crate::budget`]).
    pub fn for_codomain(r: &Rotation3<f64>, lmax: usize, codomain: Codomain) -> Result<Self> {
        let spin2 = codomain.has_spin2();
        check_block_memory(lmax, if spin2 { 24 } else { 8 })?;
        let mut degrees = Vec::with_capacity(lmax + 1);
        let mut real = Vec::new();
        for_each_block(r, lmax, |l, b| {
            real_block(l, b, &mut real);
            degrees.push(Degree {
                real: real.clone(),
                complex: spin2.then(|| b.to_vec()),
            });
        })?;
        Ok(Self { degrees })
    }

    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.degrees.len() - 1
    }

    /// The coefficients of `R_F[f]` (PSH (35)) for the coefficients of `f`.
    pub fn rotate(&self, v: &PshVector) -> Result<PshVector> {
        if v.lmax() != self.lmax() {
            return Err(Error::InvalidArgument {
                name: "PSH vector",
                value: format!("lmax {}", v.lmax()),
                reason: format!("the rotation was built for lmax {}", self.lmax()),
            });
        }
        if v.codomain().has_spin2() && self.degrees[0].complex.is_none() {
            return Err(Error::InvalidArgument {
                name: "PSH vector codomain",
                value: v.codomain().name().into(),
                reason: "the rotation was built without spin-2 blocks".into(),
            });
        }
        let mut out = v.clone();
        for (l, d) in self.degrees.iter().enumerate() {
            apply_degree(l, &d.real, d.complex.as_deref(), v, &mut out);
        }
        Ok(out)
    }
}

impl PshVector {
    /// The coefficients of `R_F[f]` (PSH (35)), the Wigner blocks streamed one degree at a
    /// time (memory `O(lmax^2)` besides the vector): equal to the bit to
    /// [`PshRotation::rotate`], which keeps the blocks for many vectors.
    pub fn rotated(&self, r: &Rotation3<f64>) -> Result<PshVector> {
        let mut out = self.clone();
        let spin2 = self.codomain().has_spin2();
        let mut real = Vec::new();
        for_each_block(r, self.lmax(), |l, b| {
            real_block(l, b, &mut real);
            apply_degree(l, &real, spin2.then_some(b), self, &mut out);
        })?;
        Ok(out)
    }
}

/// Degree `l` of `R_F[v]` into `out`: the real block on the spin-0 components, the
/// complex block on `a = f_1 + i f_2` (PSH (37)); row `m` is `sum_m' B_mm' x_m'`.
///
/// The columns (every channel's spin-0 components, every channel's `a`) are gathered
/// contiguous in `m'`, so that each entry is a dot product of a block row with a column in
/// SIMD lanes ([`lane_dot`]), each block row read once per degree from cache.
fn apply_degree(
    l: usize,
    real: &[f64],
    complex: Option<&[Complex64]>,
    v: &PshVector,
    out: &mut PshVector,
) {
    let n = 2 * l + 1;
    let comps = v.codomain().components();
    let np = comps.len();
    let per_channel = crate::sh::num_coeffs(v.lmax()) * np;
    let at = |c: usize, m: usize, k: usize| c * per_channel + (l * l + m) * np + k;
    let src = v.data();
    let scalar: Vec<(usize, usize)> = (0..v.channels())
        .flat_map(|c| {
            let ks = comps.iter().enumerate().filter(|(_, &p)| p == 0 || p == 3);
            ks.map(move |(k, _)| (c, k))
        })
        .collect();
    let mut column = vec![0.0; n];
    let mut results = vec![0.0; n * scalar.len()];
    for (&(c, k), y) in scalar.iter().zip(results.chunks_exact_mut(n)) {
        for (m, x) in column.iter_mut().enumerate() {
            *x = src[at(c, m, k)];
        }
        for (row, y) in real.chunks_exact(n).zip(y.iter_mut()) {
            *y = lane_dot(row, &column).reduce_add();
        }
    }
    // a = f_1 + i f_2 interleaved ([re, im] per m'), and swapped ([im, re]): the lane sums
    // of a block row (interleaved) with them hold sum (Re B Re a, Im B Im a) and the
    // imaginary part.
    let spin2 = complex.zip(comps.iter().position(|&p| p == 1));
    let mut complex_results = Vec::new();
    if let Some((block, k1)) = spin2 {
        let flat: &[f64] = interleaved(block);
        let (mut a, mut swapped) = (vec![0.0; 2 * n], vec![0.0; 2 * n]);
        for c in 0..v.channels() {
            for m in 0..n {
                let (re, im) = (src[at(c, m, k1)], src[at(c, m, k1 + 1)]);
                a[2 * m..2 * m + 2].copy_from_slice(&[re, im]);
                swapped[2 * m..2 * m + 2].copy_from_slice(&[im, re]);
            }
            for row in flat.chunks_exact(2 * n) {
                let s = lane_dot(row, &a).to_array();
                let re = (s[0] + s[2]) - (s[1] + s[3]);
                let im = lane_dot(row, &swapped).reduce_add();
                complex_results.push((re, im));
            }
        }
    }
    let dst = out.data_mut();
    for (&(c, k), y) in scalar.iter().zip(results.chunks_exact(n)) {
        for (m, &y) in y.iter().enumerate() {
            dst[at(c, m, k)] = y;
        }
    }
    if let Some((_, k1)) = spin2 {
        for (i, &(re, im)) in complex_results.iter().enumerate() {
            let (c, m) = (i / n, i % n);
            dst[at(c, m, k1)] = re;
            dst[at(c, m, k1 + 1)] = im;
        }
    }
}

/// `[re, im, re, im, ...]` of complex numbers (`Complex64` is `repr(C)`, two `f64`).
fn interleaved(z: &[Complex64]) -> &[f64] {
    // SAFETY: Complex64 is #[repr(C)] { re: f64, im: f64 }: 2 z.len() f64 in place.
    unsafe { std::slice::from_raw_parts(z.as_ptr().cast::<f64>(), 2 * z.len()) }
}

/// Lane sums of `a[j] b[j]`: lane `q` sums the `j = q mod 4` (the tail past the last full
/// vector goes to lanes `0, 1, ...`, keeping that rule), in a fixed order.
#[inline]
fn lane_dot(a: &[f64], b: &[f64]) -> f64x4 {
    let mut acc = [f64x4::ZERO; 2];
    let (ac, bc) = (a.chunks_exact(8), b.chunks_exact(8));
    let (at, bt) = (ac.remainder(), bc.remainder());
    for (x, y) in ac.zip(bc) {
        for h in 0..2 {
            let x = f64x4::new([x[4 * h], x[4 * h + 1], x[4 * h + 2], x[4 * h + 3]]);
            let y = f64x4::new([y[4 * h], y[4 * h + 1], y[4 * h + 2], y[4 * h + 3]]);
            acc[h] = x.mul_add(y, acc[h]);
        }
    }
    let mut tail = [0.0; 4];
    for (j, (x, y)) in at.iter().zip(bt).enumerate() {
        tail[j % 4] += x * y;
    }
    acc[0] + acc[1] + f64x4::new(tail)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::rotation_from_rotvec;
    use crate::testing::random_psh;

    #[test]
    fn streamed_equals_stored_to_the_bit() {
        let r = rotation_from_rotvec([0.3, -1.1, 0.7]).unwrap();
        for codomain in [
            Codomain::Intensity,
            Codomain::Linear,
            Codomain::NoCircular,
            Codomain::Full,
        ] {
            let v = random_psh(12, codomain, 3, 5).unwrap();
            let stored = PshRotation::for_codomain(&r, 12, codomain)
                .unwrap()
                .rotate(&v)
                .unwrap();
            assert_eq!(v.rotated(&r).unwrap().data(), stored.data(), "{codomain:?}");
        }
    }

    #[test]
    fn stored_blocks_are_checked_against_the_budget() {
        let r = rotation_from_rotvec([0.0, 0.0, 1.0]).unwrap();
        // sum (2l+1)^2 ~ 1.7e11 entries of 24 bytes: refused before allocating.
        let e = PshRotation::new(&r, 5000).unwrap_err();
        assert!(matches!(e, Error::MemoryBudget { .. }), "{e}");
        let v = random_psh(4, Codomain::Full, 1, 1).unwrap();
        let scalar_only = PshRotation::for_codomain(&r, 4, Codomain::Intensity).unwrap();
        assert!(scalar_only.rotate(&v).is_err());
    }
}
