//! [`GauntTable`]: every nonzero Gaunt coupling needed to multiply two band-limited SH
//! expansions, complex ([`crate::sh::coupling::gaunt::gaunt_product`]) or real
//! ([`crate::sh::coupling::gaunt::real_gaunt`]); the sparse tensor behind SH products and the spin-0
//! triple products of PSH (55).

use crate::error::{Error, Result};
use crate::sh::coupling::gaunt::{gaunt_prefactor, real_coupling};
use crate::sh::coupling::wigner3j::{row_unchecked, MAX_GAUNT_DEGREE};
use crate::sh::index::{lm_index, num_coeffs};
use std::ops::{Add, Mul};

/// Largest `lmax_a`, `lmax_b` accepted by [`GauntTable::new`]. The table holds
/// `O(lmax_a^2 lmax_b^2 min(lmax_a, lmax_b))` entries of 24 bytes; for the real basis with
/// `lmax_a = lmax_b = L`, `lmax_out = 2L`: 4.4·10^4 entries for `L = 8`, 1.1·10^6 for
/// `L = 16`, roughly 3.5·10^7 (0.8 GB) for `L = 32`.
pub const MAX_TABLE_DEGREE: usize = 32;

/// Which spherical harmonics a [`GauntTable`] couples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GauntBasis {
    /// Complex SH of PSH (1): entries `∫ conj(Y_out) Y_a Y_b` ([`gaunt_product`](crate::sh::coupling::gaunt::gaunt_product)).
    Complex,
    /// Real SH of PSH (12): entries `∫ Y^R_out Y^R_a Y^R_b` ([`real_gaunt`](crate::sh::coupling::gaunt::real_gaunt)).
    Real,
}

/// One nonzero coupling: `(f g)_out += value * f_a * g_b`. Indices are flat SH indices
/// `l*l + l + m` ([`crate::sh::lm_index`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GauntEntry {
    /// Flat index of the output harmonic.
    pub out: u32,
    /// Flat index of the harmonic of the first factor.
    pub a: u32,
    /// Flat index of the harmonic of the second factor.
    pub b: u32,
    /// The Gaunt coefficient.
    pub value: f64,
}

/// Every nonzero Gaunt coefficient coupling two band-limited SH expansions
/// (`l_a <= lmax_a`, `l_b <= lmax_b`) into their product truncated at `lmax_out`; the sparse
/// tensor behind SH products and the spin-0 triple products of PSH (55).
///
/// For `f = sum_a f_a Y_a`, `g = sum_b g_b Y_b` the product has coefficients
/// `(f g)_out = sum_{(out, a, b)} value * f_a * g_b` ([`GauntTable::product`]), exactly for
/// `lmax_out >= lmax_a + lmax_b`. Entries are sorted by `(out, a, b)`. Built from one 3j row per
/// `(l_a, l_b, m_a, m_b)` (cost about that of the entries themselves).
#[derive(Clone, Debug)]
pub struct GauntTable {
    basis: GauntBasis,
    lmax_a: usize,
    lmax_b: usize,
    lmax_out: usize,
    entries: Vec<GauntEntry>,
}

impl GauntTable {
    /// Builds the table. Errors: [`Error::DegreeOutOfRange`] if `lmax_a` or `lmax_b` exceeds
    /// [`MAX_TABLE_DEGREE`] or `lmax_out` exceeds [`MAX_GAUNT_DEGREE`].
    pub fn new(basis: GauntBasis, lmax_a: usize, lmax_b: usize, lmax_out: usize) -> Result<Self> {
        for (name, v) in [("lmax_a", lmax_a), ("lmax_b", lmax_b)] {
            if v > MAX_TABLE_DEGREE {
                return Err(Error::DegreeOutOfRange {
                    name,
                    value: v as i128,
                    reason: format!(
                        "Gaunt tables are limited to degree {MAX_TABLE_DEGREE} per factor"
                    ),
                });
            }
        }
        if lmax_out > MAX_GAUNT_DEGREE {
            return Err(Error::DegreeOutOfRange {
                name: "lmax_out",
                value: lmax_out as i128,
                reason: format!("the largest degree supported is {MAX_GAUNT_DEGREE}"),
            });
        }
        let mut entries = Vec::new();
        let mut w0 = Vec::new();
        let mut scratch = Vec::new();
        // rows[(mu1 + l1) * (2 l2 + 1) + (mu2 + l2)] = (l3_min, row) for the complex pattern.
        let mut rows: Vec<Option<(usize, Vec<f64>)>> = Vec::new();
        for l1 in 0..=lmax_a {
            for l2 in 0..=lmax_b {
                let lo = l1.abs_diff(l2);
                if lo > lmax_out {
                    continue;
                }
                let hi = (l1 + l2).min(lmax_out);
                let w0_min = row_unchecked(l1, 0, l2, 0, &mut w0);
                let width = 2 * l2 + 1;
                rows.clear();
                rows.resize((2 * l1 + 1) * width, None);
                let row =
                    |mu1: i64, mu2: i64, rows: &mut Vec<Option<(usize, Vec<f64>)>>| -> usize {
                        let key = (mu1 + l1 as i64) as usize * width + (mu2 + l2 as i64) as usize;
                        if rows[key].is_none() {
                            let mut v = Vec::new();
                            let min = row_unchecked(l1, mu1, l2, mu2, &mut v);
                            rows[key] = Some((min, v));
                        }
                        key
                    };
                for m1 in -(l1 as i64)..=l1 as i64 {
                    for m2 in -(l2 as i64)..=l2 as i64 {
                        let ia = lm_index(l1, m1) as u32;
                        let ib = lm_index(l2, m2) as u32;
                        // (output order m3, pattern (mu1, mu2), coefficient) triples.
                        scratch.clear();
                        match basis {
                            GauntBasis::Complex => {
                                let m = m1 + m2;
                                let sign = if m.rem_euclid(2) == 1 { -1.0 } else { 1.0 };
                                scratch.push((m, m1, m2, sign));
                            }
                            GauntBasis::Real => {
                                let (a, b) = (m1.abs(), m2.abs());
                                let mut cands = [a + b, -(a + b), (a - b).abs(), -(a - b).abs()];
                                cands.sort_unstable();
                                for (i, &m3) in cands.iter().enumerate() {
                                    if i > 0 && cands[i - 1] == m3 {
                                        continue;
                                    }
                                    if let Some((mu, c)) = real_coupling([m1, m2, m3]) {
                                        scratch.push((m3, mu[0], mu[1], c));
                                    }
                                }
                            }
                        }
                        for &(m3, mu1, mu2, c) in &scratch {
                            let l3_first = lo.max(m3.unsigned_abs() as usize);
                            if l3_first > hi {
                                continue;
                            }
                            let key = row(mu1, mu2, &mut rows);
                            let (rmin, r) = rows[key].as_ref().expect("row computed above");
                            // l1 + l2 + l3 even.
                            let mut l3 = l3_first + (l1 + l2 + l3_first) % 2;
                            while l3 <= hi {
                                let value = c
                                    * gaunt_prefactor(l1, l2, l3)
                                    * w0[l3 - w0_min]
                                    * r[l3 - rmin];
                                if value != 0.0 {
                                    entries.push(GauntEntry {
                                        out: lm_index(l3, m3) as u32,
                                        a: ia,
                                        b: ib,
                                        value,
                                    });
                                }
                                l3 += 2;
                            }
                        }
                    }
                }
            }
        }
        entries.sort_unstable_by_key(|e| (e.out, e.a, e.b));
        Ok(GauntTable {
            basis,
            lmax_a,
            lmax_b,
            lmax_out,
            entries,
        })
    }

    /// The basis the table couples.
    pub fn basis(&self) -> GauntBasis {
        self.basis
    }
    /// Band limit of the first factor.
    pub fn lmax_a(&self) -> usize {
        self.lmax_a
    }
    /// Band limit of the second factor.
    pub fn lmax_b(&self) -> usize {
        self.lmax_b
    }
    /// Band limit of the (truncated) product.
    pub fn lmax_out(&self) -> usize {
        self.lmax_out
    }
    /// The nonzero couplings, sorted by `(out, a, b)`.
    pub fn entries(&self) -> &[GauntEntry] {
        &self.entries
    }
    /// Number of nonzero couplings.
    pub fn len(&self) -> usize {
        self.entries.len()
    }
    /// Whether the table has no entries.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Coefficients of the product `f g` (length `(lmax_out+1)^2`) from those of `f`
    /// (length `(lmax_a+1)^2`) and `g` (length `(lmax_b+1)^2`), in the table's basis. Works for
    /// real (`f64`) and complex (`Complex64`) coefficients alike.
    /// Errors: [`Error::LengthMismatch`].
    pub fn product<T>(&self, a: &[T], b: &[T]) -> Result<Vec<T>>
    where
        T: Copy + Default + Add<Output = T> + Mul<Output = T> + Mul<f64, Output = T>,
    {
        crate::error::check_len("a", num_coeffs(self.lmax_a), a.len())?;
        crate::error::check_len("b", num_coeffs(self.lmax_b), b.len())?;
        let mut out = vec![T::default(); num_coeffs(self.lmax_out)];
        for e in &self.entries {
            let o = &mut out[e.out as usize];
            *o = *o + a[e.a as usize] * b[e.b as usize] * e.value;
        }
        Ok(out)
    }

    /// The matrix of multiplication by `f`: `M[out][j] = sum_a f_a C(out, a, j)`, row-major
    /// with `(lmax_out+1)^2` rows and `(lmax_b+1)^2` columns, so that `(f g)_out = sum_j M[out][j] g_j`.
    /// With `f` a visibility this is the spin-0 shadowing transfer matrix of PSH (55).
    /// Errors: [`Error::LengthMismatch`].
    pub fn product_matrix<T>(&self, a: &[T]) -> Result<Vec<T>>
    where
        T: Copy + Default + Add<Output = T> + Mul<Output = T> + Mul<f64, Output = T>,
    {
        crate::error::check_len("a", num_coeffs(self.lmax_a), a.len())?;
        let nb = num_coeffs(self.lmax_b);
        let mut m = vec![T::default(); num_coeffs(self.lmax_out) * nb];
        for e in &self.entries {
            let o = &mut m[e.out as usize * nb + e.b as usize];
            *o = *o + a[e.a as usize] * e.value;
        }
        Ok(m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::pseudo_random;
    use crate::sh::coupling::gaunt::tests::{integrate, poly_mul, real_y, Poly};
    use crate::sh::coupling::gaunt::{gaunt_product, real_gaunt};
    use crate::sh::index::lm_of_index;
    use num_complex::Complex64;

    #[test]
    fn bad_input_is_an_error() {
        assert!(GauntTable::new(GauntBasis::Real, MAX_TABLE_DEGREE + 1, 1, 2).is_err());
        let t = GauntTable::new(GauntBasis::Real, 1, 1, 2).unwrap();
        assert!(matches!(
            t.product(&[1.0; 3], &[1.0; 4]),
            Err(Error::LengthMismatch { name: "a", .. })
        ));
    }

    #[test]
    fn tables_hold_exactly_the_nonzero_couplings() {
        use std::collections::HashMap;
        for basis in [GauntBasis::Complex, GauntBasis::Real] {
            let (la, lb, lo) = (4usize, 3usize, 6usize);
            let t = GauntTable::new(basis, la, lb, lo).unwrap();
            let e = t.entries();
            assert!(e
                .windows(2)
                .all(|w| (w[0].out, w[0].a, w[0].b) < (w[1].out, w[1].a, w[1].b)));
            let map: HashMap<(usize, usize, usize), f64> = e
                .iter()
                .map(|x| ((x.out as usize, x.a as usize, x.b as usize), x.value))
                .collect();
            let mut nonzero = 0;
            for out in 0..num_coeffs(lo) {
                for a in 0..num_coeffs(la) {
                    for b in 0..num_coeffs(lb) {
                        let (l, m) = lm_of_index(out);
                        let (l1, m1) = lm_of_index(a);
                        let (l2, m2) = lm_of_index(b);
                        let v = match basis {
                            GauntBasis::Complex => gaunt_product(l, m, l1, m1, l2, m2).unwrap(),
                            GauntBasis::Real => real_gaunt(l, m, l1, m1, l2, m2).unwrap(),
                        };
                        // Selection rules, written out independently.
                        let tri = l1.abs_diff(l2) <= l && l <= l1 + l2 && (l + l1 + l2) % 2 == 0;
                        let allowed = tri
                            && match basis {
                                GauntBasis::Complex => m == m1 + m2,
                                GauntBasis::Real => {
                                    let neg = [m, m1, m2].iter().filter(|&&x| x < 0).count();
                                    let (x, y, z) = (m.abs(), m1.abs(), m2.abs());
                                    neg % 2 == 0 && (x == y + z || y == x + z || z == x + y)
                                }
                            };
                        match map.get(&(out, a, b)) {
                            // Values agree; nontrivial zeros such as (3 3 2; -2 2 0) = 0 come
                            // out at rounding level (or exactly zero) in either computation.
                            Some(&tv) => {
                                assert!(allowed, "{basis:?}: entry {out} {a} {b} not allowed");
                                assert!((tv - v).abs() <= 1e-15, "{basis:?} {out} {a} {b}");
                                nonzero += 1;
                            }
                            None => {
                                assert!(v.abs() <= 1e-15, "{basis:?}: missing {out} {a} {b}");
                                if !allowed {
                                    assert_eq!(v, 0.0);
                                }
                            }
                        }
                    }
                }
            }
            assert_eq!(nonzero, e.len());
        }
    }

    #[test]
    fn table_product_reproduces_triple_integrals() {
        // For band-limited f, g (l <= 2) and h (l <= 2), ∫ f g h = sum_k (f g)_k h_k, with all
        // three written as hand polynomials and integrated exactly.
        let t = GauntTable::new(GauntBasis::Real, 2, 2, 4).unwrap();
        let (f, g, h) = (
            pseudo_random(9, 1),
            pseudo_random(9, 2),
            pseudo_random(9, 3),
        );
        let expand = |c: &[f64]| -> Poly {
            let mut p = Vec::new();
            for (i, &ci) in c.iter().enumerate() {
                let (l, m) = lm_of_index(i);
                for (e, v) in real_y(l, m) {
                    p.push((e, v * ci));
                }
            }
            p
        };
        let exact = integrate(&poly_mul(&poly_mul(&expand(&f), &expand(&g)), &expand(&h))).re;
        let fg = t.product(&f, &g).unwrap();
        let via_table: f64 = (0..9).map(|k| fg[k] * h[k]).sum();
        assert!((via_table - exact).abs() < 1e-14, "{via_table} vs {exact}");
        // The multiplication matrix agrees with the product.
        let m = t.product_matrix(&f).unwrap();
        for (o, &fgo) in fg.iter().enumerate() {
            let v: f64 = (0..9).map(|j| m[o * 9 + j] * g[j]).sum();
            assert!((v - fgo).abs() < 1e-15);
        }
        // Complex coefficients through the same table.
        let fc: Vec<Complex64> = f.iter().map(|&v| Complex64::new(v, -v)).collect();
        let gc: Vec<Complex64> = g.iter().map(|&v| Complex64::new(0.0, v)).collect();
        let fgc = t.product(&fc, &gc).unwrap();
        for (k, v) in fgc.iter().enumerate() {
            // (1 - i) f * i g = (1 + i) f g
            assert!((v - Complex64::new(fg[k], fg[k])).norm() < 1e-15);
        }
    }
}
