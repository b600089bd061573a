//! Projection PSH (32) and reconstruction PSH (30) of PSH fields on the exact grid.

use super::{Codomain, PshVector};
use crate::error::{check_len, finite_all, Error, Result};
use crate::sh::num_coeffs;
use crate::sh::transform::sht::ShTransform;
use crate::swsh::SpinTransform;
use num_complex::Complex64;

/// Projection PSH (32) and reconstruction PSH (30) on the exact grid of band limit `lmax`.
pub struct PshTransform {
    pub(super) scalar: ShTransform,
    /// `None` below `lmax = 2`, where PSH (31) has no spin-2 index.
    pub(super) spin2: Option<SpinTransform>,
}

impl std::fmt::Debug for PshTransform {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PshTransform")
            .field("lmax", &self.lmax())
            .finish()
    }
}

impl PshTransform {
    /// Transforms for band limit `lmax` on the smallest exact grid.
    pub fn new(lmax: usize) -> Result<Self> {
        let scalar = ShTransform::new(lmax)?;
        let spin2 = if lmax >= 2 {
            Some(SpinTransform::with_grid(2, lmax, scalar.grid().clone())?)
        } else {
            None
        };
        Ok(Self { scalar, spin2 })
    }

    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.scalar.lmax()
    }

    /// The grid (values ring-major).
    pub fn grid(&self) -> &crate::sh::transform::grid::SphereGrid {
        self.scalar.grid()
    }

    /// Projection PSH (32) of one channel of Stokes components `[s0, s1, s2, s3]` given at
    /// the grid points in the theta-phi frame field (PSH (28)); components outside
    /// `codomain` are ignored. Exact for band-limited fields.
    pub fn project(&self, stokes: &[[f64; 4]], codomain: Codomain) -> Result<PshVector> {
        self.project_channels(&[stokes], codomain)
    }

    /// Projection of several channels.
    pub fn project_channels(
        &self,
        channels: &[&[[f64; 4]]],
        codomain: Codomain,
    ) -> Result<PshVector> {
        let mut out = PshVector::zeros(self.lmax(), codomain, channels.len())?;
        let n = num_coeffs(self.lmax());
        for (c, field) in channels.iter().enumerate() {
            check_len("Stokes field", self.grid().len(), field.len())?;
            finite_all("Stokes component", field.iter().flatten())?;
            for (k, &p) in codomain.components().iter().enumerate() {
                if p == 0 || p == 3 {
                    let values: Vec<f64> = field.iter().map(|s| s[p]).collect();
                    let mut coeffs = vec![0.0; n];
                    self.scalar.analysis_real(&values, &mut coeffs)?;
                    out.set_component(c, k, &coeffs);
                }
            }
            if let (Some(spin2), true) = (&self.spin2, codomain.has_spin2()) {
                let z: Vec<Complex64> = field.iter().map(|s| Complex64::new(s[1], s[2])).collect();
                let mut a = vec![Complex64::default(); n];
                spin2.analysis(&z, &mut a)?;
                out.set_spin2(c, &a);
            }
        }
        Ok(out)
    }

    /// Reconstruction PSH (30): the Stokes components `[s0, s1, s2, s3]` of channel `c` at
    /// the grid points, in the theta-phi frame field (absent components are 0).
    pub fn reconstruct(&self, v: &PshVector, c: usize) -> Result<Vec<[f64; 4]>> {
        if v.lmax() != self.lmax() || c >= v.channels() {
            return Err(Error::invalid(
                "PSH vector",
                format!("lmax {}, channel {c}", v.lmax()),
                format!(
                    "this transform has lmax {} ({} channels given)",
                    self.lmax(),
                    v.channels()
                ),
            ));
        }
        let npts = self.grid().len();
        let mut out = vec![[0.0; 4]; npts];
        for (k, &p) in v.codomain().components().iter().enumerate() {
            if p == 0 || p == 3 {
                let mut f = vec![0.0; npts];
                self.scalar.synthesis_real(&v.component(c, k), &mut f)?;
                for (o, x) in out.iter_mut().zip(f) {
                    o[p] = x;
                }
            }
        }
        if let (Some(spin2), true) = (&self.spin2, v.codomain().has_spin2()) {
            let mut z = vec![Complex64::default(); npts];
            spin2.synthesis(&v.spin2(c), &mut z)?;
            for (o, x) in out.iter_mut().zip(z) {
                o[1] = x.re;
                o[2] = x.im;
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn linear_codomain_round_trips() {
        let lmax = 6;
        let t = PshTransform::new(lmax).unwrap();
        let mut v = PshVector::zeros(lmax, Codomain::Linear, 1).unwrap();
        let re = crate::random::pseudo_random(num_coeffs(lmax), 9);
        let z: Vec<Complex64> = re
            .iter()
            .enumerate()
            .map(|(i, &x)| {
                if i < 4 {
                    Complex64::default()
                } else {
                    Complex64::new(x, 1.0 - x)
                }
            })
            .collect();
        v.set_spin2(0, &z);
        let f = t.reconstruct(&v, 0).unwrap();
        assert!(f.iter().all(|s| s[0] == 0.0 && s[3] == 0.0));
        let back = t.project(&f, Codomain::Linear).unwrap();
        for (a, b) in v.data().iter().zip(back.data()) {
            assert!((a - b).abs() < 1e-13);
        }
        assert!(t.reconstruct(&v, 1).is_err());
        let mut bad = f.clone();
        bad[3][1] = f64::INFINITY;
        assert!(t.project(&bad, Codomain::Linear).is_err());
    }
}
