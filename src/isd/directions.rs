//! The axes `z_l^m` of the rotated mother functions (ISD Sec. 5.1): `2l + 1` unit
//! directions per band, either per band or shared across bands ("lobe sharing",
//! `z_{l+1}^m = z_l^m`: band `l` uses the first `2l + 1` of `2L + 1` directions).

use crate::error::{check_len, Error, Result};
use crate::geometry::{check_direction, direction, fibonacci_point, GOLDEN_ANGLE};
use crate::sh::num_coeffs;
use nalgebra::{Rotation3, Vector3};
use std::f64::consts::PI;

/// A low-discrepancy point pattern on the sphere.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pattern {
    /// The first `n` points of the spherical Fibonacci lattice of `n + 1` points:
    /// `z_k = 1 - (2k + 1)/(n + 1)`, azimuth `k` times the golden angle `pi (3 - sqrt 5)`.
    /// (The full lattice of an odd number `2l + 1` of points is invariant under a half
    /// turn about its equatorial point, which makes every odd band `l` singular,
    /// `proofs/isd.md` §4; dropping one point breaks the symmetry.) Its prefixes cluster
    /// at the north pole, so it suits per-band sets; points from `offset > 0` on are
    /// the lattice turned by `offset` golden angles about `(1, 1, 1)/sqrt 3`, so that
    /// bands do not share (nearly) the same axes.
    Fibonacci,
    /// Halton points of bases 2 and 3 mapped area-uniformly: `z_k = 1 - 2 h_2(k + 1)`,
    /// azimuth `2 pi h_3(k + 1)`. Every prefix is well spread (suits shared sets).
    Halton,
}

/// Per-band or shared directions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sharing {
    /// Band `l` has its own `2l + 1` directions.
    PerBand,
    /// All bands use prefixes of one set of `2L + 1` directions.
    Shared,
}

/// Radical inverse of `k` in `base` (van der Corput).
fn radical_inverse(mut k: usize, base: usize) -> f64 {
    let (mut inv, mut f) = (0.0, 1.0 / base as f64);
    while k > 0 {
        inv += (k % base) as f64 * f;
        k /= base;
        f /= base as f64;
    }
    inv
}

impl Pattern {
    /// Points `offset..offset + n` of the pattern (Fibonacci: the lattice of `n` points
    /// turned by `offset` golden angles).
    pub fn points(self, offset: usize, n: usize) -> Vec<[f64; 3]> {
        let turn = Rotation3::from_axis_angle(
            &nalgebra::Unit::new_normalize(Vector3::new(1.0, 1.0, 1.0)),
            offset as f64 * GOLDEN_ANGLE,
        );
        (0..n)
            .map(|k| match self {
                Pattern::Fibonacci => (turn * Vector3::from(fibonacci_point(k, n + 1))).into(),
                Pattern::Halton => {
                    let i = offset + k + 1;
                    let z: f64 = 1.0 - 2.0 * radical_inverse(i, 2);
                    direction(z.clamp(-1.0, 1.0).acos(), 2.0 * PI * radical_inverse(i, 3))
                }
            })
            .collect()
    }
}

/// The directions `z_l^m` of all bands `l <= lmax`.
#[derive(Clone, Debug, PartialEq)]
pub struct DirectionSet {
    lmax: usize,
    sharing: Sharing,
    /// Shared: `2 lmax + 1` directions; per band: band `l` at `l*l .. (l+1)^2`.
    dirs: Vec<[f64; 3]>,
}

impl DirectionSet {
    /// Directions of a pattern: per band, band `l` gets a pattern of `2l + 1` points
    /// (Halton: the next `2l + 1` points of the sequence); shared, the first `2L + 1`.
    pub fn from_pattern(pattern: Pattern, sharing: Sharing, lmax: usize) -> Result<Self> {
        let dirs = match sharing {
            Sharing::Shared => pattern.points(0, 2 * lmax + 1),
            Sharing::PerBand => (0..=lmax)
                .flat_map(|l| pattern.points(l * l, 2 * l + 1))
                .collect(),
        };
        Self::new(dirs, sharing, lmax)
    }

    /// Given directions: `(lmax + 1)^2` per band (band `l` at `l*l .. (l+1)^2`), or
    /// `2 lmax + 1` shared. Errors: a wrong count, or a direction not finite and unit.
    pub fn new(dirs: Vec<[f64; 3]>, sharing: Sharing, lmax: usize) -> Result<Self> {
        super::check_isd_lmax(lmax)?;
        let expected = match sharing {
            Sharing::Shared => 2 * lmax + 1,
            Sharing::PerBand => num_coeffs(lmax),
        };
        check_len("ISD directions", expected, dirs.len())?;
        for &w in &dirs {
            check_direction(w)
                .map_err(|e| Error::invalid("ISD direction", format!("{w:?}"), e.to_string()))?;
        }
        Ok(Self {
            lmax,
            sharing,
            dirs,
        })
    }

    /// The band limit `L`.
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// Per band or shared.
    pub fn sharing(&self) -> Sharing {
        self.sharing
    }

    /// The distinct directions (shared: `2L + 1`; per band: `(L + 1)^2`).
    pub fn distinct(&self) -> &[[f64; 3]] {
        &self.dirs
    }

    /// Index into [`Self::distinct`] of `z_l^m`, `|m| <= l <= L`.
    #[inline]
    pub fn index(&self, l: usize, m: i64) -> usize {
        let j = (l as i64 + m) as usize;
        match self.sharing {
            Sharing::Shared => j,
            Sharing::PerBand => l * l + j,
        }
    }

    /// The bands `l` using the distinct direction `k`, with `m` (shared: `l >= ceil(k/2)`,
    /// `m = k - l`; per band: the one `(l, m)` of flat index `k`).
    pub fn users(&self, k: usize) -> impl Iterator<Item = (usize, i64)> + '_ {
        let (lo, hi) = match self.sharing {
            Sharing::Shared => (k.div_ceil(2), self.lmax),
            Sharing::PerBand => {
                let l = crate::sh::lm_of_index(k).0;
                (l, l)
            }
        };
        let shared = self.sharing == Sharing::Shared;
        (lo..=hi).map(move |l| {
            let m = if shared {
                k as i64 - l as i64
            } else {
                crate::sh::lm_of_index(k).1
            };
            (l, m)
        })
    }
}
