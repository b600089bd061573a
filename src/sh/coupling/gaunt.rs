//! Gaunt coefficients: integrals of products of three spherical harmonics, complex
//! (PSH (1)) and real (PSH (12)), from the Wigner 3j symbols of [`crate::sh::coupling::wigner3j`].
//!
//! # Conventions
//! * Complex SH: `Y_lm = A_lm P_l^m(cos theta) e^{i m phi}` with the Condon-Shortley
//!   phase `(-1)^m` inside `P_l^m` (PSH (1)). Hence `conj(Y_lm) = (-1)^m Y_{l,-m}`.
//! * Real SH (PSH (12)), written as a unitary change of basis `Y^R_lm = sum_mu U_{m mu} Y_{l mu}`:
//!
//!   | `m`   | `U_{m,m}`          | `U_{m,-m}`        | meaning                 |
//!   |-------|--------------------|-------------------|-------------------------|
//!   | `> 0` | `1/sqrt 2`         | `(-1)^m/sqrt 2`   | `sqrt 2 Re Y_{lm}`      |
//!   | `= 0` | `1`                | (same entry)      | `Y_{l0}`                |
//!   | `< 0` | `i (-1)^m/sqrt 2`  | `-i/sqrt 2`       | `sqrt 2 Im Y_{l,abs(m)}`|
//!
//!   The real SH therefore carry the Condon-Shortley sign, e.g.
//!   `Y^R_{1,1} = -sqrt(3/(4 pi)) sin(theta) cos(phi)`.
//!
//! # What is computed
//! * [`gaunt`]: `G(l1 m1, l2 m2, l3 m3) = ∫ Y_{l1 m1} Y_{l2 m2} Y_{l3 m3} dω`;
//!   [`gaunt_product`]: `∫ conj(Y_{lm}) Y_{l1 m1} Y_{l2 m2} dω`, the coupling of a product of
//!   two complex SH expansions (PSH (55));
//!   [`real_gaunt`]: `∫ Y^R_{l1 m1} Y^R_{l2 m2} Y^R_{l3 m3} dω`.
//! * Tables of every coupling of two expansions: [`crate::sh::coupling::gaunt_table`].
//!
//! Degrees up to [`MAX_GAUNT_DEGREE`](crate::sh::MAX_GAUNT_DEGREE) are accepted; the coefficients add a few roundings to
//! the 3j symbols' (relative error below `1e-15`).

use crate::error::Result;
use crate::sh::coupling::wigner3j::{check_degree_order, triangle, wigner_3j_checked};
use num_complex::Complex64;

/// `1/sqrt(4 pi)`, the constant of DLMF §34.3(vii) (Gaunt's integral).
const INV_SQRT_4PI: f64 = 0.282_094_791_773_878_14;

/// `sqrt((2l1+1)(2l2+1)(2l3+1)/(4 pi))` (DLMF §34.3(vii)).
pub(super) fn gaunt_prefactor(l1: usize, l2: usize, l3: usize) -> f64 {
    (((2 * l1 + 1) * (2 * l2 + 1) * (2 * l3 + 1)) as f64).sqrt() * INV_SQRT_4PI
}

/// Complex Gaunt coefficient
/// `G(l1 m1, l2 m2, l3 m3) = ∫_{S^2} Y_{l1 m1} Y_{l2 m2} Y_{l3 m3} dω
///  = sqrt((2l1+1)(2l2+1)(2l3+1)/(4 pi)) (l1 l2 l3; 0 0 0) (l1 l2 l3; m1 m2 m3)`
/// (DLMF §34.3(vii), Gaunt's integral), for the SH of PSH (1) (Condon-Shortley phase
/// included). No conjugation: for the coupling of a product use [`gaunt_product`].
///
/// Exact zero unless `m1+m2+m3 = 0`, the triangle condition holds and `l1+l2+l3` is even.
/// Errors: [`crate::Error::DegreeOutOfRange`] (degree above [`MAX_GAUNT_DEGREE`](crate::sh::MAX_GAUNT_DEGREE)),
/// [`crate::Error::OrderOutOfRange`] (`|m_i| > l_i`).
pub fn gaunt(l1: usize, m1: i64, l2: usize, m2: i64, l3: usize, m3: i64) -> Result<f64> {
    check_degree_order("l1", "m1", l1, m1)?;
    check_degree_order("l2", "m2", l2, m2)?;
    check_degree_order("l3", "m3", l3, m3)?;
    let mut buf = Vec::new();
    Ok(gaunt_checked(l1, m1, l2, m2, l3, m3, &mut buf))
}

fn gaunt_checked(
    l1: usize,
    m1: i64,
    l2: usize,
    m2: i64,
    l3: usize,
    m3: i64,
    buf: &mut Vec<f64>,
) -> f64 {
    if m1 + m2 + m3 != 0 || !triangle(l1, l2, l3) || (l1 + l2 + l3) % 2 == 1 {
        return 0.0;
    }
    let w0 = wigner_3j_checked(l1, 0, l2, 0, l3, 0, buf);
    let wm = if m1 == 0 && m2 == 0 {
        w0
    } else {
        wigner_3j_checked(l1, m1, l2, m2, l3, m3, buf)
    };
    gaunt_prefactor(l1, l2, l3) * w0 * wm
}

/// Product-form Gaunt coefficient `∫_{S^2} conj(Y_{lm}) Y_{l1 m1} Y_{l2 m2} dω
/// = (-1)^m G(l1 m1, l2 m2, l -m)` (using `conj(Y_lm) = (-1)^m Y_{l,-m}`, PSH (1) with the
/// Condon-Shortley phase). It is the coefficient of `Y_lm` in the product
/// `Y_{l1 m1} Y_{l2 m2}`, i.e. the spin-0 triple product of PSH (55): for
/// `f = sum a_{l1 m1} Y_{l1 m1}`, `g = sum b_{l2 m2} Y_{l2 m2}`,
/// `(f g)_{lm} = sum a_{l1 m1} b_{l2 m2} gaunt_product(l, m, l1, m1, l2, m2)`.
///
/// Exact zero unless `m = m1 + m2`, the triangle condition holds and `l+l1+l2` is even.
/// Errors as [`gaunt`].
pub fn gaunt_product(l: usize, m: i64, l1: usize, m1: i64, l2: usize, m2: i64) -> Result<f64> {
    check_degree_order("l", "m", l, m)?;
    check_degree_order("l1", "m1", l1, m1)?;
    check_degree_order("l2", "m2", l2, m2)?;
    let mut buf = Vec::new();
    let g = gaunt_checked(l1, m1, l2, m2, l, -m, &mut buf);
    Ok(if m.rem_euclid(2) == 1 { -g } else { g })
}

/// Reduction of a real Gaunt coefficient to a single complex one.
///
/// With `Y^R_{lm} = sum_mu U_{m mu} Y_{l mu}` (PSH (12)),
/// `R(l1 m1, l2 m2, l3 m3) = sum_{mu1 mu2 mu3} U_{m1 mu1} U_{m2 mu2} U_{m3 mu3} G(l1 mu1, l2 mu2, l3 mu3)`,
/// with `mu_i = ±|m_i|` and `mu1+mu2+mu3 = 0`. Only one pattern `mu` and its negative `-mu`
/// satisfy the sum rule (if all `m_i != 0`, exactly one `|m_i|` is the sum of the other
/// two), and `G(-mu) = G(mu)` whenever `l1+l2+l3` is even (DLMF 34.3.10, the only case in
/// which `G != 0`). So `R = c G(l1 mu1, l2 mu2, l3 mu3)` with `c = U(mu) + U(-mu)`, which is
/// `0` if an odd number of the `m_i` are negative (the integrand is then odd under
/// `phi -> -phi`), and otherwise `±1/sqrt 2` (three nonzero `m_i`) or `±1` (one `m_i` zero,
/// or all zero). Returns the canonical pattern (first nonzero `mu` positive) and `c`, or
/// `None` when `R` vanishes by these selection rules.
pub(super) fn real_coupling(m: [i64; 3]) -> Option<([i64; 3], f64)> {
    let negatives = m.iter().filter(|&&x| x < 0).count();
    if negatives % 2 == 1 {
        return None;
    }
    let a = m.map(i64::abs);
    let mut total = Complex64::new(0.0, 0.0);
    let mut pattern: Option<[i64; 3]> = None;
    for signs in 0..8u32 {
        let mut mu = [0i64; 3];
        let mut skip = false;
        for i in 0..3 {
            let negative = signs & (1 << i) != 0;
            if negative && a[i] == 0 {
                skip = true; // mu_i = 0 is counted once
            }
            mu[i] = if negative { -a[i] } else { a[i] };
        }
        if skip || mu.iter().sum::<i64>() != 0 {
            continue;
        }
        let canonical = match mu.iter().find(|&&x| x != 0) {
            Some(&x) if x < 0 => mu.map(|v| -v),
            _ => mu,
        };
        debug_assert!(pattern.is_none() || pattern == Some(canonical));
        pattern = Some(canonical);
        total += crate::sh::evaluation::harmonics::real_from_complex(m[0], mu[0])
            * crate::sh::evaluation::harmonics::real_from_complex(m[1], mu[1])
            * crate::sh::evaluation::harmonics::real_from_complex(m[2], mu[2]);
    }
    let pattern = pattern?;
    let nonzero = a.iter().filter(|&&x| x != 0).count();
    let magnitude = if nonzero == 3 {
        std::f64::consts::FRAC_1_SQRT_2
    } else {
        1.0
    };
    // |total| is exactly 0 or `magnitude` (up to rounding); its imaginary part vanishes.
    debug_assert!(total.im.abs() < 1e-12);
    if total.re.abs() < 0.5 * magnitude {
        return None;
    }
    Some((pattern, magnitude.copysign(total.re)))
}

/// Real Gaunt coefficient `∫_{S^2} Y^R_{l1 m1} Y^R_{l2 m2} Y^R_{l3 m3} dω` for the real SH of
/// PSH (12) (which include the Condon-Shortley sign).
///
/// Derived from the complex ones through the unitary change of basis
/// `Y^R_{lm} = sum_mu U_{m mu} Y_{l mu}` of PSH (12) (see the module documentation):
/// `R = sum_{mu} U_{m1 mu1} U_{m2 mu2} U_{m3 mu3} G(l1 mu1, l2 mu2, l3 mu3)`. The sum collapses
/// to `c G(l1 mu1, l2 mu2, l3 mu3)` for the single pattern `mu_i = ±|m_i|` with
/// `mu1+mu2+mu3 = 0`, with `c in {±1, ±1/sqrt 2}`; see `proofs/wigner3j-recursion.md`.
/// Being an integral of real functions it is symmetric in its three `(l, m)` pairs, and since
/// `Y^R` is real it is also the coefficient of `Y^R_{l3 m3}` in `Y^R_{l1 m1} Y^R_{l2 m2}`.
///
/// Exact zero unless the triangle condition holds, `l1+l2+l3` is even, an even number of the
/// `m_i` are negative, and one `|m_i|` is the sum of the other two.
/// Errors as [`gaunt`].
pub fn real_gaunt(l1: usize, m1: i64, l2: usize, m2: i64, l3: usize, m3: i64) -> Result<f64> {
    check_degree_order("l1", "m1", l1, m1)?;
    check_degree_order("l2", "m2", l2, m2)?;
    check_degree_order("l3", "m3", l3, m3)?;
    if !triangle(l1, l2, l3) || (l1 + l2 + l3) % 2 == 1 {
        return Ok(0.0);
    }
    let Some((mu, c)) = real_coupling([m1, m2, m3]) else {
        return Ok(0.0);
    };
    let mut buf = Vec::new();
    Ok(c * gaunt_checked(l1, mu[0], l2, mu[1], l3, mu[2], &mut buf))
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::error::Error;
    use crate::random::pseudo_random;
    use crate::sh::coupling::wigner3j::tests::pick;
    use crate::sh::index::lm_of_index;

    /// A polynomial in (x, y, z) on the unit sphere: (exponents, complex coefficient).
    pub(crate) type Poly = Vec<([u32; 3], Complex64)>;

    fn mono(c: Complex64, e: [u32; 3]) -> Poly {
        vec![(e, c)]
    }

    pub(crate) fn poly_mul(p: &Poly, q: &Poly) -> Poly {
        let mut r = Vec::new();
        for (ea, ca) in p {
            for (eb, cb) in q {
                r.push(([ea[0] + eb[0], ea[1] + eb[1], ea[2] + eb[2]], ca * cb));
            }
        }
        r
    }

    /// ∫_{S^2} x^a y^b z^c dω = 4 pi (a-1)!! (b-1)!! (c-1)!! / (a+b+c+1)!! for a, b, c even,
    /// zero otherwise.
    pub(crate) fn integrate(p: &Poly) -> Complex64 {
        let dfact = |n: i64| -> f64 {
            let mut r = 1.0;
            let mut k = n;
            while k > 1 {
                r *= k as f64;
                k -= 2;
            }
            r
        };
        let mut s = Complex64::new(0.0, 0.0);
        for (e, c) in p {
            if e.iter().any(|&k| k % 2 == 1) {
                continue;
            }
            let (a, b, cc) = (e[0] as i64, e[1] as i64, e[2] as i64);
            let v = 4.0 * std::f64::consts::PI * dfact(a - 1) * dfact(b - 1) * dfact(cc - 1)
                / dfact(a + b + cc + 1);
            s += c * v;
        }
        s
    }

    /// Complex Y_lm (PSH (1), Condon-Shortley phase) for l <= 2, written out by hand from
    /// the textbook table of spherical harmonics, as polynomials in x, y, z.
    fn complex_y(l: usize, m: i64) -> Poly {
        use std::f64::consts::PI;
        let c = |re: f64, im: f64| Complex64::new(re, im);
        let x = [1, 0, 0];
        let y = [0, 1, 0];
        let z = [0, 0, 1];
        match (l, m) {
            (0, 0) => mono(c(0.5 / PI.sqrt(), 0.0), [0, 0, 0]),
            (1, 0) => mono(c((3.0 / (4.0 * PI)).sqrt(), 0.0), z),
            (1, 1) | (1, -1) => {
                // Y_11 = -sqrt(3/8pi)(x + i y), Y_1-1 = +sqrt(3/8pi)(x - i y)
                let k = (3.0 / (8.0 * PI)).sqrt();
                let s = if m == 1 { -1.0 } else { 1.0 };
                let iy = if m == 1 { 1.0 } else { -1.0 };
                vec![(x, c(s * k, 0.0)), (y, c(0.0, s * k * iy))]
            }
            (2, 0) => {
                let k = 0.25 * (5.0 / PI).sqrt();
                vec![([0, 0, 2], c(3.0 * k, 0.0)), ([0, 0, 0], c(-k, 0.0))]
            }
            (2, 1) | (2, -1) => {
                // Y_21 = -(1/2) sqrt(15/2pi) z (x + i y), Y_2-1 = +(1/2) sqrt(15/2pi) z (x - i y)
                let k = 0.5 * (15.0 / (2.0 * PI)).sqrt();
                let s = if m == 1 { -1.0 } else { 1.0 };
                let iy = if m == 1 { 1.0 } else { -1.0 };
                vec![([1, 0, 1], c(s * k, 0.0)), ([0, 1, 1], c(0.0, s * k * iy))]
            }
            (2, 2) | (2, -2) => {
                // Y_2±2 = (1/4) sqrt(15/2pi) (x ± i y)^2
                let k = 0.25 * (15.0 / (2.0 * PI)).sqrt();
                let iy = if m == 2 { 1.0 } else { -1.0 };
                vec![
                    ([2, 0, 0], c(k, 0.0)),
                    ([0, 2, 0], c(-k, 0.0)),
                    ([1, 1, 0], c(0.0, 2.0 * k * iy)),
                ]
            }
            _ => unreachable!(),
        }
    }

    /// Real Y^R_lm of PSH (12) for l <= 2, written out by hand (Condon-Shortley sign kept).
    pub(crate) fn real_y(l: usize, m: i64) -> Poly {
        use std::f64::consts::PI;
        let r = |v: f64| Complex64::new(v, 0.0);
        match (l, m) {
            (0, 0) => mono(r(0.5 / PI.sqrt()), [0, 0, 0]),
            (1, -1) => mono(r(-(3.0 / (4.0 * PI)).sqrt()), [0, 1, 0]),
            (1, 0) => mono(r((3.0 / (4.0 * PI)).sqrt()), [0, 0, 1]),
            (1, 1) => mono(r(-(3.0 / (4.0 * PI)).sqrt()), [1, 0, 0]),
            (2, -2) => mono(r(0.5 * (15.0 / PI).sqrt()), [1, 1, 0]),
            (2, -1) => mono(r(-0.5 * (15.0 / PI).sqrt()), [0, 1, 1]),
            (2, 0) => {
                let k = 0.25 * (5.0 / PI).sqrt();
                vec![([0, 0, 2], r(3.0 * k)), ([0, 0, 0], r(-k))]
            }
            (2, 1) => mono(r(-0.5 * (15.0 / PI).sqrt()), [1, 0, 1]),
            (2, 2) => {
                let k = 0.25 * (15.0 / PI).sqrt();
                vec![([2, 0, 0], r(k)), ([0, 2, 0], r(-k))]
            }
            _ => unreachable!(),
        }
    }

    #[test]
    fn gaunt_matches_polynomial_integrals() {
        let mut max_err: f64 = 0.0;
        let mut nonzero = 0;
        for i1 in 0..9 {
            for i2 in 0..9 {
                for i3 in 0..9 {
                    let (l1, m1) = lm_of_index(i1);
                    let (l2, m2) = lm_of_index(i2);
                    let (l3, m3) = lm_of_index(i3);
                    let pc = poly_mul(
                        &poly_mul(&complex_y(l1, m1), &complex_y(l2, m2)),
                        &complex_y(l3, m3),
                    );
                    let ec = integrate(&pc);
                    assert!(ec.im.abs() < 1e-15);
                    let gc = gaunt(l1, m1, l2, m2, l3, m3).unwrap();
                    max_err = max_err.max((gc - ec.re).abs());
                    // Product form: ∫ conj(Y_l3m3) Y_l1m1 Y_l2m2.
                    let conj3: Poly = complex_y(l3, m3)
                        .into_iter()
                        .map(|(e, c)| (e, c.conj()))
                        .collect();
                    let ep = integrate(&poly_mul(
                        &poly_mul(&complex_y(l1, m1), &complex_y(l2, m2)),
                        &conj3,
                    ));
                    let gp = gaunt_product(l3, m3, l1, m1, l2, m2).unwrap();
                    max_err = max_err.max((gp - ep.re).abs());
                    // Real.
                    let pr = poly_mul(&poly_mul(&real_y(l1, m1), &real_y(l2, m2)), &real_y(l3, m3));
                    let er = integrate(&pr).re;
                    let gr = real_gaunt(l1, m1, l2, m2, l3, m3).unwrap();
                    max_err = max_err.max((gr - er).abs());
                    if er.abs() > 1e-12 {
                        nonzero += 1;
                    } else {
                        assert_eq!(gr, 0.0, "real ({l1},{m1}) ({l2},{m2}) ({l3},{m3})");
                    }
                    if ec.re.abs() <= 1e-12 {
                        assert_eq!(gc, 0.0);
                    }
                }
            }
        }
        assert!(nonzero > 50);
        assert!(max_err < 2e-16 * 8.0, "max error {max_err:e}");
    }

    #[test]
    fn known_values() {
        // ∫ Y^R_11 Y^R_11 Y^R_20 = -(2/5) sqrt(5/(16 pi)) (hand integration of x^2 (3z^2 - 1)).
        let e = -0.4 * (5.0 / (16.0 * std::f64::consts::PI)).sqrt();
        assert!((real_gaunt(1, 1, 1, 1, 2, 0).unwrap() - e).abs() < 1e-16);
        // ∫ Y_00 Y_lm Y_l-m = (-1)^m / sqrt(4 pi), for large l too.
        for &(l, m) in &[(0usize, 0i64), (5, 3), (100, -77), (4000, 4000)] {
            let g = gaunt(0, 0, l, m, l, -m).unwrap();
            let s = if m.rem_euclid(2) == 0 { 1.0 } else { -1.0 };
            assert!((g - s * INV_SQRT_4PI).abs() < 1e-15, "l={l} m={m}: {g}");
            let r = real_gaunt(l, m, 0, 0, l, m).unwrap();
            assert!((r - INV_SQRT_4PI).abs() < 1e-15, "l={l} m={m}: {r}");
        }
    }

    /// A-priori bound on |G| (complex or real): the prefactor of DLMF §34.3(vii) times the
    /// bound 1/sqrt(2 l + 1) on each of the two 3j symbols.
    fn gaunt_bound(l: [usize; 3]) -> f64 {
        let lmax = l[0].max(l[1]).max(l[2]);
        gaunt_prefactor(l[0], l[1], l[2]) / (2 * lmax + 1) as f64
    }

    #[test]
    fn real_gaunt_is_symmetric() {
        let mut count = 0;
        for x in pseudo_random(6 * 100_000, 4).chunks(6) {
            if count == 500 {
                break;
            }
            let l = [pick(x[0], 0, 30), pick(x[1], 0, 30), pick(x[2], 0, 30)];
            let m = [
                pick(x[3], -l[0], l[0]),
                pick(x[4], -l[1], l[1]),
                pick(x[5], -l[2], l[2]),
            ];
            let u = l.map(|v| v as usize);
            let v = real_gaunt(u[0], m[0], u[1], m[1], u[2], m[2]).unwrap();
            if v == 0.0 {
                continue;
            }
            count += 1;
            for p in [[1, 2, 0], [2, 0, 1], [1, 0, 2], [0, 2, 1], [2, 1, 0]] {
                let w = real_gaunt(u[p[0]], m[p[0]], u[p[1]], m[p[1]], u[p[2]], m[p[2]]).unwrap();
                assert!(
                    (w - v).abs() <= 4.0 * f64::EPSILON * v.abs() + 1e-28 * gaunt_bound(u),
                    "{l:?} {m:?} perm {p:?}: {w} vs {v}"
                );
            }
        }
        assert_eq!(count, 500);
    }

    #[test]
    fn selection_rules_give_exact_zeros() {
        assert_eq!(gaunt(1, 0, 1, 0, 1, 0).unwrap(), 0.0);
        assert_eq!(gaunt(2, 1, 3, 1, 4, -1).unwrap(), 0.0);
        assert_eq!(gaunt(2, 1, 3, -1, 6, 0).unwrap(), 0.0);
        assert_eq!(gaunt(2, 1, 3, -1, 4, 0).unwrap(), 0.0); // odd l-sum with nonzero m
        assert_eq!(gaunt_product(4, 1, 2, 1, 2, 1).unwrap(), 0.0);
        assert_eq!(real_gaunt(1, 1, 1, -1, 2, 1).unwrap(), 0.0); // odd number of negative m
        assert_eq!(real_gaunt(2, 1, 2, 1, 2, 1).unwrap(), 0.0); // no |m_i| = sum of the others
        assert_eq!(real_gaunt(3, 1, 2, 2, 2, 0).unwrap(), 0.0);
    }

    #[test]
    fn bad_input_is_an_error() {
        assert!(matches!(
            gaunt(2, 0, 2, 3, 2, 0),
            Err(Error::OrderOutOfRange { .. })
        ));
        assert!(matches!(
            gaunt_product(1, 2, 1, 1, 1, 1),
            Err(Error::OrderOutOfRange { name: "m", .. })
        ));
        assert!(matches!(
            real_gaunt(0, 0, usize::MAX, 0, 0, 0),
            Err(Error::DegreeOutOfRange { .. })
        ));
        assert!(matches!(
            real_gaunt(2, i64::MIN, 2, 0, 2, 0),
            Err(Error::OrderOutOfRange { .. })
        ));
    }
}
