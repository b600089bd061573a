//! Shadowed transfer by triple products (PSH Sec. 6.3.4): the PSH coefficient matrix of
//! the operator `f -> V f` for a scalar visibility `V` given by real SH coefficients
//! (PSH (54)-(56); derivation in `proofs/triple-products.md`). The visibility is a scalar
//! field ([`PshVector`] of [`Codomain::Intensity`], one channel) with its own
//! [`super::FieldArgument`]; it multiplies fields indexed the same way (polarsh's
//! visibilities are functions of the travel direction, `(-1)^l` apart from psh's).
//!
//! - Spin 0-to-0 (`p_o = p_i` in `{0, 3}`): `sum v_{l'm'} int Y^R_{j_o} Y^R_{l'm'} Y^R_{j_i}`
//!   (real Gaunt coefficients, PSH (55)).
//! - Spin 2-to-2 (`p_o, p_i` in `{1, 2}`): `V` is a pure isomorphic part, so the block is
//!   `R(P~iso)` (`proofs/coefficient-matrices.md` (51a)) with
//!   `P~iso_{j_o j_i} = sum v_{l'm'} int conj(2Y_{j_o}) Y^R_{l'm'} 2Y_{j_i}` (PSH (56)).
//! - Spin 0-to-2 and 2-to-0 blocks vanish.

use super::{in_index_set, Codomain, PshMatrix, PshVector};
use crate::error::{Error, Result};
use crate::sh::coupling::wigner3j::wigner_3j_row_into;
use crate::sh::{check_lmax, lm_index, num_coeffs};
use crate::sh::{wigner_3j_row, GauntBasis, GauntTable};
use num_complex::Complex64;
use std::f64::consts::{FRAC_1_SQRT_2, PI};
use std::sync::{Arc, Mutex};

/// `(-1)^n`.
fn parity(n: i64) -> f64 {
    if n.rem_euclid(2) == 0 {
        1.0
    } else {
        -1.0
    }
}

/// `int conj(2Y_{lo mo}) Y_{l m} 2Y_{li mi} dw` for the complex SH of PSH (1) and the
/// `2Y` of `crate::swsh`: `(-1)^{mo} sqrt((2lo+1)(2l+1)(2li+1)/(4 pi))
/// (lo l li; -mo m mi) (lo l li; 2 0 -2)` (`proofs/triple-products.md` (T3)).
pub fn spin2_gaunt(lo: usize, mo: i64, l: usize, m: i64, li: usize, mi: i64) -> Result<f64> {
    for (name, lv, mv) in [("mo", lo, mo), ("m", l, m), ("mi", li, mi)] {
        crate::sh::check_lm(lv as i64, mv).map_err(|_| Error::OrderOutOfRange {
            name,
            l: lv as i64,
            m: mv,
        })?;
    }
    if lo < 2 || li < 2 || mi != mo - m {
        return Ok(0.0);
    }
    let a = wigner_3j_row(lo, -mo, l, m)?.get(li);
    let b = wigner_3j_row(lo, 2, l, 0)?.get(li);
    Ok(parity(mo) * prefactor(lo, l, li) * a * b)
}

/// `sqrt((2l1+1)(2l2+1)(2l3+1)/(4 pi))` (DLMF §34.3(vii)).
fn prefactor(l1: usize, l2: usize, l3: usize) -> f64 {
    (((2 * l1 + 1) * (2 * l2 + 1) * (2 * l3 + 1)) as f64 / (4.0 * PI)).sqrt()
}

/// Complex SH coefficients `c_{l mu}` of a real expansion `sum v_{lm} Y^R_{lm}` (PSH (12)):
/// `c_{l,mu} = (v_{l,mu} - i v_{l,-mu})/sqrt 2`, `c_{l,-mu} = (-1)^mu conj(c_{l,mu})` for
/// `mu > 0`, `c_{l0} = v_{l0}` (`proofs/triple-products.md` (T4)).
fn real_to_complex(v: &[f64], lmax: usize) -> Vec<Complex64> {
    let mut c = vec![Complex64::default(); v.len()];
    for l in 0..=lmax {
        c[lm_index(l, 0)] = Complex64::new(v[lm_index(l, 0)], 0.0);
        for mu in 1..=l as i64 {
            let (a, b) = (v[lm_index(l, mu)], v[lm_index(l, -mu)]);
            let z = Complex64::new(a, -b) * FRAC_1_SQRT_2;
            c[lm_index(l, mu)] = z;
            c[lm_index(l, -mu)] = z.conj() * parity(mu);
        }
    }
    c
}

/// One term of the spin 2-to-2 block: `P~iso[jo][ji] += value * c[lm]`.
#[derive(Clone, Copy, Debug)]
struct SpinEntry {
    jo: u32,
    ji: u32,
    lm: u32,
    value: f64,
}

/// Precomputed couplings for visibilities of degree `<= lv` and transfer matrices of band
/// limit `lmax`: build once, then [`TripleTable::transfer`] costs one pass over the
/// nonzero couplings.
#[derive(Clone, Debug)]
pub struct TripleTable {
    lv: usize,
    lmax: usize,
    scalar: GauntTable,
    spin: Vec<SpinEntry>,
    has_spin2: bool,
}

impl TripleTable {
    /// The couplings of PSH (55) (real Gaunt table) and PSH (56) (closed form (T5) of
    /// `proofs/triple-products.md`). Errors: `lv` or `lmax` beyond the Gaunt table limit
    /// ([`crate::sh::MAX_TABLE_DEGREE`]).
    pub fn new(lv: usize, lmax: usize) -> Result<Self> {
        Self::for_codomain(lv, lmax, Codomain::Full)
    }

    /// The couplings that act on `codomain`: PSH (56) only when it has `s1, s2` (scalar SH
    /// needs the real Gaunt table alone). Without them [`Self::transfer`] and
    /// [`Self::shadow`] of vectors with spin-2 components are errors.
    pub fn for_codomain(lv: usize, lmax: usize, codomain: Codomain) -> Result<Self> {
        check_lmax(lmax)?;
        let scalar = GauntTable::new(GauntBasis::Real, lv, lmax, lmax)?;
        let mut spin = Vec::new();
        let (mut row_m, mut row_s) = (Vec::new(), Vec::new());
        // No spin-2 degrees for scalar SH.
        let last = if codomain.has_spin2() { lmax } else { 1 };
        for lo in 2..=last {
            for l in 0..=lv {
                // (lo l li; 2 0 -2) for li = smin..=lo+l.
                let smin = wigner_3j_row_into(lo, 2, l, 0, &mut row_s)?;
                for mo in -(lo as i64)..=lo as i64 {
                    let jo = lm_index(lo, mo) as u32;
                    let sign = parity(mo);
                    for m in -(l as i64)..=l as i64 {
                        let mi = mo - m;
                        // (lo l li; -mo m mi) for li = mmin..=lo+l.
                        let mmin = wigner_3j_row_into(lo, -mo, l, m, &mut row_m)?;
                        let first = mmin.max(smin).max(2).max(mi.unsigned_abs() as usize);
                        for li in first..=lmax.min(lo + l) {
                            let value =
                                sign * prefactor(lo, l, li) * row_m[li - mmin] * row_s[li - smin];
                            if value != 0.0 {
                                spin.push(SpinEntry {
                                    jo,
                                    ji: lm_index(li, mi) as u32,
                                    lm: lm_index(l, m) as u32,
                                    value,
                                });
                            }
                        }
                    }
                }
            }
        }
        Ok(Self {
            lv,
            lmax,
            scalar,
            spin,
            has_spin2: codomain.has_spin2(),
        })
    }

    /// Degree limit of the visibility.
    pub fn lv(&self) -> usize {
        self.lv
    }

    /// Band limit of the transfer matrices.
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// The coefficients of the visibility `v`. Errors: `v` not a one-channel scalar field
    /// of degree `lv`.
    fn visibility<'a>(&self, v: &'a PshVector) -> Result<&'a [f64]> {
        check_scalar_field(v)?;
        if v.lmax() != self.lv {
            return Err(Error::invalid(
                "visibility",
                format!("lmax {}", v.lmax()),
                format!("the triple table has visibilities of degree {}", self.lv),
            ));
        }
        Ok(v.data())
    }

    /// The coefficients of `V f` (PSH (54)) for `V = sum v_{lm} Y^R_{lm}`, in `f`'s
    /// codomain and convention, without forming the matrix: one pass over the couplings of
    /// PSH (55) per spin-0 component, and of PSH (56) when `f` has `s1, s2` (scalar SH
    /// costs the first pass alone). Errors: as [`Self::transfer`], `f` of another band
    /// limit, `f` indexed otherwise than `v`, a product beyond the range of `f64`.
    pub fn shadow(&self, v: &PshVector, f: &PshVector) -> Result<PshVector> {
        let coefficients = self.visibility(v)?;
        v.argument()
            .expect(f.argument(), "PSH vector", "the visibility")?;
        let v = coefficients;
        if f.lmax() != self.lmax || (f.codomain().has_spin2() && !self.has_spin2) {
            return Err(Error::invalid(
                "PSH vector",
                format!("lmax {}, {}", f.lmax(), f.codomain().name()),
                format!(
                    "the triple table has lmax {}{}",
                    self.lmax,
                    if self.has_spin2 { "" } else { ", spin 0 only" }
                ),
            ));
        }
        let mut out = f.clone();
        let c = real_to_complex(v, self.lv);
        for ch in 0..f.channels() {
            for (k, &p) in f.codomain().components().iter().enumerate() {
                if p == 0 || p == 3 {
                    out.set_component(ch, k, &self.scalar.product(v, &f.component(ch, k))?);
                }
            }
            if f.codomain().has_spin2() {
                let a = f.spin2(ch);
                let mut b = vec![Complex64::default(); a.len()];
                for e in &self.spin {
                    b[e.jo as usize] += c[e.lm as usize] * e.value * a[e.ji as usize];
                }
                out.set_spin2(ch, &b);
            }
        }
        // Finite inputs whose product exceeds the range of f64 are named, not returned
        // as infinities.
        crate::error::finite_all("triple product coefficient", out.data())?;
        Ok(out)
    }

    /// The PSH matrix of `f -> V f` (PSH (54)) for `V = sum v_{lm} Y^R_{lm}`, `l <= lv`,
    /// flat order `l*l + l + m`, from and to fields indexed as `v`. Errors: `v` not a
    /// one-channel scalar field of degree `lv`, a table built without the spin-2 couplings
    /// ([`Self::for_codomain`]), whose matrix would be wrong on `s1, s2`.
    pub fn transfer(&self, v: &PshVector) -> Result<PshMatrix> {
        let argument = v.argument();
        let v = self.visibility(v)?;
        if !self.has_spin2 {
            return Err(Error::invalid(
                "triple table",
                "spin 0 only",
                "the full PSH matrix needs the spin-2 couplings (TripleTable::new)",
            ));
        }
        let n = num_coeffs(self.lmax);
        let mut data = vec![0.0; n * n * 16];
        // PSH (55): the real Gaunt product matrix, on the diagonal p_o = p_i in {0, 3}.
        let s = self.scalar.product_matrix(v)?;
        for (k, &x) in s.iter().enumerate() {
            let base = k * 16;
            data[base] = x;
            data[base + 15] = x;
        }
        // PSH (56) with (51a): the 2x2 block R(P~iso) = [[Re, -Im], [Im, Re]].
        let c = real_to_complex(v, self.lv);
        let mut iso = vec![Complex64::default(); n * n];
        for e in &self.spin {
            iso[e.jo as usize * n + e.ji as usize] += c[e.lm as usize] * e.value;
        }
        for (k, z) in iso.iter().enumerate() {
            let base = k * 16;
            data[base + 5] = z.re;
            data[base + 6] = -z.im;
            data[base + 9] = z.im;
            data[base + 10] = z.re;
        }
        Ok(PshMatrix::from_data(self.lmax, data)?.labelled(argument, argument))
    }
}

/// Error unless `v` is a one-channel scalar field (a visibility).
fn check_scalar_field(v: &PshVector) -> Result<()> {
    if v.codomain() != Codomain::Intensity || v.channels() != 1 {
        return Err(Error::invalid(
            "visibility",
            format!("{}, {} channels", v.codomain().name(), v.channels()),
            "a visibility is a one-channel scalar field (SCALAR)",
        ));
    }
    Ok(())
}

/// The PSH matrix of the shadowing operator `f -> V f` (PSH (54)-(56)) for the visibility
/// `V = sum v_{lm} Y^R_{lm}` (real SH, PSH (12), a one-channel scalar field of degree
/// `lv`), band limit `lmax`, from and to fields indexed as `v`. The couplings are built
/// once per `(lv, lmax)` and reused by later calls (the four most recently used are
/// kept); [`TripleTable`] holds them explicitly.
pub fn visibility_transfer(v: &PshVector, lmax: usize) -> Result<PshMatrix> {
    // Checked before the table is built.
    check_scalar_field(v)?;
    shared_table(v.lmax(), lmax)?.transfer(v)
}

/// How many full tables [`visibility_transfer`] keeps between calls.
pub(crate) const RECENT_TABLES: usize = 4;

/// The full table of `(lv, lmax)`: reused if among the [`RECENT_TABLES`] most recently
/// used, else built (outside the lock) and kept in place of the least recently used.
fn shared_table(lv: usize, lmax: usize) -> Result<Arc<TripleTable>> {
    static RECENT: Mutex<Vec<Arc<TripleTable>>> = Mutex::new(Vec::new());
    let find = |tables: &mut Vec<Arc<TripleTable>>| {
        let i = tables.iter().position(|t| (t.lv, t.lmax) == (lv, lmax))?;
        let t = tables.remove(i);
        tables.push(t.clone());
        Some(t)
    };
    // A poisoned lock only means another thread panicked while holding it: the list is
    // still a list of complete tables.
    let lock = || RECENT.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(t) = find(&mut lock()) {
        return Ok(t);
    }
    let t = Arc::new(TripleTable::new(lv, lmax)?);
    let mut tables = lock();
    if let Some(found) = find(&mut tables) {
        return Ok(found);
    }
    if tables.len() == RECENT_TABLES {
        tables.remove(0);
    }
    tables.push(t.clone());
    Ok(t)
}

/// Direct evaluation of PSH (54) on an exact grid, for tests and `psh verify`:
/// `sum_a w_a <Y_{j_o p_o}(w_a), V(w_a) Y_{j_i p_i}(w_a)>` for every pair of basis functions,
/// with the basis fields reconstructed by [`super::PshTransform`] (PSH (30)).
pub fn visibility_transfer_quadrature(v: &PshVector, lmax: usize) -> Result<PshMatrix> {
    use super::PshTransform;
    check_scalar_field(v)?;
    let (argument, lv, v) = (v.argument(), v.lmax(), v.data());
    // Integrand degree lo + lv + li <= 2 lmax + lv: exact for 2 L >= 2 lmax + lv.
    let big = lmax + lv / 2 + 1;
    let t = PshTransform::new(big.max(2))?;
    let big = t.lmax();
    let (nb, n) = (num_coeffs(big), num_coeffs(lmax));
    let grid = t.grid();
    let mut vpad = vec![0.0; nb];
    vpad[..v.len()].copy_from_slice(v);
    let mut vis = vec![0.0; grid.len()];
    crate::sh::transform::sht::ShTransform::with_grid(big, grid.clone())?
        .synthesis_real(&vpad, &mut vis)?;
    // fields[j * 4 + p][a]: basis function Y_{jp} at grid point a (zero outside PSH (31)).
    let mut fields = Vec::with_capacity(n * 4);
    for j in 0..n {
        for p in 0..4 {
            let mut data = vec![0.0; nb * 4];
            if in_index_set(j, p) {
                data[j * 4 + p] = 1.0;
            }
            let b = PshVector::from_data(big, Codomain::Full, 1, data)?;
            fields.push(t.reconstruct(&b, 0)?);
        }
    }
    let mut data = vec![0.0; n * n * 16];
    for (o, fo) in fields.iter().enumerate() {
        for (i, fi) in fields.iter().enumerate() {
            let mut sum = 0.0;
            for (a, (so, si)) in fo.iter().zip(fi).enumerate() {
                let dot: f64 = (0..4).map(|p| so[p] * si[p]).sum();
                sum += grid.point_weight(a) * vis[a] * dot;
            }
            let (jo, po, ji, pi) = (o / 4, o % 4, i / 4, i % 4);
            data[((jo * n + ji) * 4 + po) * 4 + pi] = sum;
        }
    }
    Ok(PshMatrix::from_data(lmax, data)?.labelled(argument, argument))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::pseudo_random;
    use crate::sh::evaluation::harmonics::sh_complex;
    use crate::sh::lm_of_index;
    use crate::swsh::swsh;

    /// `shadow` equals the matrix product, in every codomain, and a scalar-only table
    /// refuses spin-2 input.
    #[test]
    fn shadow_equals_transfer_matrix() {
        let (lv, lmax) = (6, 4);
        let v = PshVector::scalar(lv, pseudo_random(num_coeffs(lv), 3)).unwrap();
        let want_full = TripleTable::new(lv, lmax).unwrap().transfer(&v).unwrap();
        for cod in [Codomain::Intensity, Codomain::NoCircular, Codomain::Full] {
            let f = crate::testing::random_psh(lmax, cod, 2, 5).unwrap();
            let table = TripleTable::for_codomain(lv, lmax, cod).unwrap();
            let got = table.shadow(&v, &f).unwrap();
            let want = want_full.apply(&f).unwrap().with_codomain(cod);
            for (a, b) in got.data().iter().zip(want.data()) {
                assert!((a - b).abs() < 1e-13, "{cod:?}: {a} vs {b}");
            }
        }
        let scalar = TripleTable::for_codomain(lv, lmax, Codomain::Intensity).unwrap();
        let f = crate::testing::random_psh(lmax, Codomain::Full, 1, 5).unwrap();
        assert!(scalar.shadow(&v, &f).is_err());
        assert!(scalar.transfer(&v).is_err());
        // A visibility of the other convention is an error, not a silent flip.
        let table = TripleTable::new(lv, lmax).unwrap();
        let travel = v.converted(crate::polarized::FieldArgument::Travel);
        assert!(table.shadow(&travel, &f).is_err());
        let both = table
            .shadow(&travel, &f.converted(travel.argument()))
            .unwrap();
        let want = table.shadow(&v, &f).unwrap().converted(travel.argument());
        assert!(max_diff(both.data(), want.data()) < 1e-13);
    }

    /// `visibility_transfer` reuses the table of a `(lv, lmax)` it has built and keeps at
    /// most `RECENT_TABLES` of them; its matrices are the explicit table's.
    #[test]
    fn visibility_transfer_reuses_recent_tables() {
        let first = shared_table(3, 2).unwrap();
        assert!(Arc::ptr_eq(&first, &shared_table(3, 2).unwrap()));
        for lv in 0..=RECENT_TABLES {
            let v = PshVector::scalar(lv, pseudo_random(num_coeffs(lv), 9)).unwrap();
            let got = visibility_transfer(&v, 3).unwrap();
            let want = TripleTable::new(lv, 3).unwrap().transfer(&v).unwrap();
            assert_eq!(got.data(), want.data(), "lv {lv}");
        }
        assert!(!Arc::ptr_eq(&first, &shared_table(3, 2).unwrap()));
    }

    fn max_diff(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
    }

    /// (T3) against quadrature with psh's own `2Y` and `Y` on an exact grid.
    #[test]
    fn spin2_gaunt_matches_quadrature() {
        let (lmax, lv) = (4usize, 3usize);
        let g = crate::sh::transform::grid::SphereGrid::for_band_limit(lmax + lv).unwrap();
        let pts: Vec<_> = (0..g.len())
            .map(|a| {
                let (t, p) = g.angles(a).unwrap();
                (
                    g.point_weight(a),
                    swsh(2, lmax, t, p).unwrap(),
                    sh_complex(lv, t, p).unwrap(),
                )
            })
            .collect();
        let mut worst = 0.0f64;
        for jo in 4..num_coeffs(lmax) {
            for ji in 4..num_coeffs(lmax) {
                for j in 0..num_coeffs(lv) {
                    let ((lo, mo), (li, mi), (l, m)) =
                        (lm_of_index(jo), lm_of_index(ji), lm_of_index(j));
                    let q: Complex64 = pts
                        .iter()
                        .map(|(w, y2, y)| y2[jo].conj() * y[j] * y2[ji] * *w)
                        .sum();
                    let e = spin2_gaunt(lo, mo, l, m, li, mi).unwrap();
                    worst = worst.max((q - e).norm());
                }
            }
        }
        assert!(worst < 1e-14, "{worst}");
        // An odd lo + l + li, where (lo l li; -2 0 2) would flip the sign:
        // (2 1 2; -2 0 2) = -(2 1 2; 2 0 -2) = 2/sqrt(30) (DLMF 34.3.2 with 34.3.9-34.3.10).
        let e = -(75.0 / (4.0 * PI)).sqrt() * 4.0 / 30.0;
        assert!((spin2_gaunt(2, 2, 1, 0, 2, 2).unwrap() - e).abs() < 1e-15);
        assert!(spin2_gaunt(2, 3, 1, 0, 2, 3).is_err());
    }

    /// PSH (54) by quadrature vs the triple products, random band-limited visibilities.
    #[test]
    fn transfer_equals_quadrature_of_54() {
        for (lv, lmax, seed) in [(3usize, 3usize, 5u64), (5, 4, 7), (2, 5, 11)] {
            let v = PshVector::scalar(lv, pseudo_random(num_coeffs(lv), seed)).unwrap();
            let a = visibility_transfer(&v, lmax).unwrap();
            let b = visibility_transfer_quadrature(&v, lmax).unwrap();
            let d = max_diff(a.data(), b.data());
            assert!(d <= 1e-12, "lv {lv} lmax {lmax}: {d}");
        }
    }

    /// A constant visibility `V = 1` (`v_00 = sqrt(4 pi)`) is the identity.
    #[test]
    fn unit_visibility_is_identity() {
        let lmax = 4;
        let mut v = vec![0.0; num_coeffs(2)];
        v[0] = (4.0 * PI).sqrt();
        let m = visibility_transfer(&PshVector::scalar(2, v).unwrap(), lmax).unwrap();
        let n = num_coeffs(lmax);
        for jo in 0..n {
            for ji in 0..n {
                for po in 0..4 {
                    for pi in 0..4 {
                        let on = jo == ji && po == pi && in_index_set(jo, po);
                        let e = if on { 1.0 } else { 0.0 };
                        assert!((m.get(jo, ji, po, pi) - e).abs() < 1e-14);
                    }
                }
            }
        }
    }

    #[test]
    fn table_reuse_and_bad_input() {
        let t = TripleTable::new(3, 3).unwrap();
        let v = PshVector::scalar(3, pseudo_random(16, 3)).unwrap();
        assert_eq!(t.transfer(&v).unwrap(), visibility_transfer(&v, 3).unwrap());
        let low = PshVector::scalar(2, pseudo_random(9, 3)).unwrap();
        assert!(t
            .transfer(&low)
            .unwrap_err()
            .to_string()
            .contains("degree 3"));
        let colour = crate::testing::random_psh(3, Codomain::Intensity, 3, 4).unwrap();
        assert!(t
            .transfer(&colour)
            .unwrap_err()
            .to_string()
            .contains("one-channel"));
        assert!(TripleTable::new(40, 3).is_err());
    }
}
