//! Polarized spherical convolution kernels (PSH Sec. 6.4.1): a Mueller matrix
//! `k(theta)` of one angle (PSH (61)-(62)), read between the frame at the input direction
//! and the frame at the output direction whose `x` axes run along the great circle
//! through both, and the convolution it defines in the angular domain (PSH (63)).

use crate::error::{Error, Result};
use crate::geometry::check_direction;
use crate::geometry::frame::Frame;
use crate::stokes::{MuellerField, MuellerMatrix, MuellerTransform};
use nalgebra::Vector3;
use std::f64::consts::PI;
use std::sync::Arc;

/// A numeric 4 x 4 kernel value `k(theta)`, rows the output Stokes component.
pub type KernelValue = [[f64; 4]; 4];

/// Below this `sin theta` the great circle through two directions is taken as any one
/// (the kernel must then be invariant under rotations about the axis, as every
/// band-limited kernel is: its spin-changing entries vanish at `theta = 0, pi`).
const DEGENERATE_SIN: f64 = 1e-12;

/// A convolution kernel `k: [0, pi] -> R^{4x4}` (PSH (62)): a closure, or a table of
/// samples interpolated linearly in `theta`.
#[derive(Clone)]
pub struct ConvolutionKernel {
    eval: Arc<dyn Fn(f64) -> KernelValue + Send + Sync>,
    /// Angles where the kernel may have kinks (the table's samples), for quadrature.
    breakpoints: Vec<f64>,
    /// Number of samples of a table (`None` for a closure).
    samples: Option<usize>,
}

impl std::fmt::Debug for ConvolutionKernel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ConvolutionKernel")
            .field("samples", &self.samples)
            .finish()
    }
}

impl ConvolutionKernel {
    /// A kernel given by a closure of `theta` in `[0, pi]`; non-finite values are
    /// reported as errors where the kernel is evaluated.
    pub fn from_fn(f: impl Fn(f64) -> KernelValue + Send + Sync + 'static) -> Self {
        Self {
            eval: Arc::new(f),
            breakpoints: Vec::new(),
            samples: None,
        }
    }

    /// The paper's test kernel `k(theta) = (pi - theta) I` (PSH Sec. 6.4.3, Fig. 16).
    pub fn linear_zenith() -> Self {
        Self::from_fn(|t| {
            let mut k = [[0.0; 4]; 4];
            for (p, row) in k.iter_mut().enumerate() {
                row[p] = PI - t;
            }
            k
        })
    }

    /// A kernel tabulated at `theta` (strictly increasing, from 0 to pi within `1e-9`),
    /// linearly interpolated. Errors name the offending sample: fewer than two samples,
    /// non-monotone or non-finite angles, an uncovered end of `[0, pi]`, non-finite
    /// entries, or a number of values different from the number of angles.
    pub fn from_table(theta: Vec<f64>, values: Vec<KernelValue>) -> Result<Self> {
        let bad = |value: String, reason: &str| Error::invalid("kernel table", value, reason);
        if theta.len() != values.len() {
            return Err(bad(
                format!("{} angles, {} values", theta.len(), values.len()),
                "one 4 x 4 value per angle",
            ));
        }
        if theta.len() < 2 {
            return Err(bad(
                format!("{} samples", theta.len()),
                "at least two samples",
            ));
        }
        if let Some(i) = theta.iter().position(|t| !t.is_finite()) {
            return Err(bad(format!("theta[{i}] = {}", theta[i]), "finite angles"));
        }
        if let Some(i) = (1..theta.len()).find(|&i| theta[i] <= theta[i - 1]) {
            return Err(bad(
                format!("theta[{i}] = {} after {}", theta[i], theta[i - 1]),
                "angles strictly increasing",
            ));
        }
        let (first, last) = (theta[0], theta[theta.len() - 1]);
        if first.abs() > 1e-9 || (last - PI).abs() > 1e-9 {
            return Err(bad(
                format!("[{first}, {last}]"),
                "the samples must cover [0, pi] (first 0, last pi)",
            ));
        }
        for (i, v) in values.iter().enumerate() {
            if let Some(x) = v.iter().flatten().find(|x| !x.is_finite()) {
                return Err(bad(format!("k(theta[{i}]) has {x}"), "finite entries"));
            }
        }
        let samples = theta.len();
        let (t, v) = (theta.clone(), values);
        Ok(Self {
            eval: Arc::new(move |x| {
                let j = t.partition_point(|&s| s <= x).clamp(1, t.len() - 1);
                let u = ((x - t[j - 1]) / (t[j] - t[j - 1])).clamp(0.0, 1.0);
                std::array::from_fn(|r| {
                    std::array::from_fn(|c| (1.0 - u) * v[j - 1][r][c] + u * v[j][r][c])
                })
            }),
            breakpoints: theta,
            samples: Some(samples),
        })
    }

    /// The band-limited kernel of convolution coefficients
    /// ([`super::KernelCoefficients::synthesize`]).
    pub fn from_coefficients(k: super::KernelCoefficients) -> Self {
        Self::from_fn(move |t| k.synthesize(t).unwrap_or([[f64::NAN; 4]; 4]))
    }

    /// `k(theta)`. Errors: `theta` outside `[0, pi]` or a non-finite value, naming it.
    pub fn value(&self, theta: f64) -> Result<KernelValue> {
        if !(0.0..=PI).contains(&theta) {
            return Err(Error::invalid(
                "kernel angle",
                theta.to_string(),
                "theta in [0, pi]",
            ));
        }
        let k = (self.eval)(theta);
        match k.iter().flatten().find(|x| !x.is_finite()) {
            Some(x) => Err(Error::invalid(
                "kernel",
                format!("k({theta}) has {x}"),
                "a kernel must be finite on [0, pi]",
            )),
            None => Ok(k),
        }
    }

    /// The interior angles where the kernel may have kinks (a table's samples).
    pub(crate) fn breakpoints(&self) -> &[f64] {
        &self.breakpoints
    }

    /// Number of samples of a tabulated kernel (`None` for a closure).
    pub fn samples(&self) -> Option<usize> {
        self.samples
    }
}

/// The operator of the convolution (PSH (63)) as a Mueller transform field:
/// `K(w_i, w_o) = [k(acos(w_i . w_o))]_{F_i -> F_o}` with `F_i` at `w_i` and `F_o` at `w_o`
/// both with `x` along the great circle from `w_i` to `w_o` (PSH (61): the frames
/// `F_thetaphi(0, phi)` and `F_thetaphi(theta, phi)` when `w_i` is the pole).
impl MuellerField for ConvolutionKernel {
    fn transform(&self, wi: [f64; 3], wo: [f64; 3]) -> Result<MuellerTransform> {
        let (a, b) = (
            Vector3::from(check_direction(wi)?),
            Vector3::from(check_direction(wo)?),
        );
        // n: the unit normal of the great circle; F = [n x w, n, w] at both ends has x
        // along the circle, from w_i towards w_o at w_i and onwards at w_o.
        let cross = a.cross(&b);
        let s = cross.norm();
        let theta = s.atan2(a.dot(&b));
        let n = if s > DEGENERATE_SIN {
            cross / s
        } else {
            Frame::from_z(wi)?.y()
        };
        let frame = |w: &Vector3<f64>| {
            let x = n.cross(w);
            Frame::new([x.x, x.y, x.z], [n.x, n.y, n.z], [w.x, w.y, w.z])
        };
        Ok(MuellerTransform::new(
            MuellerMatrix::from_rows(self.value(theta)?)?,
            frame(&a)?,
            frame(&b)?,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_interpolate_and_reject_bad_samples() {
        let n = 5;
        let theta: Vec<f64> = (0..n).map(|i| PI * i as f64 / (n - 1) as f64).collect();
        let values: Vec<KernelValue> = theta.iter().map(|&t| [[PI - t; 4]; 4]).collect();
        let k = ConvolutionKernel::from_table(theta.clone(), values.clone()).unwrap();
        // Linear data is reproduced between the samples.
        assert!((k.value(1.0).unwrap()[2][3] - (PI - 1.0)).abs() < 1e-15);
        assert_eq!(k.samples(), Some(5));
        let mut swapped = theta.clone();
        swapped.swap(1, 2);
        let e = ConvolutionKernel::from_table(swapped, values.clone()).unwrap_err();
        assert!(e.to_string().contains("strictly increasing"), "{e}");
        let e =
            ConvolutionKernel::from_table(theta[..4].to_vec(), values[..4].to_vec()).unwrap_err();
        assert!(e.to_string().contains("cover [0, pi]"), "{e}");
        let e = ConvolutionKernel::from_table(theta.clone(), values[..4].to_vec()).unwrap_err();
        assert!(e.to_string().contains("5 angles, 4 values"), "{e}");
        let mut nan = values.clone();
        nan[3][1][2] = f64::NAN;
        let e = ConvolutionKernel::from_table(theta, nan).unwrap_err();
        assert!(e.to_string().contains("k(theta[3])"), "{e}");
        let e = k.value(4.0).unwrap_err();
        assert!(e.to_string().contains("4"), "{e}");
    }

    /// With `w_i` at the pole the frames are the theta-phi frames of PSH (61).
    #[test]
    fn frames_follow_the_great_circle() {
        use crate::geometry::frame::{FrameField, ThetaPhiFrameField};
        let value = |t: f64| -> KernelValue {
            std::array::from_fn(|r| std::array::from_fn(|c| (1 + r * 4 + c) as f64 * (1.0 + t)))
        };
        let k = ConvolutionKernel::from_fn(value);
        let (t, p) = (0.8f64, 2.1f64);
        let wo = [t.sin() * p.cos(), t.sin() * p.sin(), t.cos()];
        let m = k.transform([0.0, 0.0, 1.0], wo).unwrap();
        let fo = ThetaPhiFrameField::new().frame(wo).unwrap();
        let fi = ThetaPhiFrameField::new().frame_at_angles(0.0, p).unwrap();
        let got = m.matrix_in(&fi, &fo).unwrap();
        for r in 0..4 {
            for c in 0..4 {
                let want = value(t)[r][c];
                assert!((got.get(r, c).unwrap() - want).abs() < 1e-14);
            }
        }
    }
}
