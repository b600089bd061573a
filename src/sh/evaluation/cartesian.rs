//! Real SH PSH (12) of small degree at unit vectors from their Cartesian coordinates, four
//! directions per SIMD vector: the batch kernel of [`crate::sh::ShEvaluator::real_batch`] for
//! `lmax <= CARTESIAN_LMAX`.
//!
//! With `rho = sin theta` and `Pbar_lm = Qbar_lm rho^m`, the real SH are
//! `Y^R_{l,+-m} = sqrt(2) Qbar_lm Re/Im (x + i y)^m` (`rho^m e^{i m phi} = (x + i y)^m`) and
//! `Y^R_{l0} = Qbar_l0`, where `Qbar_lm` obeys the column recursion of
//! [`crate::sh::recursion::legendre`] (it does not depend on `rho`) from the diagonal
//! `Qbar_mm = -sqrt((2m+1)/(2m)) Qbar_{m-1,m-1}`, `Qbar_00 = 1/sqrt(4 pi)` (the form of
//! sphericart, Bigi et al., J. Chem. Phys. 159 (2023)). No angle, no square root but the
//! normalization of the direction, and no exponent scaling: at these degrees `Qbar_lm` is
//! far inside the f64 range (it is a polynomial in `z` of degree `l - m`, at most
//! `Pbar_lm(theta) / sin^m theta <= sqrt((2l+1)/(4 pi)) l^m`), and the powers `(x + i y)^m`
//! only underflow where the harmonic is below `2^-1000`.
//! As in [`crate::sh::recursion::legendre`], the recursion runs in `u = 1 - |z| = rho^2 / (1 + |z|)` on the
//! northern mirror of each direction (full relative accuracy near the poles), with
//! `Pbar_lm(pi - theta) = (-1)^{l+m} Pbar_lm(theta)` for the southern ones.

use crate::lanes::{F64x4, LaneSet};
use crate::sh::index::lm_index;
use crate::sh::recursion::legendre::Legendre;
use std::f64::consts::{PI, SQRT_2};

/// The largest band limit the Cartesian kernel serves.
pub(crate) const CARTESIAN_LMAX: usize = 24;

/// Directions per SIMD vector.
pub(crate) const LANES: usize = 4;

/// Real SH of degrees `<= table.lmax()` at four directions (finite, near unit length;
/// normalized here) into `tile[l*l + l + m]` (one lane per direction), in the lanes of
/// `set`.
#[inline(always)]
pub(crate) fn real_lanes<L: LaneSet>(
    set: L,
    table: &Legendre,
    dirs: &[[f64; 3]; LANES],
    tile: &mut [F64x4],
) {
    let lmax = table.lmax();
    let [x, y, z] = std::array::from_fn(|i| set.load(&F64x4::new(dirs.map(|w| w[i]))));
    let one = set.splat(1.0);
    let inv = one / set.sqrt(x * x + y * y + z * z);
    let (x, y, z) = (x * inv, y * inv, z * inv);
    let rho2 = x * x + y * y;
    let u = rho2 / (one + set.abs(z));
    let south = set.sign_of_negative(z);
    let (mut c, mut s) = (one, set.zero());
    let mut diag = set.splat(0.5 / PI.sqrt());
    let sqrt2 = set.splat(SQRT_2);
    for m in 0..=lmax {
        if m > 0 {
            diag = diag * set.splat(table.diagonal(m));
            (c, s) = (x * c - y * s, x * s + y * c);
        }
        let (fc, fs) = if m == 0 {
            (one, set.zero())
        } else {
            (c * sqrt2, s * sqrt2)
        };
        let ab = table.column_coefficients(m);
        let (mut p1, mut p2, mut parity) = (diag, set.zero(), one);
        for (k, &[a, b]) in ab.iter().enumerate() {
            if k > 0 {
                let (a, b) = (set.splat(a), set.splat(b));
                let p = a * ((p1 - b * p2) - u * p1);
                p2 = p1;
                p1 = p;
                parity = parity * south;
            }
            let l = m + k;
            let v = p1 * parity;
            if m == 0 {
                tile[lm_index(l, 0)] = set.store(v);
            } else {
                tile[lm_index(l, m as i64)] = set.store(v * fc);
                tile[lm_index(l, -(m as i64))] = set.store(v * fs);
            }
        }
    }
}
