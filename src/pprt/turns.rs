//! The transfer as a function of the environment's turn about the vertical, for a viewer
//! that turns the environment every frame: sampled once, then interpolated exactly.
//!
//! The transfer of a vertex is linear in the environment ([`super::stages::retransfer`]:
//! the triple product PSH (54)-(56), the turn into the shading frame PSH (35)-(37) and the
//! pBRDF PSH (41) are linear maps), and it reads the environment truncated to `l <= l_low`.
//! Turned by `a` about `+z`, a coefficient of order `m` is multiplied by `e^{-i m a}`
//! (PSH (35)-(36) with `R = R_z(a)`: `D^l_{m'm}(R_z(a)) = e^{-i m a} delta_{m'm}`), for the
//! spin-2 coefficients too (the theta-phi frames are carried onto themselves by `R_z`), so
//! each transfer coefficient is a trigonometric polynomial in `a` of degree at most
//! `l_low`. Sampled at the `N = 2 l_low + 1` turns `a_k = 2 pi k / N`, it is exactly
//! `f(a) = sum_k f(a_k) D_N(a - a_k) / N` with the Dirichlet kernel
//! `D_N(x) = sin(N x / 2) / sin(x / 2)` (`D_N(0) = N`): trigonometric interpolation at an
//! odd number of equispaced points, exact for degree `<= (N - 1) / 2` (Zygmund,
//! *Trigonometric Series*, Ch. X; `proofs/environment-turns.md`).

use super::plan::Plan;
use super::scene::Scene;
use super::settings::Visibility;
use super::transfer::{precompute_planned, retransfer, VertexTransfer};
use crate::error::{check_len, Result};
use crate::polarized::PshVector;
use crate::progress::Progress;
use rayon::prelude::*;

/// The transfer's radiance at `2 l_low + 1` turns of the environment (module docs).
pub struct TransferTurns {
    /// `[k][object][vertex]`: the radiance with the environment turned by `2 pi k / N`.
    samples: Vec<Vec<Vec<PshVector>>>,
}

impl TransferTurns {
    /// The largest memory the samples may take, bytes (1 GiB).
    pub const MAX_BYTES: usize = 1 << 30;

    /// The bytes the samples of `transfer` under `plan` take.
    pub fn bytes(plan: &Plan, transfer: &[Vec<VertexTransfer>]) -> usize {
        let per_sample: usize = transfer
            .iter()
            .flatten()
            .map(|t| t.radiance.data().len())
            .sum();
        (2 * plan.settings.l_low + 1)
            .saturating_mul(per_sample)
            .saturating_mul(8)
    }

    /// The samples of `transfer` (of `scene` under `plan`) at `2 l_low + 1` turns, each
    /// by [`retransfer`] (visibility kept; [`precompute_planned`] when the plan casts no
    /// rays), reporting to `progress`. Errors: samples over [`Self::MAX_BYTES`] (named,
    /// before any work), and as [`retransfer`].
    pub fn new(
        scene: &Scene,
        plan: &Plan,
        transfer: &[Vec<VertexTransfer>],
        progress: &dyn Progress,
    ) -> Result<Self> {
        let n = 2 * plan.settings.l_low + 1;
        let bytes = Self::bytes(plan, transfer);
        if bytes > Self::MAX_BYTES {
            return Err(crate::Error::invalid(
                "transfer turn samples",
                format!("{n} samples, {bytes} bytes"),
                format!("at most {} bytes", Self::MAX_BYTES),
            ));
        }
        let samples = (0..n)
            .map(|k| {
                let angle = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
                let turned = scene.clone().with_environment_turned(angle)?;
                let t = match plan.visibility {
                    Visibility::Rays => retransfer(&turned, plan, transfer, progress)?,
                    _ => precompute_planned(&turned, plan, progress)?,
                };
                Ok(t.into_iter()
                    .map(|o| o.into_iter().map(|v| v.radiance).collect())
                    .collect())
            })
            .collect::<Result<_>>()?;
        Ok(Self { samples })
    }

    /// `transfer` (the one the samples were made of) with each vertex's radiance at the
    /// environment turned by `angle` radians (module docs). Errors: a non-finite angle,
    /// `transfer` of another shape.
    pub fn at(
        &self,
        transfer: &[Vec<VertexTransfer>],
        angle: f64,
    ) -> Result<Vec<Vec<VertexTransfer>>> {
        let angle = crate::error::finite("environment turn", angle)?;
        let n = self.samples.len();
        let weights: Vec<f64> = (0..n)
            .map(|k| {
                let x = angle - 2.0 * std::f64::consts::PI * k as f64 / n as f64;
                let half = (0.5 * x).sin();
                if half.abs() < 1e-12 {
                    // D_N(x) / N at x = 2 pi j: (-1)^{j (N - 1)} = 1 for odd N.
                    1.0
                } else {
                    (0.5 * n as f64 * x).sin() / (n as f64 * half)
                }
            })
            .collect();
        check_len("transfer objects", self.samples[0].len(), transfer.len())?;
        transfer
            .iter()
            .enumerate()
            .map(|(o, vertices)| {
                check_len("vertex transfers", self.samples[0][o].len(), vertices.len())?;
                vertices
                    .par_iter()
                    .enumerate()
                    .map(|(v, t)| {
                        let mut radiance = self.samples[0][o][v].scaled(weights[0])?;
                        for (k, w) in weights.iter().enumerate().skip(1) {
                            radiance.accumulate(*w, &self.samples[k][o][v])?;
                        }
                        Ok(VertexTransfer {
                            rotation: t.rotation,
                            visibility: t.visibility.clone(),
                            radiance,
                        })
                    })
                    .collect()
            })
            .collect()
    }
}
