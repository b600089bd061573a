//! Isotropic operators (PSH Sec. 6.3.3): an operator that commutes with rotations about
//! the normal `z` has a coefficient matrix with `P = 0` unless `|m_i| = |m_o|` (PSH (52)),
//! and a spin 2-to-2 block with `P~iso = 0` unless `m_i = m_o` and `P~conj = 0` unless
//! `m_i = -m_o` (PSH (53)). [`IsotropicMatrix`] stores only the `O(lmax^3)` blocks that
//! PSH (52) allows, per colour channel, in the order of polarsh's `ISOBI2` layout
//! (its `SH.py`, `lms2idx` / `idx2lms`; `docs/conventions.md`):
//!
//! - degree pairs by shells `n = max(l_o, l_i) = 0, 1, ...`, within a shell by
//!   `l = min(l_o, l_i) = 0, 1, ..., n`, and for `l < n` first `(l_o, l_i) = (n, l)` then
//!   `(l, n)`;
//! - within a pair of `k = min(l_o, l_i)`, the entries `(m_i, m_o)` with `|m_o| = |m_i| <= k`
//!   in lexicographic order of `(m_i, m_o)`: `(-k, -k), (-k, k), ..., (0, 0), (1, -1), (1, 1),
//!   ..., (k, -k), (k, k)`;
//! - each entry a 4 x 4 block `[p_o][p_i]`.

use super::matrix::apply_by_channel;
use super::{in_index_set, FieldArgument, PshMatrix, PshVector};
use crate::error::{check_len, Error, Result};
use crate::sh::{lm_index, lm_of_index, num_coeffs};
use crate::stokes::complex_pair;
use std::collections::HashMap;

/// The number of entries of the isotropic layout for band limit `lmax`:
/// `N (4 N^2 - 3 N + 2) / 3` with `N = lmax + 1` (the shells below `N` of
/// [`isotropic_pairs`]; about `4/3 lmax^3`, not `(lmax + 1)^2`); `None` past `usize`.
pub fn isotropic_pair_count(lmax: usize) -> Option<usize> {
    let n = lmax.checked_add(1)?;
    let inner = n
        .checked_mul(n)?
        .checked_mul(4)?
        .checked_sub(3 * n)?
        .checked_add(2)?;
    Some(n.checked_mul(inner)? / 3)
}

/// The `(j_o, j_i)` flat index pairs of the isotropic layout for band limit `lmax`
/// ([`isotropic_pair_count`] of them).
pub fn isotropic_pairs(lmax: usize) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut block = |lo: usize, li: usize| {
        let k = lo.min(li) as i64;
        for mi in -k..=k {
            let mos: &[i64] = if mi == 0 {
                &[0]
            } else {
                &[-mi.abs(), mi.abs()]
            };
            for &mo in mos {
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
/// `4 min(l_o, l_i) + 1` entries (one `m_o` for `m_i = 0`, two otherwise).
pub fn isotropic_lmax(k: usize) -> Option<usize> {
    let mut total = 0usize;
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
        let (_, mo) = lm_of_index(jo);
        for ji in 0..n {
            let (_, mi) = lm_of_index(ji);
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

/// The coefficient matrices of an isotropic operator in the isotropic layout (module
/// docs), one per colour channel: `blocks[c * K + k]` is the 4 x 4 block `[p_o][p_i]` of
/// pair `k` of [`isotropic_pairs`] in channel `c`. Input and output fields are indexed as
/// [`Self::input`] and [`Self::output`] say.
///
/// # Example
///
/// A zonal filter `k_l` with one `s0 -> s3` coupling of `|m_i| = |m_o|`: isotropic
/// (PSH (52)), so the sparse form is lossless and applies as the dense matrix; an entry
/// with `|m_i| != |m_o|` is refused.
///
/// ```
/// use psh::polarized::{in_index_set, IsotropicMatrix, PshMatrix, PshVector};
/// use psh::sh::lm_of_index;
///
/// let (lmax, n) = (2, 9);
/// let at = |jo: usize, ji: usize, po: usize, pi: usize| ((jo * n + ji) * 4 + po) * 4 + pi;
/// let k = [1.0, 0.5, 0.25];
/// let mut data = vec![0.0; n * n * 16];
/// for j in 0..n {
///     for p in (0..4).filter(|&p| in_index_set(j, p)) {
///         data[at(j, j, p, p)] = k[lm_of_index(j).0];
///     }
/// }
/// data[at(7, 1, 3, 0)] = 0.1; // f_{1,-1,0} to f_{2,1,3}
/// let dense = PshMatrix::from_data(lmax, data.clone())?;
/// let iso = IsotropicMatrix::from_dense(&dense, 1e-15)?;
/// assert_eq!(iso.to_dense(0)?, dense);
///
/// let f = PshVector::scalar(lmax, (0..n).map(|j| 1.0 + j as f64).collect())?;
/// let (a, b) = (iso.apply(&f)?, dense.apply(&f)?);
/// assert!(a.data().iter().zip(b.data()).all(|(x, y)| (x - y).abs() < 1e-14));
///
/// data[at(3, 2, 0, 0)] = 0.01; // f_{1,0,0} to f_{1,1,0}
/// assert!(IsotropicMatrix::from_dense(&PshMatrix::from_data(lmax, data)?, 1e-6).is_err());
/// # Ok::<(), psh::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct IsotropicMatrix {
    lmax: usize,
    channels: usize,
    input: FieldArgument,
    output: FieldArgument,
    pairs: Vec<(usize, usize)>,
    blocks: Vec<[[f64; 4]; 4]>,
}

impl IsotropicMatrix {
    /// The sparse form of an isotropic matrix (one channel, its conventions). Errors: a
    /// `tolerance` that is NaN or negative; an isotropy defect ([`isotropy_defect`]) above
    /// it, naming it.
    pub fn from_dense(m: &PshMatrix, tolerance: f64) -> Result<Self> {
        if tolerance.is_nan() || tolerance < 0.0 {
            return Err(Error::invalid(
                "isotropy tolerance",
                format!("{tolerance}"),
                "a relative tolerance >= 0 (infinity accepts any defect)",
            ));
        }
        let defect = isotropy_defect(m);
        if defect > tolerance {
            return Err(Error::invalid(
                "isotropy defect",
                format!("{defect:e}"),
                format!(
                    "entries PSH (52)-(53) require to vanish exceed {tolerance:e} of the largest"
                ),
            ));
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
            channels: 1,
            input: m.input(),
            output: m.output(),
            pairs,
            blocks,
        })
    }

    /// Matrices from blocks in the isotropic layout (`4 x 4` each, flat
    /// `[c][k][p_o][p_i]` for `channels` channels), input indexed by the direction towards
    /// the source and output by the direction of travel (as [`PshMatrix::zeros`];
    /// [`Self::labelled`] declares others). Errors: no channels, wrong length, non-finite
    /// entries or entries outside PSH (31).
    pub fn from_blocks(lmax: usize, channels: usize, data: &[f64]) -> Result<Self> {
        if channels == 0 {
            return Err(Error::invalid("channels", "0", "at least one channel"));
        }
        let pairs = isotropic_pairs(lmax);
        let per_channel = pairs.len().checked_mul(16).ok_or(Error::invalid(
            "lmax",
            lmax.to_string(),
            "the isotropic layout's size overflows",
        ))?;
        check_len(
            "isotropic blocks",
            per_channel.saturating_mul(channels),
            data.len(),
        )?;
        crate::error::finite_all("isotropic matrix entry", data)?;
        for (q, x) in data.iter().enumerate() {
            let (jo, ji) = pairs[(q / 16) % pairs.len()];
            let (po, pi) = ((q / 4) % 4, q % 4);
            let spin2_low = !(in_index_set(jo, po) && in_index_set(ji, pi));
            if spin2_low && *x != 0.0 {
                return Err(Error::invalid(
                    "isotropic matrix entry",
                    format!(
                        "channel {}, entry {}, [{po}][{pi}] = {x}",
                        q / per_channel,
                        (q / 16) % pairs.len()
                    ),
                    "spin-2 rows and columns start at l = 2 (PSH (31))",
                ));
            }
        }
        let blocks = data
            .chunks_exact(16)
            .map(|b| std::array::from_fn(|po| std::array::from_fn(|pi| b[po * 4 + pi])))
            .collect();
        Ok(Self {
            lmax,
            channels,
            input: FieldArgument::TowardsSource,
            output: FieldArgument::Travel,
            pairs,
            blocks,
        })
    }

    /// The channels of `parts` side by side. Errors: no parts, or parts of different band
    /// limits or conventions, naming the first that differs.
    pub fn from_channels(parts: &[IsotropicMatrix]) -> Result<Self> {
        let first = parts.first().ok_or_else(|| {
            Error::invalid("isotropic matrices", "[]", "at least one matrix to stack")
        })?;
        let key = |m: &IsotropicMatrix| (m.lmax, m.input, m.output);
        if let Some((k, m)) = parts.iter().enumerate().find(|(_, m)| key(m) != key(first)) {
            return Err(Error::invalid(
                "isotropic matrix",
                format!("#{k}: lmax {}, {} -> {}", m.lmax, m.input, m.output),
                format!(
                    "the first has lmax {}, {} -> {}",
                    first.lmax, first.input, first.output
                ),
            ));
        }
        Ok(Self {
            channels: parts.iter().map(|m| m.channels).sum(),
            blocks: parts
                .iter()
                .flat_map(|m| m.blocks.iter().copied())
                .collect(),
            ..first.clone()
        })
    }

    /// The same entries declared to map fields indexed by `input` to fields indexed by
    /// `output`, without changing them ([`Self::with_input`] converts).
    pub fn labelled(mut self, input: FieldArgument, output: FieldArgument) -> Self {
        self.input = input;
        self.output = output;
        self
    }

    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// The number of colour channels.
    pub fn channels(&self) -> usize {
        self.channels
    }

    /// What the argument of the input field means.
    pub fn input(&self) -> FieldArgument {
        self.input
    }

    /// What the argument of the output field means.
    pub fn output(&self) -> FieldArgument {
        self.output
    }

    /// The blocks, flat `[c][k][p_o][p_i]` in the isotropic layout.
    pub fn blocks(&self) -> Vec<f64> {
        self.blocks.iter().flatten().flatten().copied().collect()
    }

    /// Channel `c` as a dense matrix (its conventions). Error: `c` out of range.
    pub fn to_dense(&self, c: usize) -> Result<PshMatrix> {
        let blocks = self.channel_blocks(c)?;
        let n = num_coeffs(self.lmax);
        let mut data = vec![0.0; n * n * 16];
        for (&(jo, ji), b) in self.pairs.iter().zip(blocks) {
            for po in 0..4 {
                for pi in 0..4 {
                    data[((jo * n + ji) * 4 + po) * 4 + pi] = b[po][pi];
                }
            }
        }
        Ok(PshMatrix::from_data(self.lmax, data)?.labelled(self.input, self.output))
    }

    /// The blocks of channel `c`. Error: `c` out of range.
    fn channel_blocks(&self, c: usize) -> Result<&[[[f64; 4]; 4]]> {
        if c >= self.channels {
            return Err(Error::invalid(
                "channel",
                c.to_string(),
                format!("{} channels", self.channels),
            ));
        }
        Ok(&self.blocks[c * self.pairs.len()..][..self.pairs.len()])
    }

    /// The same operator with its input indexed by `input`: itself when it already is,
    /// else `P T` in the sparse layout, the same as [`PshMatrix::with_input`] of the dense
    /// matrix. `T` maps column `(l, m, p)` to `(-1)^l (l, m, 0)`, `-(-1)^l (l, m, 3)`,
    /// `(-1)^(l+m) (l, -m, 1)`, `-(-1)^(l+m) (l, -m, 2)` ([`PshVector::converted`]), and
    /// `m_i -> -m_i` keeps `|m_i| = |m_o|`, so the layout holds the partner entry.
    pub fn with_input(&self, input: FieldArgument) -> Result<IsotropicMatrix> {
        if input == self.input {
            return Ok(self.clone());
        }
        let index: HashMap<(usize, usize), usize> = self
            .pairs
            .iter()
            .enumerate()
            .map(|(k, &p)| (p, k))
            .collect();
        let k_pairs = self.pairs.len();
        let mut blocks = self.blocks.clone();
        for (k, &(jo, ji)) in self.pairs.iter().enumerate() {
            let (l, m) = lm_of_index(ji);
            let partner = index[&(jo, lm_index(l, -m))];
            let sl = if l % 2 == 0 { 1.0 } else { -1.0 };
            let slm = if (l as i64 + m) % 2 == 0 { 1.0 } else { -1.0 };
            for c in 0..self.channels {
                let (own, other) = (
                    self.blocks[c * k_pairs + k],
                    self.blocks[c * k_pairs + partner],
                );
                let b = &mut blocks[c * k_pairs + k];
                for po in 0..4 {
                    b[po][0] = sl * own[po][0];
                    b[po][3] = -sl * own[po][3];
                    b[po][1] = slm * other[po][1];
                    b[po][2] = -slm * other[po][2];
                }
            }
        }
        Ok(IsotropicMatrix {
            input,
            blocks,
            ..self.clone()
        })
    }

    /// PSH (41) over the stored blocks only, `O(lmax^3)` per channel: channel `c` of `f`
    /// through channel `c` of the matrix, or every channel through a one-channel matrix;
    /// the result is indexed as [`Self::output`]. Errors: `f` of another band limit, not
    /// indexed as [`Self::input`], or of another number of channels.
    pub fn apply(&self, f: &PshVector) -> Result<PshVector> {
        if self.channels != 1 && self.channels != f.channels() {
            return Err(Error::invalid(
                "PSH vector",
                format!("{} channels", f.channels()),
                format!("the isotropic matrix has {} channels", self.channels),
            ));
        }
        let k_pairs = self.pairs.len();
        apply_by_channel((self.lmax, self.input, self.output), f, |c, x, out| {
            let c = if self.channels == 1 { 0 } else { c };
            let blocks = &self.blocks[c * k_pairs..][..k_pairs];
            for (&(jo, ji), b) in self.pairs.iter().zip(blocks) {
                let o = &mut out[jo * 4..][..4];
                for po in 0..4 {
                    o[po] += b[po].iter().zip(&x[ji]).map(|(a, y)| a * y).sum::<f64>();
                }
            }
        })
    }
}

/// The default quadrature band for projecting a pBRDF to band limit `lmax`:
/// `max(lmax, 2)` rounded up to odd, so that the Gauss-Legendre grid has an even number
/// of rings, none on the horizon, where a pBRDF steps to zero (a ring there counts the
/// whole step: 6% too much for a Lambertian table at 25 rings, `docs/measured-pbrdf.md`).
pub fn horizon_free_grid(lmax: usize) -> usize {
    lmax.max(2) | 1
}

/// The smallest default quadrature band for a measured table, [`table_grid`].
pub const TABLE_GRID_MIN: usize = 19;

/// The default quadrature band for projecting a measured table to band limit `lmax`:
/// [`horizon_free_grid`] of `max(lmax, 19)`. A table is piecewise linear, not
/// band-limited, so a low band limit computed on its own small grid aliases: the KAIST
/// dataset's resolution (19 samples of `theta_d` and `theta_h`) is sampled by at least 20
/// rings (a constant KAIST-layout table at `l = 4`: isotropy defect 1e-2 on the grid of
/// band 5, 9e-4 on that of band 19; `docs/measured-pbrdf.md`).
pub fn table_grid(lmax: usize) -> usize {
    horizon_free_grid(lmax.max(TABLE_GRID_MIN))
}

/// An isotropic projection of measured or sampled operators, with what the grid says of it.
#[derive(Clone, Debug)]
pub struct IsotropicProjection {
    /// The matrices, one channel per field.
    pub matrix: IsotropicMatrix,
    /// The largest isotropy defect of a channel ([`isotropy_defect`]: what the quadrature
    /// aliased into entries isotropy forbids, which are dropped).
    pub isotropy_defect: f64,
    /// The largest relative residual of the band limit of a channel on the grid,
    /// `sqrt(1 - |P_L|^2 / |P|^2)`: the part of the operator's norm (sampled on the grid)
    /// that degrees `<= lmax` do not hold (`proofs/band-limit-residual.md`).
    pub band_limit_residual: f64,
}

/// The isotropic matrices of `fields` (one channel each, PSH (40) projected on the exact
/// grid of band `grid_lmax` as [`super::project_operator_with`]) in the isotropic layout
/// (PSH (52), (53)), with the largest isotropy defect and band-limit residual of a channel.
/// Errors: a defect above `tolerance`, and the projection's.
pub fn project_isotropic_with(
    fields: &[&dyn crate::stokes::MuellerField],
    lmax: usize,
    grid_lmax: usize,
    tolerance: f64,
    progress: &dyn crate::progress::Progress,
) -> Result<IsotropicProjection> {
    let (mut defect, mut residual) = (0.0f64, 0.0f64);
    let channels = fields
        .iter()
        .map(|field| {
            let (dense, norm_sq) = super::project_operator_normed(
                *field,
                lmax,
                grid_lmax,
                super::SpinBlock22::ComplexPair,
                progress,
            )?;
            defect = defect.max(isotropy_defect(&dense));
            residual = residual.max(super::band_limit_residual(norm_sq, &dense));
            IsotropicMatrix::from_dense(&dense, tolerance)
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(IsotropicProjection {
        matrix: IsotropicMatrix::from_channels(&channels)?,
        isotropy_defect: defect,
        band_limit_residual: residual,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against the closed form of `psh verify` (feature `verify`).
    #[cfg(feature = "verify")]
    #[test]
    fn layout_is_polarsh_isobi2() {
        // SHMat_*_L20_ISOBI2.npz: 10280 entries for l < 20.
        assert_eq!(isotropic_pairs(19).len(), 10280);
        let p = isotropic_pairs(2);
        // Shell 1 starts at entry 1 with (l_o, l_i) = (1, 0); (2, 0) is entry 8.
        assert_eq!(p[1], (lm_index(1, 0), 0));
        assert_eq!(p[8], (lm_index(2, 0), 0));
        assert_eq!(p[9], (0, lm_index(2, 0)));
        // Pair (2, 2) from entry 20: (m_i, m_o) = (-2, -2), then (-2, 2).
        assert_eq!(p[20], (lm_index(2, -2), lm_index(2, -2)));
        assert_eq!(p[21], (lm_index(2, 2), lm_index(2, -2)));
        for lmax in 0..9 {
            for (k, &(jo, ji)) in isotropic_pairs(lmax).iter().enumerate() {
                let ((lo, mo), (li, mi)) = (lm_of_index(jo), lm_of_index(ji));
                assert_eq!(
                    crate::verify::isobi2_index(li, lo, mi, mo),
                    k,
                    "{lo} {mo} {li} {mi}"
                );
            }
        }
        for l in 0..12 {
            assert_eq!(isotropic_lmax(isotropic_pairs(l).len()), Some(l));
            assert_eq!(isotropic_lmax(isotropic_pairs(l).len() + 1), None);
        }
        assert_eq!(isotropic_lmax(10280), Some(19));
        for l in 0..30 {
            assert_eq!(
                isotropic_pair_count(l),
                Some(isotropic_pairs(l).len()),
                "{l}"
            );
        }
        assert_eq!(isotropic_pair_count(usize::MAX), None);
    }

    /// Blocks of two channels with distinct entries (zero outside PSH (31)).
    fn distinct_blocks(lmax: usize) -> Vec<f64> {
        let pairs = isotropic_pairs(lmax);
        (0..2 * pairs.len() * 16)
            .map(|q| {
                let (jo, ji) = pairs[(q / 16) % pairs.len()];
                let (po, pi) = ((q / 4) % 4, q % 4);
                if !(in_index_set(jo, po) && in_index_set(ji, pi)) {
                    0.0
                } else {
                    ((q * 7919) % 1000) as f64 / 1000.0 - 0.5
                }
            })
            .collect()
    }

    /// The sparse map to the other input convention equals the dense one in every channel,
    /// and is an involution.
    #[test]
    fn with_input_sparse_equals_dense() {
        let lmax = 6;
        let m = IsotropicMatrix::from_blocks(lmax, 2, &distinct_blocks(lmax)).unwrap();
        let sparse = m.with_input(FieldArgument::Travel).unwrap();
        assert_eq!(sparse.input(), FieldArgument::Travel);
        for c in 0..2 {
            let dense = m
                .to_dense(c)
                .unwrap()
                .with_input(FieldArgument::Travel)
                .unwrap();
            assert_eq!(sparse.to_dense(c).unwrap(), dense);
        }
        assert_eq!(sparse.with_input(FieldArgument::TowardsSource).unwrap(), m);
    }

    /// A two-channel matrix applies channel by channel; a one-channel one to every
    /// channel; other channel counts and the other input convention are errors.
    #[test]
    fn channels_apply_in_one_call() {
        let lmax = 4;
        let m = IsotropicMatrix::from_blocks(lmax, 2, &distinct_blocks(lmax)).unwrap();
        let f = crate::testing::random_psh(lmax, super::super::Codomain::Full, 2, 5).unwrap();
        let out = m.apply(&f).unwrap();
        assert_eq!(out.argument(), FieldArgument::Travel);
        for c in 0..2 {
            let want = m
                .to_dense(c)
                .unwrap()
                .apply(&f.channel(c).unwrap())
                .unwrap();
            assert_eq!(out.channel(c).unwrap(), want);
        }
        let one =
            IsotropicMatrix::from_blocks(lmax, 1, &distinct_blocks(lmax)[..m.blocks().len() / 2])
                .unwrap();
        let both = one.apply(&f).unwrap();
        assert_eq!(
            both.channel(1).unwrap(),
            one.apply(&f.channel(1).unwrap()).unwrap()
        );
        let three = crate::testing::random_psh(lmax, super::super::Codomain::Full, 3, 6).unwrap();
        assert!(m.apply(&three).is_err());
        assert!(m.apply(&f.converted(FieldArgument::Travel)).is_err());
        assert!(IsotropicMatrix::from_channels(&[
            m.clone(),
            m.with_input(FieldArgument::Travel).unwrap()
        ])
        .is_err());
        assert_eq!(
            IsotropicMatrix::from_channels(&[one.clone(), one])
                .unwrap()
                .channels(),
            2
        );
    }
}
