//! Tabulated (measured) pBRDFs: Mueller matrices on a grid of Rusinkiewicz angles
//! `(phi_d, theta_d, theta_h)` per wavelength, in the layout of the KAIST dataset (Baek et
//! al. 2020) and of Mitsuba 3's `measured_polarized` tables (`.pbsdf`,
//! [`crate::io::read_pbsdf`]).
//!
//! **Angles** (Rusinkiewicz 1998, with `i = w_i` towards the light, `o = w_o` towards the
//! viewer, `n = z`): `h = normalize(i + o)`, `theta_h = acos(h_z)`, `theta_d = acos(h . i)`,
//! `b = normalize(n x h)`, `t = normalize(b x h)`, `phi_d = atan2(b . i, t . i)` in
//! `(-pi, pi]`, as Mitsuba's plugin computes them. At `h = n` (`theta_h = 0`, a set of
//! measure zero where `b` is undefined) `t = x`, `b = y` are taken.
//!
//! **Values**: the pBRDF `f` without the cosine, linearly interpolated in each angle
//! between the table's samples and clamped at its ends; a NaN (a sample the measurement
//! marks invalid) among the eight surrounding samples gives the zero matrix; `f_00` is
//! clamped at 0; then `P = f cos theta_i` (Mitsuba's `measured_polarized`, so that both
//! renderers see one function). Zero below the horizon.
//!
//! **Frames** (`proofs/tabulated-pbrdf-frames.md`): a table's Mueller matrices map
//! Stokes vectors in the frame `[x, (-w_i) x x, -w_i]` (z along the incident light's
//! travel) to `[x, w_o x x, w_o]`, `x = normalize(w_i x w_o)` (the sign of `x` does not
//! change Stokes components). psh's input frames have `z = w_i`: `[x, w_i x x, w_i]`, so
//! `[P]_psh = [P]_table D` with `D = diag(1, 1, -1, -1)`, in the frames of
//! [`super::sp_frames`].

use super::microfacet::{sp_frames_unit, unit_pair};
use crate::error::{check_len, Error, Result};
use crate::stokes::{MuellerField, MuellerMatrix, MuellerTransform};
use nalgebra::{Matrix4, Vector3};

/// A measured pBRDF table (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct TabulatedPbrdf {
    phi_d: Vec<f64>,
    theta_d: Vec<f64>,
    theta_h: Vec<f64>,
    wavelengths_nm: Vec<f64>,
    /// `[phi_d][theta_d][theta_h][wavelength][row][column]`, row-major.
    values: Vec<f64>,
}

impl TabulatedPbrdf {
    /// A table from its axes (radians, strictly increasing, finite; `phi_d` within
    /// `[-pi, pi]`, `theta_d` and `theta_h` within `[0, pi/2]`), its wavelengths (nm) and
    /// its Mueller matrices `[phi_d][theta_d][theta_h][wavelength][4][4]` in the table's
    /// frames (finite, or NaN for invalid samples). Errors name the axis or the count; a
    /// table of NaN alone is an error.
    pub fn new(
        phi_d: Vec<f64>,
        theta_d: Vec<f64>,
        theta_h: Vec<f64>,
        wavelengths_nm: Vec<f64>,
        values: Vec<f64>,
    ) -> Result<Self> {
        use std::f64::consts::{FRAC_PI_2, PI};
        check_axis("phi_d", &phi_d, -PI, PI)?;
        check_axis("theta_d", &theta_d, 0.0, FRAC_PI_2)?;
        check_axis("theta_h", &theta_h, 0.0, FRAC_PI_2)?;
        if wavelengths_nm.is_empty() || wavelengths_nm.iter().any(|w| !(*w > 0.0 && w.is_finite()))
        {
            return Err(Error::invalid(
                "wavelengths",
                format!("{wavelengths_nm:?}"),
                "at least one, each positive and finite (nm)",
            ));
        }
        let count = [
            phi_d.len(),
            theta_d.len(),
            theta_h.len(),
            wavelengths_nm.len(),
            16,
        ]
        .iter()
        .try_fold(1usize, |n, &d| n.checked_mul(d));
        if count != Some(values.len()) {
            return Err(Error::invalid(
                "Mueller table",
                format!("{} values", values.len()),
                format!(
                    "{} x {} x {} x {} x 4 x 4 (phi_d, theta_d, theta_h, wavelengths)",
                    phi_d.len(),
                    theta_d.len(),
                    theta_h.len(),
                    wavelengths_nm.len()
                ),
            ));
        }
        if values.iter().all(|v| v.is_nan()) {
            return Err(Error::invalid(
                "Mueller table",
                format!("{} values, every one NaN", values.len()),
                "at least one valid (non-NaN) sample",
            ));
        }
        if let Some(k) = values.iter().position(|v| v.is_infinite()) {
            return Err(Error::invalid(
                "Mueller table",
                format!("value {k} = {}", values[k]),
                "finite values, or NaN for invalid samples",
            ));
        }
        Ok(Self {
            phi_d,
            theta_d,
            theta_h,
            wavelengths_nm,
            values,
        })
    }

    /// The `phi_d` samples (radians).
    pub fn phi_d(&self) -> &[f64] {
        &self.phi_d
    }

    /// The `theta_d` samples (radians).
    pub fn theta_d(&self) -> &[f64] {
        &self.theta_d
    }

    /// The `theta_h` samples (radians).
    pub fn theta_h(&self) -> &[f64] {
        &self.theta_h
    }

    /// The wavelengths (nm).
    pub fn wavelengths_nm(&self) -> &[f64] {
        &self.wavelengths_nm
    }

    /// The stored values `[phi_d][theta_d][theta_h][wavelength][4][4]`.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The fraction of samples marked invalid (NaN).
    pub fn invalid_fraction(&self) -> f64 {
        let matrices = self.values.chunks_exact(16);
        let n = matrices.len().max(1);
        matrices.filter(|m| m.iter().any(|v| v.is_nan())).count() as f64 / n as f64
    }

    /// The table in linear sRGB (three channels), from the KAIST dataset's five bands
    /// 450, 500, 550, 600, 650 nm as the dataset's own code converts them (Baek et al.
    /// 2020, `spec2rgb.m`; polarsh `polar.py`): each Mueller entry is weighted by D65 times
    /// the CIE 1931 2-degree colour-matching functions at the bands (CIE 15:2004 tables),
    /// mapped from XYZ to linear sRGB (IEC 61966-2-1), each channel normalized so that a
    /// spectrally flat reflectance of 1 gives 1 ([`rgb_from_bands`]). NaN samples stay
    /// NaN. The channels R, G, B carry the nominal labels 611, 549 and 464 nm (names for
    /// the channels only: no computation uses them). Error: other wavelengths.
    pub fn to_rgb(&self) -> Result<Self> {
        if self.wavelengths_nm != KAIST_BANDS_NM {
            return Err(Error::invalid(
                "wavelengths",
                format!("{:?}", self.wavelengths_nm),
                format!("the KAIST bands {KAIST_BANDS_NM:?} nm for RGB"),
            ));
        }
        let w = rgb_from_bands();
        let mut values = Vec::with_capacity(self.values.len() / 5 * 3);
        for sample in self.values.chunks_exact(5 * 16) {
            for row in &w {
                values.extend(
                    (0..16).map(|e| (0..5).map(|b| row[b] * sample[b * 16 + e]).sum::<f64>()),
                );
            }
        }
        Self::new(
            self.phi_d.clone(),
            self.theta_d.clone(),
            self.theta_h.clone(),
            vec![611.0, 549.0, 464.0],
            values,
        )
    }

    /// The Mueller field of wavelength `k`. Error: `k` out of range.
    pub fn channel(&self, k: usize) -> Result<TabulatedChannel<'_>> {
        if k >= self.wavelengths_nm.len() {
            return Err(Error::invalid(
                "wavelength index",
                k.to_string(),
                format!("below {}", self.wavelengths_nm.len()),
            ));
        }
        Ok(TabulatedChannel { table: self, k })
    }

    /// The table of `fields` (one per wavelength of `wavelengths_nm`) sampled at the
    /// axes' every combination (`phi_h = 0`): `f = [P]_psh D / cos theta_i` in the table's
    /// frames (the inverse of [`TabulatedChannel`]'s reading); zero where `w_i` or `w_o`
    /// is at or below the horizon (cosine under 1e-6), as a measurement and
    /// Mitsuba 3's BSDFs give them, and where the half vector is undefined. Project such a
    /// table on a grid with no ring on the horizon
    /// ([`crate::polarized::horizon_free_grid`]). Errors: as [`Self::new`], a field's.
    pub fn sample(
        fields: &[&dyn MuellerField],
        phi_d: Vec<f64>,
        theta_d: Vec<f64>,
        theta_h: Vec<f64>,
        wavelengths_nm: Vec<f64>,
    ) -> Result<Self> {
        check_len("fields", wavelengths_nm.len(), fields.len())?;
        let n = crate::budget::check(
            "a sampled pBRDF table",
            &[phi_d.len(), theta_d.len(), theta_h.len(), fields.len(), 16],
            8,
        )?;
        let mut values = Vec::with_capacity(n);
        for &pd in &phi_d {
            for &td in &theta_d {
                for &th in &theta_h {
                    let (i, o) = rusinkiewicz_directions(pd, td, th);
                    for field in fields {
                        values.extend(sample_one(*field, &i, &o)?.transpose().iter());
                    }
                }
            }
        }
        Self::new(phi_d, theta_d, theta_h, wavelengths_nm, values)
    }

    /// The table's matrix at `(phi_d, theta_d, theta_h)` for wavelength `k`, in its
    /// frames, without the cosine: trilinear between the samples, clamped at the ends; the
    /// zero matrix if one of the eight samples is NaN.
    pub fn lookup(&self, k: usize, phi_d: f64, theta_d: f64, theta_h: f64) -> Matrix4<f64> {
        let (a, b, c) = (
            bracket(&self.phi_d, phi_d),
            bracket(&self.theta_d, theta_d),
            bracket(&self.theta_h, theta_h),
        );
        let (nd, nh, nw) = (
            self.theta_d.len(),
            self.theta_h.len(),
            self.wavelengths_nm.len(),
        );
        let mut out = Matrix4::zeros();
        for (ia, wa) in [(a.0, 1.0 - a.2), (a.1, a.2)] {
            for (ib, wb) in [(b.0, 1.0 - b.2), (b.1, b.2)] {
                for (ic, wc) in [(c.0, 1.0 - c.2), (c.1, c.2)] {
                    let at = ((((ia * nd) + ib) * nh + ic) * nw + k) * 16;
                    let m = &self.values[at..at + 16];
                    if m.iter().any(|v| v.is_nan()) {
                        return Matrix4::zeros();
                    }
                    let w = wa * wb * wc;
                    if w != 0.0 {
                        out += Matrix4::from_row_slice(m) * w;
                    }
                }
            }
        }
        out
    }
}

/// The KAIST dataset's bands (nm).
pub const KAIST_BANDS_NM: [f64; 5] = [450.0, 500.0, 550.0, 600.0, 650.0];

/// CIE D65 relative spectral power at [`KAIST_BANDS_NM`] (CIE 15:2004, Table T.1, as
/// the dataset's code stores it, in single precision).
const D65: [f64; 5] = [117.008003, 109.353996, 104.045998, 90.006203, 80.026802];

/// CIE 1931 2-degree colour-matching functions `(x, y, z)` at [`KAIST_BANDS_NM`]
/// (CIE 15:2004, Table T.4; `z(450)` as the dataset's code has it).
const CMF: [[f64; 3]; 5] = [
    [0.3362, 0.0380, 1.77211],
    [0.0049, 0.3230, 0.2720],
    [0.4334499, 0.994950, 0.008750],
    [1.0622, 0.6310, 0.0008],
    [0.2835, 0.1070, 0.0],
];

/// XYZ to linear sRGB (IEC 61966-2-1).
const XYZ_TO_SRGB: [[f64; 3]; 3] = [
    [3.2406, -1.5372, -0.4986],
    [-0.9689, 1.8758, 0.0415],
    [0.0557, -0.2040, 1.0570],
];

/// The weights `W[c][b]` of [`TabulatedPbrdf::to_rgb`]: `S = XYZ_TO_SRGB CMF^T`,
/// `W[c][b] = S[c][b] D65[b] / sum_b' S[c][b'] D65[b']` (each row sums to 1).
pub fn rgb_from_bands() -> [[f64; 5]; 3] {
    std::array::from_fn(|c| {
        let s: [f64; 5] = std::array::from_fn(|b| {
            (0..3).map(|k| XYZ_TO_SRGB[c][k] * CMF[b][k]).sum::<f64>() * D65[b]
        });
        let total: f64 = s.iter().sum();
        s.map(|x| x / total)
    })
}

/// Checks a table axis: at least one sample, finite, strictly increasing, within
/// `[lo, hi]` (to rounding of `f32` storage, `1e-6`).
fn check_axis(name: &'static str, axis: &[f64], lo: f64, hi: f64) -> Result<()> {
    let ok = !axis.is_empty()
        && axis
            .iter()
            .all(|x| x.is_finite() && *x >= lo - 1e-6 && *x <= hi + 1e-6)
        && axis.windows(2).all(|w| w[0] < w[1]);
    if ok {
        return Ok(());
    }
    Err(Error::invalid(
        "table axis",
        format!("{name} = {}", crate::error::clip(&format!("{axis:?}"))),
        format!("finite, strictly increasing samples in [{lo:.6}, {hi:.6}] radians"),
    ))
}

/// The samples around `x` and the weight of the upper one: `(j, j + 1, t)`, clamped to the
/// ends (`(0, 0, 0)` below the first, `(n - 1, n - 1, 0)` above the last).
fn bracket(axis: &[f64], x: f64) -> (usize, usize, f64) {
    let n = axis.len();
    if n == 1 || x.is_nan() || x <= axis[0] {
        return (0, 0, 0.0);
    }
    if x >= axis[n - 1] {
        return (n - 1, n - 1, 0.0);
    }
    // The first sample above x; 1 <= j < n.
    let j = axis.partition_point(|&a| a <= x);
    let t = (x - axis[j - 1]) / (axis[j] - axis[j - 1]);
    (j - 1, j, t)
}

/// The Rusinkiewicz angles `(phi_d, theta_d, theta_h)` of unit directions `i` (towards
/// the light) and `o` (towards the viewer), as the module doc defines them; `None` when
/// `i + o` vanishes (grazing, opposite directions: no half vector).
pub fn rusinkiewicz(i: &Vector3<f64>, o: &Vector3<f64>) -> Option<(f64, f64, f64)> {
    let v = i + o;
    if v.amax() < 1e-12 {
        return None;
    }
    let h = (v / v.amax()).normalize();
    let theta_h = h[2].clamp(-1.0, 1.0).acos();
    let theta_d = h.dot(i).clamp(-1.0, 1.0).acos();
    let n = Vector3::z();
    let c = n.cross(&h);
    let (t, b) = if c.amax() > 1e-300 {
        let b = (c / c.amax()).normalize();
        (b.cross(&h).normalize(), b)
    } else {
        (Vector3::x(), Vector3::y())
    };
    let phi_d = b.dot(i).atan2(t.dot(i));
    Some((phi_d, theta_d, theta_h))
}

/// Unit `i` (towards the light) and `o` (towards the viewer) with Rusinkiewicz angles
/// `(phi_d, theta_d, theta_h)` and `phi_h = 0` (the inverse of [`rusinkiewicz`]).
pub fn rusinkiewicz_directions(
    phi_d: f64,
    theta_d: f64,
    theta_h: f64,
) -> (Vector3<f64>, Vector3<f64>) {
    let h = Vector3::new(theta_h.sin(), 0.0, theta_h.cos());
    // b = normalize(n x h) = y, t = b x h (x at theta_h = 0 as well).
    let b = Vector3::y();
    let t = b.cross(&h);
    let (sd, cd) = theta_d.sin_cos();
    let i = t * (sd * phi_d.cos()) + b * (sd * phi_d.sin()) + h * cd;
    let o = h * (2.0 * h.dot(&i)) - i;
    (i.normalize(), o.normalize())
}

/// The table entry `f = [P]_psh D / cos theta_i` of `field` at `(i, o)`: zero with a
/// direction at or below the horizon (cosine under [`HORIZON_COSINE`]: the samples on
/// `theta_d + theta_h = pi/2` at `phi_d = 0` lie on the horizon to rounding, where
/// `P / cos theta_i` would be `0 / 0`; above it the half vector is defined). (An even continuation
/// below the horizon, mirroring each direction above it, was tried: at `theta_d = pi/2`
/// it puts the mirror configuration's specular peak, and where `f` diverges at grazing
/// a huge value, into samples whose cells reach the upper hemisphere; projected at
/// `l = 19`, a GGX gold table then had directional albedos near 900, `psh verify`'s
/// `pbrdf.passivity_table`.)
fn sample_one(
    field: &dyn MuellerField,
    i: &Vector3<f64>,
    o: &Vector3<f64>,
) -> Result<Matrix4<f64>> {
    if i[2] < HORIZON_COSINE || o[2] < HORIZON_COSINE {
        return Ok(Matrix4::zeros());
    }
    let (fi, fo) = sp_frames_unit(i, o)?;
    let mut m = field.matrix_in(&fi, &fo)?.matrix();
    for r in 0..4 {
        m[(r, 2)] = -m[(r, 2)];
        m[(r, 3)] = -m[(r, 3)];
    }
    Ok(m / i[2])
}

/// Sampled directions of a smaller cosine are on or below the horizon: their entries are
/// zero.
const HORIZON_COSINE: f64 = 1e-6;

/// One wavelength of a [`TabulatedPbrdf`] as a Mueller field (a cosine-weighted pBRDF).
#[derive(Clone, Copy, Debug)]
pub struct TabulatedChannel<'a> {
    table: &'a TabulatedPbrdf,
    k: usize,
}

impl TabulatedChannel<'_> {
    /// `[P(w_i, w_o)]` in the frames of [`super::sp_frames`] for validated unit directions
    /// (see the module doc).
    fn matrix_unit(&self, wi: &Vector3<f64>, wo: &Vector3<f64>) -> Matrix4<f64> {
        if wi[2] <= 0.0 || wo[2] < 0.0 {
            return Matrix4::zeros();
        }
        let Some((phi_d, theta_d, theta_h)) = rusinkiewicz(wi, wo) else {
            return Matrix4::zeros();
        };
        let mut f = self.table.lookup(self.k, phi_d, theta_d, theta_h);
        f[(0, 0)] = f[(0, 0)].max(0.0);
        // The table's input frame has z = -w_i: D = diag(1, 1, -1, -1) on the right.
        for r in 0..4 {
            f[(r, 2)] = -f[(r, 2)];
            f[(r, 3)] = -f[(r, 3)];
        }
        f * wi[2]
    }
}

impl MuellerField for TabulatedChannel<'_> {
    /// `[P(w_i, w_o)]_{F_i -> F_o}` in the frames of [`super::sp_frames`]. Errors: a
    /// non-unit or non-finite direction.
    fn transform(&self, wi: [f64; 3], wo: [f64; 3]) -> Result<MuellerTransform> {
        let (wi, wo) = unit_pair(wi, wo)?;
        let m = self.matrix_unit(&wi, &wo);
        let (fi, fo) = sp_frames_unit(&wi, &wo)?;
        Ok(MuellerTransform::new(MuellerMatrix::new(m)?, fi, fo))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    /// Rusinkiewicz angles of a configuration built from them come back; `phi_d` spans
    /// `(-pi, pi]`.
    #[test]
    fn rusinkiewicz_angles_round_trip() {
        for &(pd, td, th) in &[
            (0.3, 0.4, 0.2),
            (-2.0, 1.0, 0.7),
            (3.0, 0.1, 1.2),
            (-0.5, 1.5, 0.05),
        ] {
            let (i, o) = rusinkiewicz_directions(pd, td, th);
            let (p, d, h) = rusinkiewicz(&i, &o).unwrap();
            assert!((p - pd).abs() < 1e-12 && (d - td).abs() < 1e-12 && (h - th).abs() < 1e-12);
        }
        assert!(rusinkiewicz(&Vector3::x(), &-Vector3::x()).is_none());
    }

    /// Interpolation is linear between samples, clamped outside, and a NaN sample zeroes
    /// the cells around it.
    #[test]
    fn lookup_interpolates_clamps_and_respects_invalid_samples() {
        let axis = |n: usize, lo: f64, hi: f64| -> Vec<f64> {
            (0..n)
                .map(|k| lo + (hi - lo) * k as f64 / (n - 1) as f64)
                .collect()
        };
        let (pd, td, th) = (
            axis(3, -PI, PI),
            axis(3, 0.0, FRAC_PI_2),
            axis(2, 0.0, FRAC_PI_2),
        );
        let mut values = Vec::new();
        for a in 0..3 {
            for b in 0..3 {
                for c in 0..2 {
                    // m_00 = a + 10 b + 100 c: linear in the indices.
                    let mut m = [0.0; 16];
                    m[0] = a as f64 + 10.0 * b as f64 + 100.0 * c as f64;
                    values.extend(m);
                }
            }
        }
        let mut table = TabulatedPbrdf::new(pd, td, th, vec![550.0], values).unwrap();
        let m = table.lookup(0, -PI / 2.0, FRAC_PI_2 / 4.0, FRAC_PI_2 * 0.75);
        assert!((m[(0, 0)] - (0.5 + 5.0 + 75.0)).abs() < 1e-12);
        let clamped = table.lookup(0, 10.0, -1.0, 5.0);
        assert_eq!(clamped[(0, 0)], 2.0 + 100.0);
        table.values[0] = f64::NAN;
        assert_eq!(table.lookup(0, -PI + 0.1, 0.1, 0.1), Matrix4::zeros());
        assert!(table.lookup(0, 0.1, 1.0, 0.1)[(0, 0)] > 0.0);
        assert!((table.invalid_fraction() - 1.0 / 18.0).abs() < 1e-15);
    }

    /// The RGB weights are polarsh's (its `polar.py` conversion evaluated in Python:
    /// R = [0.078712, -0.307345, -0.061290, 1.014646, 0.275276] etc.), and a spectrally
    /// flat table gives the same matrices in every channel.
    #[test]
    fn rgb_is_the_dataset_s_conversion() {
        let w = rgb_from_bands();
        let polarsh = [
            [0.078712, -0.307345, -0.061290, 1.014646, 0.275276],
            [-0.103612, 0.327786, 0.736739, 0.068061, -0.028974],
            [1.000216, 0.110088, -0.080052, -0.028060, -0.002192],
        ];
        for (a, b) in w.iter().flatten().zip(polarsh.iter().flatten()) {
            assert!((a - b).abs() < 2e-6, "{a} {b}");
        }
        let flat: Vec<f64> = (0..2 * 5 * 16)
            .map(|k| ((k % 16) as f64 - 4.0) * 0.1)
            .collect();
        let t = TabulatedPbrdf::new(
            vec![0.0],
            vec![0.1, 0.2],
            vec![0.0],
            KAIST_BANDS_NM.to_vec(),
            flat,
        )
        .unwrap();
        let rgb = t.to_rgb().unwrap();
        assert_eq!(rgb.wavelengths_nm().len(), 3);
        for (k, v) in rgb.values().iter().enumerate() {
            assert!((v - ((k % 16) as f64 - 4.0) * 0.1).abs() < 1e-12);
        }
        let other =
            TabulatedPbrdf::new(vec![0.0], vec![0.0], vec![0.0], vec![500.0], vec![0.0; 16]);
        assert!(other.unwrap().to_rgb().is_err());
    }

    /// Bad axes, counts and infinite values are errors naming them.
    #[test]
    fn bad_tables_are_errors() {
        let ok = || (vec![0.0, 1.0], vec![0.0, 1.0], vec![0.0, 1.0], vec![550.0]);
        let (p, d, h, w) = ok();
        let e = TabulatedPbrdf::new(p, d, h, w, vec![0.0; 10]).unwrap_err();
        assert!(e.to_string().contains("2 x 2 x 2 x 1"), "{e}");
        let (_, d, h, w) = ok();
        let e = TabulatedPbrdf::new(vec![1.0, 0.0], d, h, w, vec![0.0; 128]).unwrap_err();
        assert!(e.to_string().contains("phi_d"), "{e}");
        let (p, _, h, w) = ok();
        assert!(TabulatedPbrdf::new(p, vec![0.0, 2.0], h, w, vec![0.0; 128]).is_err());
        let (p, d, h, _) = ok();
        assert!(TabulatedPbrdf::new(p, d, h, vec![f64::NAN], vec![0.0; 128]).is_err());
        let (p, d, h, w) = ok();
        let mut v = vec![0.0; 128];
        v[7] = f64::INFINITY;
        assert!(TabulatedPbrdf::new(p, d, h, w, v).is_err());
        let (p, d, h, w) = ok();
        let e = TabulatedPbrdf::new(p, d, h, w, vec![f64::NAN; 128]).unwrap_err();
        assert!(e.to_string().contains("every one NaN"), "{e}");
        let (p, d, h, w) = ok();
        let t = TabulatedPbrdf::new(p, d, h, w, vec![0.0; 128]).unwrap();
        assert!(t.channel(1).is_err());
    }
}
