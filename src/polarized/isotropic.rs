//! Isotropic operators (PSH Sec. 6.3.3): an operator that commutes with rotations about
//! the normal `z` has a coefficient matrix with `P = 0` unless `|m_i| = |m_o|` (PSH (52)),
//! and a spin 2-to-2 block with `P~iso = 0` unless `m_i = m_o` and `P~conj = 0` unless
//! `m_i = -m_o` (PSH (53)). [`IsotropicMatrix`] stores only the `O(lmax^3)` blocks that
//! PSH (52) allows, in the order of polarsh's `ISOBI2` layout:
//!
//! - degree pairs by shells `n = 0, 1, ...`: `(n, 0), (0, n), (n, 1), (1, n), ...,
//!   (n, n-1), (n-1, n), (n, n)` as `(l_o, l_i)`;
//! - within a pair, `(m_o, m_i)` in lexicographic order with `|m_o| = |m_i| <= min(l_o, l_i)`;
//! - each entry a 4 x 4 block `[p_o][p_i]`.
//!
//! (Worked out from the shared `SHMat_*_ISOBI2.npz` files: 10280 entries for `l < 20`, the
//! zero pattern of the spin-2 rows and columns below `l = 2`, and the symmetry of the
//! spin 0-to-0 block under `m -> -m`; `docs/conventions.md`.)

use super::matrix::apply_by_channel;
use super::{PshMatrix, PshVector};
use crate::error::{check_len, Error, Result};
use crate::sh::{lm_index, num_coeffs};
use crate::stokes::complex_pair;

/// The `(j_o, j_i)` flat index pairs of the isotropic layout for band limit `lmax`.
pub fn isotropic_pairs(lmax: usize) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut block = |lo: usize, li: usize| {
        let k = lo.min(li) as i64;
        for mo in -k..=k {
            let mis: &[i64] = if mo == 0 {
                &[0]
            } else {
                &[-mo.abs(), mo.abs()]
            };
            for &mi in mis {
                out.push((lm_index(lo, mo), lm_index(li, mi)));
            }
        }
    };
    for n in 0..=lmax {
        for l in 0..n {
            block(n, l);
            block(l, n);
        }
        block(n, n);
    }
    out
}

/// The band limit whose isotropic layout has `k` entries, if any: pair `(l_o, l_i)` has
/// `4 min(l_o, l_i) + 1` entries (one `m_i` for `m_o = 0`, two otherwise).
pub fn isotropic_lmax(k: usize) -> Option<usize> {
    let mut total = 0;
    for lmax in 0..=crate::sh::MAX_DEGREE {
        // Shell `lmax` adds the pairs with max(l_o, l_i) = lmax.
        total += 4 * lmax + 1 + (0..lmax).map(|l| 2 * (4 * l + 1)).sum::<usize>();
        match total.cmp(&k) {
            std::cmp::Ordering::Equal => return Some(lmax),
            std::cmp::Ordering::Greater => return None,
            std::cmp::Ordering::Less => {}
        }
    }
    None
}

/// How far a coefficient matrix is from isotropy: the largest entry that PSH (52) or
/// PSH (53) says is zero, relative to the largest entry.
pub fn isotropy_defect(m: &PshMatrix) -> f64 {
    let n = num_coeffs(m.lmax());
    let scale = m.data().iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let mut worst = 0.0f64;
    for jo in 0..n {
        let (_, mo) = crate::sh::lm_of_index(jo);
        for ji in 0..n {
            let (_, mi) = crate::sh::lm_of_index(ji);
            for po in 0..4 {
                for pi in 0..4 {
                    let spin22 = (1..3).contains(&po) && (1..3).contains(&pi);
                    if mo.abs() != mi.abs() && !spin22 {
                        worst = worst.max(m.get(jo, ji, po, pi).abs());
                    }
                }
            }
            let b = |r, c| m.get(jo, ji, r, c);
            let (iso, conj) = complex_pair([[b(1, 1), b(1, 2)], [b(2, 1), b(2, 2)]]);
            if mi != mo {
                worst = worst.max(iso.norm());
            }
            if mi != -mo {
                worst = worst.max(conj.norm());
            }
        }
    }
    if scale > 0.0 {
        worst / scale
    } else {
        0.0
    }
}

/// A coefficient matrix in the isotropic layout (module docs): `blocks[k]` is the 4 x 4
/// block `[p_o][p_i]` of pair `k` of [`isotropic_pairs`].
#[derive(Clone, Debug, PartialEq)]
pub struct IsotropicMatrix {
    lmax: usize,
    pairs: Vec<(usize, usize)>,
    blocks: Vec<[[f64; 4]; 4]>,
}

impl IsotropicMatrix {
    /// The sparse form of an isotropic matrix. Error: an isotropy defect
    /// ([`isotropy_defect`]) above `tolerance`, naming it.
    pub fn from_dense(m: &PshMatrix, tolerance: f64) -> Result<Self> {
        let defect = isotropy_defect(m);
        if defect > tolerance {
            return Err(Error::InvalidArgument {
                name: "isotropy defect",
                value: format!("{defect:e}"),
                reason: format!(
                    "entries PSH (52)-(53) require to vanish exceed {tolerance:e} of the largest"
                ),
            });
        }
        let pairs = isotropic_pairs(m.lmax());
        let blocks = pairs
            .iter()
            .map(|&(jo, ji)| {
                std::array::from_fn(|po| std::array::from_fn(|pi| m.get(jo, ji, po, pi)))
            })
            .collect();
        Ok(Self {
            lmax: m.lmax(),
            pairs,
            blocks,
        })
    }

    /// A matrix from blocks in the isotropic layout (`4 x 4` each, flat
    /// `[k][p_o][p_i]`). Errors: wrong length, non-finite or outside PSH (31).
    pub fn from_blocks(lmax: usize, data: &[f64]) -> Result<Self> {
        let pairs = isotropic_pairs(lmax);
        check_len("isotropic blocks", pairs.len() * 16, data.len())?;
        let mut dense = PshMatrix::zeros(lmax)?.data().to_vec();
        let n = num_coeffs(lmax);
        for (k, &(jo, ji)) in pairs.iter().enumerate() {
            for q in 0..16 {
                dense[(jo * n + ji) * 16 + q] = data[k * 16 + q];
            }
        }
        // Validates the entries (finite, PSH (31)).
        PshMatrix::from_data(lmax, dense)?;
        let blocks = (0..pairs.len())
            .map(|k| std::array::from_fn(|po| std::array::from_fn(|pi| data[k * 16 + po * 4 + pi])))
            .collect();
        Ok(Self {
            lmax,
            pairs,
            blocks,
        })
    }

    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// The blocks, flat `[k][p_o][p_i]` in the isotropic layout.
    pub fn blocks(&self) -> Vec<f64> {
        self.blocks.iter().flatten().flatten().copied().collect()
    }

    /// The dense matrix.
    pub fn to_dense(&self) -> Result<PshMatrix> {
        let n = num_coeffs(self.lmax);
        let mut data = vec![0.0; n * n * 16];
        for (&(jo, ji), b) in self.pairs.iter().zip(&self.blocks) {
            for po in 0..4 {
                for pi in 0..4 {
                    data[((jo * n + ji) * 4 + po) * 4 + pi] = b[po][pi];
                }
            }
        }
        PshMatrix::from_data(self.lmax, data)
    }

    /// `P T` for `T` the travel-direction map on the input side, in the sparse layout:
    /// the same as [`PshMatrix::travel_input`] of the dense matrix (polarsh's convention
    /// to psh's and back; an involution). `T` maps column `(l, m, p)` to
    /// `(-1)^l (l, m, 0)`, `-(-1)^l (l, m, 3)`, `(-1)^(l+m) (l, -m, 1)`,
    /// `-(-1)^(l+m) (l, -m, 2)` ([`PshVector::travel_convention`]), and `m_i -> -m_i`
    /// stays within a pair of the layout (the entry beside it).
    pub fn travel_input(&self) -> Result<IsotropicMatrix> {
        let mut blocks = self.blocks.clone();
        for (k, &(_, ji)) in self.pairs.iter().enumerate() {
            let (l, m) = crate::sh::lm_of_index(ji);
            let partner = match m.signum() {
                -1 => k + 1,
                1 => k - 1,
                _ => k,
            };
            let sl = if l % 2 == 0 { 1.0 } else { -1.0 };
            let slm = if (l as i64 + m) % 2 == 0 { 1.0 } else { -1.0 };
            for po in 0..4 {
                blocks[k][po][0] = sl * self.blocks[k][po][0];
                blocks[k][po][3] = -sl * self.blocks[k][po][3];
                blocks[k][po][1] = slm * self.blocks[partner][po][1];
                blocks[k][po][2] = -slm * self.blocks[partner][po][2];
            }
        }
        Ok(IsotropicMatrix {
            lmax: self.lmax,
            pairs: self.pairs.clone(),
            blocks,
        })
    }

    /// PSH (41) over the stored blocks only: `O(lmax^3)` per channel.
    pub fn apply(&self, f: &PshVector) -> Result<PshVector> {
        apply_by_channel(self.lmax, f, |x, out| {
            for (&(jo, ji), b) in self.pairs.iter().zip(&self.blocks) {
                let o = &mut out[jo * 4..][..4];
                for po in 0..4 {
                    o[po] += b[po].iter().zip(&x[ji]).map(|(a, y)| a * y).sum::<f64>();
                }
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_matches_polarsh_counts() {
        // SHMat_*_L20_ISOBI2.npz: 10280 entries for l < 20.
        assert_eq!(isotropic_pairs(19).len(), 10280);
        let p = isotropic_pairs(2);
        // Shell 1 starts at entry 1 with (l_o, l_i) = (1, 0); (2, 0) is entry 8.
        assert_eq!(p[1], (lm_index(1, 0), 0));
        assert_eq!(p[8], (lm_index(2, 0), 0));
        assert_eq!(p[9], (0, lm_index(2, 0)));
        assert_eq!(p[20], (lm_index(2, -2), lm_index(2, -2)));
        assert_eq!(p[21], (lm_index(2, -2), lm_index(2, 2)));
        for l in 0..12 {
            assert_eq!(isotropic_lmax(isotropic_pairs(l).len()), Some(l));
            assert_eq!(isotropic_lmax(isotropic_pairs(l).len() + 1), None);
        }
        assert_eq!(isotropic_lmax(10280), Some(19));
    }

    /// The sparse travel map equals the dense one, and is an involution.
    #[test]
    fn travel_input_sparse_equals_dense() {
        let lmax = 6;
        let k = isotropic_pairs(lmax).len();
        let mut data: Vec<f64> = (0..k * 16)
            .map(|i| ((i * 7919) % 1000) as f64 / 1000.0 - 0.5)
            .collect();
        // Zero the entries outside PSH (31).
        for (q, &(jo, ji)) in isotropic_pairs(lmax).iter().enumerate() {
            for po in 0..4 {
                for pi in 0..4 {
                    if (jo < 4 && (po == 1 || po == 2)) || (ji < 4 && (pi == 1 || pi == 2)) {
                        data[(q * 4 + po) * 4 + pi] = 0.0;
                    }
                }
            }
        }
        let m = IsotropicMatrix::from_blocks(lmax, &data).unwrap();
        let sparse = m.travel_input().unwrap();
        let dense = m.to_dense().unwrap().travel_input().unwrap();
        assert_eq!(sparse.to_dense().unwrap(), dense);
        assert_eq!(sparse.travel_input().unwrap(), m);
    }
}
