//! Oracle for the Cartesian gradients and Hessians of the real SH (SHH Sec. 4), in
//! arbitrary precision, independent of the recurrences of [`crate::sh::evaluation::solid`].
//!
//! The function is the degree-0 extension `Y_lm(x) = Y_lm(x / |x|)` of psh's real SH
//! (PSH (12)), differentiated at the point `x` given as f64 (used exactly). Nothing of
//! SHH (13), (17)-(19) or the Hessian relation of SHH Sec. 4.2 is used: the value is the
//! explicit polynomial
//! `Y_lm(X) = N_lm (-1)^m {Re, Im} (X + i Y)^m 2^-l sum_k (-1)^k C(l,k) C(2l-2k,l)
//! (l-2k)!/(l-2k-m)! Z^{l-2k-m}` (the explicit sum of `P_l` differentiated `m` times,
//! Fungrim 7a85b7 and DLMF 14.6.1, with `sin^m theta e^{i m phi} = (X + iY)^m`), where
//! `(X, Y, Z) = x / |x|`, `N_lm = A_lm` for `m = 0` and `sqrt(2) A_lm` otherwise; the
//! derivatives come from forward-mode automatic differentiation to second order
//! ([`Jet`]) through `|x|^-1 = s^{-1/2}`, `s = x^2 + y^2 + z^2`.
//!
//! Precision: the sum cancels (its terms reach about `(1 + sqrt 2)^l` times the result),
//! so the working precision must exceed `64 + 1.3 l` bits for a 64-bit result; callers
//! pass it, and the tests compare two precisions. Not certified (unlike
//! [`super::legendre`]); see `proofs/sh-hessian.md`.

use crate::sh::evaluation::solid::{hessian_index, HESSIAN_ENTRIES};
use crate::sh::num_coeffs;
use rug::float::Constant;
use rug::{Float, Integer};

/// Value, gradient and packed Hessian (order [`HESSIAN_ENTRIES`]) of a function of
/// `(x, y, z)` at one point: a second-order jet.
#[derive(Clone, Debug)]
pub struct Jet {
    /// `f(x)`.
    pub value: Float,
    /// `(df/dx, df/dy, df/dz)`.
    pub gradient: [Float; 3],
    /// Second derivatives, packed as [`HESSIAN_ENTRIES`].
    pub hessian: [Float; 6],
}

impl Jet {
    /// The constant `c`.
    pub fn constant(prec: u32, c: &Float) -> Self {
        Self {
            value: Float::with_val(prec, c),
            gradient: std::array::from_fn(|_| Float::new(prec)),
            hessian: std::array::from_fn(|_| Float::new(prec)),
        }
    }

    /// The coordinate function `x_i` at the value `x` (exact).
    pub fn variable(prec: u32, x: f64, i: usize) -> Self {
        let mut j = Self::constant(prec, &Float::with_val(prec, x));
        j.gradient[i] = Float::with_val(prec, 1);
        j
    }

    fn prec(&self) -> u32 {
        self.value.prec()
    }

    /// `self + other`.
    pub fn add(&self, other: &Self) -> Self {
        let p = self.prec();
        Self {
            value: Float::with_val(p, &self.value + &other.value),
            gradient: std::array::from_fn(|i| {
                Float::with_val(p, &self.gradient[i] + &other.gradient[i])
            }),
            hessian: std::array::from_fn(|i| {
                Float::with_val(p, &self.hessian[i] + &other.hessian[i])
            }),
        }
    }

    /// `c self`.
    pub fn scale(&self, c: &Float) -> Self {
        let p = self.prec();
        Self {
            value: Float::with_val(p, &self.value * c),
            gradient: std::array::from_fn(|i| Float::with_val(p, &self.gradient[i] * c)),
            hessian: std::array::from_fn(|i| Float::with_val(p, &self.hessian[i] * c)),
        }
    }

    /// `self * other` (product rule to second order).
    pub fn mul(&self, other: &Self) -> Self {
        let p = self.prec();
        let (a, b) = (self, other);
        Self {
            value: Float::with_val(p, &a.value * &b.value),
            gradient: std::array::from_fn(|i| {
                Float::with_val(p, &a.value * &b.gradient[i])
                    + Float::with_val(p, &b.value * &a.gradient[i])
            }),
            hessian: std::array::from_fn(|k| {
                let (i, j) = HESSIAN_ENTRIES[k];
                let mut h = Float::with_val(p, &a.value * &b.hessian[k]);
                h += Float::with_val(p, &b.value * &a.hessian[k]);
                h += Float::with_val(p, &a.gradient[i] * &b.gradient[j]);
                h += Float::with_val(p, &a.gradient[j] * &b.gradient[i]);
                h
            }),
        }
    }

    /// `f(self)` given `f, f', f''` at `self.value` (chain rule to second order).
    pub fn map(&self, f0: Float, f1: &Float, f2: &Float) -> Self {
        let p = self.prec();
        Self {
            value: f0,
            gradient: std::array::from_fn(|i| Float::with_val(p, &self.gradient[i] * f1)),
            hessian: std::array::from_fn(|k| {
                let (i, j) = HESSIAN_ENTRIES[k];
                let mut h = Float::with_val(p, &self.hessian[k] * f1);
                let gg = Float::with_val(p, &self.gradient[i] * &self.gradient[j]);
                h += gg * f2;
                h
            }),
        }
    }

    /// Entry `(i, j)` of the Hessian.
    pub fn hessian_entry(&self, i: usize, j: usize) -> &Float {
        &self.hessian[hessian_index(i, j)]
    }
}

/// Jets of the real SH `Y_lm(x / |x|)` for all `l <= lmax` at the point `x`, in flat
/// order `l*l + l + m`, computed with `prec` bits (see the module documentation for the
/// precision needed).
pub fn sh_jets(lmax: usize, x: [f64; 3], prec: u32) -> Vec<Jet> {
    let vars: [Jet; 3] = std::array::from_fn(|i| Jet::variable(prec, x[i], i));
    let s = vars
        .iter()
        .map(|v| v.mul(v))
        .reduce(|a, b| a.add(&b))
        .expect("three coordinates");
    // s^{-1/2} and its first two derivatives -s^{-3/2}/2, 3 s^{-5/2}/4.
    let inv_r = Float::with_val(prec, s.value.recip_sqrt_ref());
    let inv_s = Float::with_val(prec, s.value.recip_ref());
    let f1 = Float::with_val(prec, &inv_r * &inv_s) * -0.5f64;
    let f2 = Float::with_val(prec, &f1 * &inv_s) * -1.5f64;
    let inv = s.map(inv_r, &f1, &f2);
    let [xn, yn, zn] = vars.map(|v| v.mul(&inv));
    let one = Float::with_val(prec, 1);
    let mut zpow = vec![Jet::constant(prec, &one)];
    for j in 1..=lmax {
        let next = zpow[j - 1].mul(&zn);
        zpow.push(next);
    }
    // (X + iY)^m as (Re, Im) jets.
    let mut cis = vec![(
        Jet::constant(prec, &one),
        Jet::constant(prec, &Float::new(prec)),
    )];
    for m in 1..=lmax {
        let (c, s) = &cis[m - 1];
        let re = c
            .mul(&xn)
            .add(&s.mul(&yn).scale(&Float::with_val(prec, -1)));
        let im = s.mul(&xn).add(&c.mul(&yn));
        cis.push((re, im));
    }
    let four_pi = Float::with_val(prec, Constant::Pi) * 4u32;
    let mut out = vec![Jet::constant(prec, &Float::new(prec)); num_coeffs(lmax)];
    for l in 0..=lmax {
        for m in 0..=l {
            let mut poly = Jet::constant(prec, &Float::new(prec));
            for k in 0..=(l - m) / 2 {
                let mut c = Integer::from(Integer::binomial_u(l as u32, k as u32))
                    * Integer::from(Integer::binomial_u((2 * l - 2 * k) as u32, l as u32));
                for f in (l - 2 * k - m + 1)..=(l - 2 * k) {
                    c *= f as u32;
                }
                if k % 2 == 1 {
                    c = -c;
                }
                let c = Float::with_val(prec, &c) >> (l as u32);
                poly = poly.add(&zpow[l - 2 * k - m].scale(&c));
            }
            // N_lm (-1)^m with A_lm = sqrt((2l+1)/(4 pi) (l-m)!/(l+m)!).
            let ratio = Float::with_val(prec, Integer::from(Integer::factorial((l - m) as u32)))
                / Float::with_val(prec, Integer::from(Integer::factorial((l + m) as u32)));
            let mut norm = (ratio * (2 * l + 1) as u32 / &four_pi).sqrt();
            if m > 0 {
                norm *= Float::with_val(prec, 2).sqrt();
            }
            if m % 2 == 1 {
                norm = -norm;
            }
            let base = poly.scale(&norm);
            if m == 0 {
                out[l * l + l] = base;
            } else {
                out[l * l + l + m] = base.mul(&cis[m].0);
                out[l * l + l - m] = base.mul(&cis[m].1);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{direction, direction_angles};
    use crate::sh::evaluation::harmonics::sh_real;
    use crate::sh::evaluation::solid::SolidHarmonics;

    /// Directions of the tests: poles, 1e-8 from a pole, generic.
    fn dirs() -> Vec<[f64; 3]> {
        vec![
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
            direction(1e-8, 0.7),
            direction(0.3, 1.1),
            direction(std::f64::consts::FRAC_PI_2, -2.0),
            direction(2.5, 2.9),
        ]
    }

    /// The oracle's values agree with psh's real SH, and two working precisions agree.
    #[test]
    fn oracle_is_self_consistent_and_matches_sh_real() {
        let lmax = 30;
        for w in dirs() {
            let a = sh_jets(lmax, w, 200);
            let b = sh_jets(lmax, w, 320);
            let (t, p) = direction_angles(w).unwrap();
            let r = sh_real(lmax, t, p).unwrap();
            for (k, (a, b)) in a.iter().zip(&b).enumerate() {
                assert!((a.value.to_f64() - r[k]).abs() < 1e-14, "{k}");
                for (x, y) in a.hessian.iter().zip(&b.hessian) {
                    let d = Float::with_val(320, x - y).abs().to_f64();
                    assert!(d < 1e-40, "{k} {d}");
                }
            }
        }
    }

    /// f64 gradients and Hessians of `psh::sh::evaluation::solid` against the oracle, every `l <= 50`
    /// and every `m`: absolute errors relative to `(l + 1)^2` (the size of the Hessians),
    /// and the SHH Table 1 mean squared error of the Hessians up to each order.
    #[test]
    fn solid_matches_exact_oracle() {
        let lmax = 50;
        let sh = SolidHarmonics::new(lmax).unwrap();
        let n = sh.len();
        let (mut v, mut g, mut h) = (vec![0.0; n], vec![[0.0; 3]; n], vec![[0.0; 6]; n]);
        let mut sq = vec![0.0f64; lmax + 1];
        let mut count = vec![0usize; lmax + 1];
        for w in dirs() {
            sh.eval(w, &mut v, &mut g, &mut h).unwrap();
            let ex = sh_jets(lmax, w, 256);
            for l in 0..=lmax {
                let scale = ((l + 1) * (l + 1)) as f64;
                for k in l * l..(l + 1) * (l + 1) {
                    let e = &ex[k];
                    assert!(
                        (v[k] - e.value.to_f64()).abs() < 1e-13,
                        "value {w:?} {k} {} {}",
                        v[k],
                        e.value.to_f64()
                    );
                    for i in 0..3 {
                        let d = (g[k][i] - e.gradient[i].to_f64()).abs();
                        assert!(d < 1e-13 * scale, "grad {w:?} {k} {i} {d}");
                    }
                    for (i, x) in e.hessian.iter().enumerate() {
                        let d = (h[k][i] - x.to_f64()).abs();
                        assert!(d < 1e-13 * scale, "hess {w:?} {k} {i} {d}");
                        sq[l] += d * d;
                        count[l] += 1;
                    }
                }
            }
        }
        for order in [4usize, 8, 12, 16, 20, 30, 50] {
            let mse =
                sq[..=order].iter().sum::<f64>() / count[..=order].iter().sum::<usize>() as f64;
            eprintln!("order {order}: Hessian MSE {mse:e}");
            assert!(mse < 1e-20, "order {order}: MSE {mse:e}");
        }
    }
}
