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

use super::{Codomain, PshVector};
use crate::error::{Error, Result};
use crate::sh::wigner::{RealWignerD, WignerD};
use nalgebra::Rotation3;

/// The PSH coefficient matrix of one rotation, up to a band limit.
#[derive(Clone, Debug)]
pub struct PshRotation {
    real: RealWignerD,
    /// `None` when built for a codomain without spin-2 components.
    complex: Option<WignerD>,
}

impl PshRotation {
    /// The blocks of rotation `r` for `l <= lmax`.
    pub fn new(r: &Rotation3<f64>, lmax: usize) -> Result<Self> {
        Self::for_codomain(r, lmax, Codomain::Full)
    }

    /// The blocks that act on `codomain`: the spin-2 blocks only when it has `s1, s2`
    /// (scalar SH needs the real Wigner blocks alone).
    pub fn for_codomain(r: &Rotation3<f64>, lmax: usize, codomain: Codomain) -> Result<Self> {
        Ok(Self {
            real: RealWignerD::new(r, lmax)?,
            complex: if codomain.has_spin2() {
                Some(WignerD::new(r, lmax)?)
            } else {
                None
            },
        })
    }

    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.real.lmax()
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
        let mut out = v.clone();
        for c in 0..v.channels() {
            for (k, &p) in v.codomain().components().iter().enumerate() {
                if p == 0 || p == 3 {
                    out.set_component(c, k, &self.real.rotate(&v.component(c, k))?);
                }
            }
            if v.codomain().has_spin2() {
                let complex = self
                    .complex
                    .as_ref()
                    .ok_or_else(|| Error::InvalidArgument {
                        name: "PSH vector codomain",
                        value: v.codomain().name().into(),
                        reason: "the rotation was built without spin-2 blocks".into(),
                    })?;
                out.set_spin2(c, &complex.rotate(&v.spin2(c))?);
            }
        }
        Ok(out)
    }
}
