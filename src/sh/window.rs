//! Windowed band limits: per-degree factors `w_l` that taper a band-limited expansion
//! `sum_{l <= L} w_l f_l` instead of cutting it (Sloan 2008, *Stupid Spherical Harmonics
//! (SH) Tricks*, Sec. "Windowing", after Lanczos' sigma factors). Applied to a field's
//! coefficients they are a convolution with the zonal kernel
//! `K(gamma) = sum_l w_l (2l+1)/(4 pi) P_l(cos gamma)` (Funk-Hecke, [`super::funk_hecke`]);
//! a per-degree scaling commutes with rotations and with the polarized convolution
//! theorem, spin 0 and spin 2 (`proofs/windowed-band-limits.md`).

use std::f64::consts::PI;

/// A window over the degrees `0..=L` (PSH Sec. 8.2 leaves deringing open; the sources
/// are named per variant).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Window {
    /// `w_l = 1`: the plain cut.
    #[default]
    None,
    /// `w_l = (1 + cos(pi l / (L + 1))) / 2` (Hann; Sloan 2008).
    Hann,
    /// `w_l = sinc(pi l / (L + 1))`, `sinc x = sin x / x` (Lanczos' sigma factors; Sloan
    /// 2008).
    Lanczos,
}

crate::named_enum!(Window, "window", { None => "none", Hann => "hann", Lanczos => "lanczos" });

impl Window {
    /// The factor of degree `l` in a window over `0..=lmax` (0 above `lmax`).
    pub fn factor(self, l: usize, lmax: usize) -> f64 {
        if l > lmax {
            return 0.0;
        }
        let x = PI * l as f64 / (lmax + 1) as f64;
        match self {
            Window::None => 1.0,
            Window::Hann => 0.5 * (1.0 + x.cos()),
            Window::Lanczos if l == 0 => 1.0,
            Window::Lanczos => x.sin() / x,
        }
    }

    /// The factors `w_0 ..= w_lmax`.
    pub fn factors(self, lmax: usize) -> Vec<f64> {
        (0..=lmax).map(|l| self.factor(l, lmax)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Closed forms at the ends and the middle: `w_0 = 1` (the mean is kept), Hann
    /// `1/2` and Lanczos `2/pi` at `l = (L + 1)/2`, both positive and decreasing.
    #[test]
    fn factors_in_closed_form() {
        let lmax = 9;
        for w in [Window::Hann, Window::Lanczos] {
            let f = w.factors(lmax);
            assert_eq!(f[0], 1.0);
            assert!(
                f.windows(2).all(|p| p[1] < p[0] && p[1] > 0.0),
                "{w}: {f:?}"
            );
            assert_eq!(w.factor(lmax + 1, lmax), 0.0);
        }
        assert!((Window::Hann.factor(5, lmax) - 0.5).abs() < 1e-15);
        assert!((Window::Lanczos.factor(5, lmax) - 2.0 / PI).abs() < 1e-15);
        assert!(Window::None.factors(lmax).iter().all(|&x| x == 1.0));
        for w in Window::ALL {
            assert_eq!(Window::from_name(w.name()).unwrap(), w);
        }
        assert!(Window::from_name("hamming").is_err());
    }
}
