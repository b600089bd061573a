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
//! The blocks are applied through the Euler factors of PSH (9),
//! `D^l(R) = Z(alpha) d^l(beta) Z(gamma)`: the z-rotations are phases `e^{-i m angle}`
//! (2x2 rotations of the orders `+-m` in the real basis), and `d^l(beta)` is applied from
//! its rows `m >= 0` ([`SmallDHalf`]) as dot products with folded columns
//! (`proofs/psh-rotation.md`, "Rotation through the Euler factors"):
//! about `(l + 1)(2l + 1)` multiply-adds per column instead of `(2l + 1)^2` complex ones.
//! [`PshRotation`] stores the halves for repeated use (memory `~(2/3) lmax^3` numbers,
//! checked against [`crate::budget`]); [`PshVector::rotated`] streams them one degree at
//! a time (memory `O(lmax^2)`), with the same result to the bit.

use super::PshVector;
use crate::error::{Error, Result};
use crate::geometry::euler_zyz;
use crate::lanes::F64x4;
use crate::sh::evaluation::harmonics::cis_m;
use crate::sh::rotation::small_d::{check_block_memory, for_each_small_d, SmallDHalf};
use multiversion::multiversion;
use nalgebra::Rotation3;
use std::f64::consts::SQRT_2;

/// The PSH coefficient matrix of one rotation, up to a band limit: the phases of its
/// Euler angles and the halves of its small-d blocks.
#[derive(Clone, Debug)]
pub struct PshRotation {
    phases: EulerPhases,
    /// Degree `l`: the rows of [`SmallDHalf::to_vec`].
    halves: Vec<Vec<f64>>,
}

impl PshRotation {
    /// The blocks of rotation `r` for `l <= lmax`. Error: their memory
    /// (`sum (l+1)(2l+1)` numbers) over the budget ([`crate::budget`]; rotate one vector
    /// with [`PshVector::rotated`] instead).
    pub fn new(r: &Rotation3<f64>, lmax: usize) -> Result<Self> {
        check_block_memory(lmax, true, 8)?;
        let (phases, beta) = EulerPhases::new(r, lmax);
        let mut halves = Vec::with_capacity(lmax + 1);
        for_each_small_d(beta, lmax, |half| halves.push(half.to_vec()))?;
        Ok(Self { phases, halves })
    }

    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.halves.len() - 1
    }

    /// The coefficients of `R_F[f]` (PSH (35)) for the coefficients of `f`.
    pub fn rotate(&self, v: &PshVector) -> Result<PshVector> {
        if v.lmax() != self.lmax() {
            return Err(Error::invalid(
                "PSH vector",
                format!("lmax {}", v.lmax()),
                format!("the rotation was built for lmax {}", self.lmax()),
            ));
        }
        let mut out = v.clone();
        let mut scratch = Scratch::default();
        for (l, rows) in self.halves.iter().enumerate() {
            let half = SmallDHalf::from_rows(l, rows)?;
            apply_degree(half, &self.phases, v, &mut out, &mut scratch);
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
        let (phases, beta) = EulerPhases::new(r, self.lmax());
        let mut scratch = Scratch::default();
        for_each_small_d(beta, self.lmax(), |half| {
            apply_degree(half, &phases, self, &mut out, &mut scratch)
        })?;
        Ok(out)
    }
}

/// `(cos m angle, sin m angle)`, `m = 0..=lmax`, of the Euler angles `alpha` (applied
/// last) and `gamma` (applied first) of `R = Rz(alpha) Ry(beta) Rz(gamma)`.
#[derive(Clone, Debug)]
struct EulerPhases {
    alpha: Vec<(f64, f64)>,
    gamma: Vec<(f64, f64)>,
}

impl EulerPhases {
    /// The phases of `r` and its angle `beta`.
    fn new(r: &Rotation3<f64>, lmax: usize) -> (Self, f64) {
        let (alpha, beta, gamma) = euler_zyz(r);
        let table = |angle: f64| (0..=lmax).map(|m| cis_m(m, angle)).collect();
        let phases = Self {
            alpha: table(alpha),
            gamma: table(gamma),
        };
        (phases, beta)
    }
}

/// The columns and products of [`apply_degree`], kept between degrees.
#[derive(Default)]
struct Scratch {
    /// The [`gain`] of each channel's spin-0 components and spin-2 pair, in column order.
    gains: Vec<f64>,
    x: Vec<f64>,
    z: Vec<f64>,
}

/// The factor applied to a column before the sums and undone after them: `2^-1000` when
/// its largest magnitude passes `2^900` (where a turn or the sums of [`products`] could
/// overflow although the result does not), else 1. A power of two: exact, so the result
/// is that of the unscaled arithmetic wherever that one is finite.
fn gain(column: impl Iterator<Item = f64>) -> f64 {
    let max = column.fold(0.0f64, |a, x| a.max(x.abs()));
    if max > 2f64.powi(900) {
        2f64.powi(-1000)
    } else {
        1.0
    }
}

/// `(-1)^m`.
fn parity(m: usize) -> f64 {
    if m.is_multiple_of(2) {
        1.0
    } else {
        -1.0
    }
}

/// Degree `l` of `R_F[v]` into `out` (PSH (35)-(37)) through `Z(alpha) d^l Z(gamma)`
/// (`proofs/psh-rotation.md`, "Rotation through the Euler factors").
///
/// Every column is first turned by `Z(gamma)` and laid out in the order `m' = l..=-l` of
/// the rows of `half`, then all of them meet each row once ([`products`]):
/// - a spin-0 component `x` (after its real z-rotation) gives `u` (`u_{+-k} = (+-1)^k x_k`,
///   `u_0 = sqrt(2) x_0`) and `w` (`w_k = x_{-k}`, `w_{-k} = -(-1)^k x_{-k}`, `w_0 = 0`),
///   and the real `d` block gives `y_k = d_k . u`, `y_0 = d_0 . u / sqrt(2)`,
///   `y_{-k} = d_k . w` (`k >= 1`);
/// - a spin-2 `a = f_1 + i f_2` (after its phases) gives `x` and `x~_k = (-1)^k x_{-k}`
///   (real and imaginary parts), and `z_m = d_m . x`, `z_{-m} = (-1)^m d_m . x~`.
fn apply_degree(
    half: SmallDHalf<'_>,
    phases: &EulerPhases,
    v: &PshVector,
    out: &mut PshVector,
    scratch: &mut Scratch,
) {
    let l = half.degree();
    let n = 2 * l + 1;
    let comps = v.codomain().components();
    let np = comps.len();
    let per_channel = crate::sh::num_coeffs(v.lmax()) * np;
    // Coefficient (channel c, order m, component k).
    let at =
        |c: usize, m: i64, k: usize| c * per_channel + (l * l + (m + l as i64) as usize) * np + k;
    let scalar: Vec<usize> = (0..np)
        .filter(|&k| comps[k] == 0 || comps[k] == 3)
        .collect();
    let spin2 = comps.iter().position(|&p| p == 1);
    let per = 2 * scalar.len() + if spin2.is_some() { 4 } else { 0 };
    let cp = (v.channels() * per).div_ceil(4) * 4;
    let Scratch { gains, x, z } = scratch;
    gains.clear();
    x.clear();
    x.resize(n * cp, 0.0);
    // Column j at order m' is x[(l - m') cp + j].
    let xi = |m: i64, j: usize| (l as i64 - m) as usize * cp + j;
    let src = v.data();
    let mut j = 0;
    for c in 0..v.channels() {
        for &k in &scalar {
            let g = gain((-(l as i64)..=l as i64).map(|m| src[at(c, m, k)]));
            gains.push(g);
            x[xi(0, j)] = SQRT_2 * (g * src[at(c, 0, k)]);
            for (m, &(cs, sn)) in phases.gamma.iter().enumerate().take(l + 1).skip(1) {
                let (mi, s) = (m as i64, parity(m));
                let (fp, fm) = (g * src[at(c, mi, k)], g * src[at(c, -mi, k)]);
                let (p, q) = (cs * fp - sn * fm, sn * fp + cs * fm);
                x[xi(mi, j)] = p;
                x[xi(-mi, j)] = s * p;
                x[xi(mi, j + 1)] = q;
                x[xi(-mi, j + 1)] = -s * q;
            }
            j += 2;
        }
        if let Some(k1) = spin2 {
            let orders = -(l as i64)..=l as i64;
            let g = gain(orders.flat_map(|m| [src[at(c, m, k1)], src[at(c, m, k1 + 1)]]));
            gains.push(g);
            for m in -(l as i64)..=l as i64 {
                let (cs, sn) = phases.gamma[m.unsigned_abs() as usize];
                let e = (cs, -(m.signum() as f64) * sn);
                let (ar, ai) = (g * src[at(c, m, k1)], g * src[at(c, m, k1 + 1)]);
                let (re, im) = (e.0 * ar - e.1 * ai, e.0 * ai + e.1 * ar);
                let s = parity(m.unsigned_abs() as usize);
                x[xi(m, j)] = re;
                x[xi(m, j + 1)] = im;
                x[xi(-m, j + 2)] = s * re;
                x[xi(-m, j + 3)] = s * im;
            }
            j += 4;
        }
    }
    z.clear();
    z.resize((l + 1) * cp, 0.0);
    crate::lanes::dispatch!(products_simd | products(half, x, cp, z));
    let dst = out.data_mut();
    let (mut j, mut gains) = (0, gains.iter().map(|g| 1.0 / g));
    for c in 0..v.channels() {
        for &k in &scalar {
            let g = gains.next().unwrap_or(1.0);
            dst[at(c, 0, k)] = g * (z[j] / SQRT_2);
            for (m, &(cs, sn)) in phases.alpha.iter().enumerate().take(l + 1).skip(1) {
                let (yp, ym) = (z[m * cp + j], z[m * cp + j + 1]);
                dst[at(c, m as i64, k)] = g * (cs * yp - sn * ym);
                dst[at(c, -(m as i64), k)] = g * (sn * yp + cs * ym);
            }
            j += 2;
        }
        if let Some(k1) = spin2 {
            let g = gains.next().unwrap_or(1.0);
            for (m, &(cs, sn)) in phases.alpha.iter().enumerate().take(l + 1) {
                let zm = &z[m * cp + j..m * cp + j + 4];
                // e^{-i m alpha} z_m and e^{i m alpha} z_{-m}, z_{-m} = (-1)^m (zm[2], zm[3]).
                dst[at(c, m as i64, k1)] = g * (cs * zm[0] + sn * zm[1]);
                dst[at(c, m as i64, k1 + 1)] = g * (cs * zm[1] - sn * zm[0]);
                if m > 0 {
                    let s = parity(m);
                    let (re, im) = (s * zm[2], s * zm[3]);
                    dst[at(c, -(m as i64), k1)] = g * (cs * re - sn * im);
                    dst[at(c, -(m as i64), k1 + 1)] = g * (cs * im + sn * re);
                }
            }
            j += 4;
        }
    }
}

/// `z[m cp + j] = sum_b row_m[b] x[b cp + j]` for the rows `m = 0..=l` of `half` and the
/// `cp` columns of `x` (a multiple of 4): column blocks of up to six SIMD vectors, rows
/// in pairs, each row entry read once per block.
#[inline(always)]
fn products(half: SmallDHalf<'_>, x: &[f64], cp: usize, z: &mut [f64]) {
    let mut j = 0;
    while j < cp {
        let v = ((cp - j) / 4).min(6);
        match v {
            1 => product_block::<1>(half, x, cp, j, z),
            2 => product_block::<2>(half, x, cp, j, z),
            3 => product_block::<3>(half, x, cp, j, z),
            4 => product_block::<4>(half, x, cp, j, z),
            5 => product_block::<5>(half, x, cp, j, z),
            _ => product_block::<6>(half, x, cp, j, z),
        }
        j += 4 * v;
    }
}

/// [`products`] compiled per instruction set ([`crate::lanes`]).
#[multiversion(targets = "simd")]
fn products_simd(half: SmallDHalf<'_>, x: &[f64], cp: usize, z: &mut [f64]) {
    products(half, x, cp, z)
}

/// The columns `j..j + 4V` of [`products`] (inlined into its instruction set).
#[inline(always)]
fn product_block<const V: usize>(
    half: SmallDHalf<'_>,
    x: &[f64],
    cp: usize,
    j: usize,
    z: &mut [f64],
) {
    let l = half.degree();
    let n = 2 * l + 1;
    for m in (0..=l).step_by(2) {
        let (r0, r1) = (half.row(m), half.row((m + 1).min(l)));
        let mut acc = [[F64x4::ZERO; V]; 2];
        for ((&d0, &d1), xb) in r0.iter().zip(r1).zip(x.chunks_exact(cp)).take(n) {
            let (d0, d1) = (F64x4::splat(d0), F64x4::splat(d1));
            let xb = &xb[j..j + 4 * V];
            for v in 0..V {
                let xv = F64x4::new([xb[4 * v], xb[4 * v + 1], xb[4 * v + 2], xb[4 * v + 3]]);
                acc[0][v] = d0.mul_add(xv, acc[0][v]);
                acc[1][v] = d1.mul_add(xv, acc[1][v]);
            }
        }
        for (r, acc) in [m, m + 1].into_iter().zip(acc) {
            if r <= l {
                for (v, a) in acc.iter().enumerate() {
                    let o = r * cp + j + 4 * v;
                    z[o..o + 4].copy_from_slice(&a.to_array());
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::Codomain;
    use super::*;
    use crate::geometry::rotation_from_rotvec;
    use crate::sh::{RealWignerD, WignerD};
    use crate::testing::random_psh;
    use num_complex::Complex64;
    use std::f64::consts::PI;

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
            let stored = PshRotation::new(&r, 12).unwrap().rotate(&v).unwrap();
            assert_eq!(v.rotated(&r).unwrap().data(), stored.data(), "{codomain:?}");
        }
    }

    /// The Euler factors applied from the halves of `d` equal the whole blocks of
    /// PSH (35)-(37) ([`RealWignerD`] on spin 0, [`WignerD`] on `a = f_1 + i f_2`), at the
    /// identity, a half turn (`beta = pi`, the seam of the Euler angles), and generic
    /// rotations, to l = 40.
    #[test]
    fn euler_factors_equal_the_whole_blocks() {
        let lmax = 40;
        for rotvec in [
            [1e-9, 0.0, 0.0],
            [0.3, -1.1, 0.7],
            [PI, 0.0, 0.0],
            [0.0, 0.0, 2.5],
            [-2.0, 0.4, 1.9],
        ] {
            let r = rotation_from_rotvec(rotvec).unwrap();
            let v = random_psh(lmax, Codomain::Full, 2, 7).unwrap();
            let got = v.rotated(&r).unwrap();
            let real = RealWignerD::new(&r, lmax).unwrap();
            let complex = WignerD::new(&r, lmax).unwrap();
            let scale = v.data().iter().fold(0.0f64, |a, x| a.max(x.abs()));
            // Channel c, component p, at every (l, m) in the order of lm_index.
            let coeffs = |w: &PshVector, c: usize, p: usize| -> Vec<f64> {
                (0..=lmax)
                    .flat_map(|l| (-(l as i64)..=l as i64).map(move |m| (l, m)))
                    .map(|(l, m)| w.get(c, l, m, p).unwrap())
                    .collect()
            };
            for c in 0..2 {
                for p in [0, 3] {
                    let want = real.rotate(&coeffs(&v, c, p)).unwrap();
                    for (g, w) in coeffs(&got, c, p).iter().zip(&want) {
                        assert!((g - w).abs() < 1e-13 * scale, "{rotvec:?} c {c} p {p}");
                    }
                }
                let pair = |w: &PshVector| -> Vec<Complex64> {
                    let (re, im) = (coeffs(w, c, 1), coeffs(w, c, 2));
                    re.iter()
                        .zip(&im)
                        .map(|(&a, &b)| Complex64::new(a, b))
                        .collect()
                };
                let want = complex.rotate(&pair(&v)).unwrap();
                for (g, w) in pair(&got).iter().zip(&want) {
                    assert!((g - w).norm() < 1e-13 * scale, "{rotvec:?} c {c} spin 2");
                }
            }
        }
    }

    /// A PSH vector turned by each edge rotation (`testing::EDGE_ROTATIONS`: tiny turns
    /// about axes near z, tilted and horizontal, near half turns), built as a matrix
    /// product, equals it turned by `A^-1 R` and then by `A` for a generic `A`: both
    /// factors have well-determined Euler angles, so the route never meets the
    /// ill-determined angles of a small tilt. Within `10 l eps` of the largest
    /// coefficient; the Euler angles from atan2 of matrix entries were off by up to
    /// `eps / sin(beta)` (`proofs/euler-angles.md`).
    #[test]
    fn edge_rotations_equal_a_route_through_a_generic_rotation() {
        use nalgebra::{Rotation3, Vector3};
        let lmax = 40;
        let v = random_psh(lmax, Codomain::Full, 1, 11).unwrap();
        let scale = v.data().iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let a = rotation_from_rotvec([0.3, -1.1, 0.7]).unwrap();
        let z = |t: f64| Rotation3::from_axis_angle(&Vector3::z_axis(), t);
        let y = |t: f64| Rotation3::from_axis_angle(&Vector3::y_axis(), t);
        for &(tilt, phi, t) in &crate::testing::EDGE_ROTATIONS {
            let r = z(phi) * y(tilt) * z(t) * y(-tilt) * z(-phi);
            let direct = v.rotated(&r).unwrap();
            let routed = v.rotated(&(a.inverse() * r)).unwrap().rotated(&a).unwrap();
            let err = direct
                .data()
                .iter()
                .zip(routed.data())
                .fold(0.0f64, |m, (g, w)| m.max((g - w).abs()));
            assert!(
                err < 10.0 * lmax as f64 * f64::EPSILON * scale,
                "tilt {tilt} phi {phi} t {t}: {err:e}"
            );
        }
    }

    #[test]
    fn stored_blocks_are_checked_against_the_budget() {
        let r = rotation_from_rotvec([0.0, 0.0, 1.0]).unwrap();
        // sum (l+1)(2l+1) ~ 8e11 entries of 8 bytes: refused before allocating.
        let e = PshRotation::new(&r, 10_000).unwrap_err();
        assert!(matches!(e, Error::MemoryBudget { .. }), "{e}");
        let v = random_psh(4, Codomain::Full, 1, 1).unwrap();
        assert!(PshRotation::new(&r, 5).unwrap().rotate(&v).is_err());
    }
}
