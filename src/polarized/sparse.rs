//! A PSH coefficient matrix restricted to the Stokes components a computation needs and
//! stored sparse: the planner's storage ([`crate::pprt::plan`]). Rows and columns run over
//! `(j, p)` with `p` in the output and input codomains, in the layout of [`PshVector`]
//! (`j * components + k`), so PSH (41) is one pass over the stored entries. Isotropic
//! operators keep only the entries PSH (52) allows (`|m_o| = |m_i|`), `O(lmax^3)` of them.

use super::{Codomain, FieldArgument, PshMatrix, PshVector};
use crate::error::{Error, Result};
use crate::sh::{lm_of_index, num_coeffs};

/// Which entries of the dense matrix are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sparsity {
    /// Every nonzero entry.
    General,
    /// The nonzero entries with `|m_o| = |m_i|` (PSH (52)); the others must be negligible,
    /// as [`super::isotropy_defect`] says.
    Isotropic,
}

/// A restricted, sparse PSH matrix (compressed rows).
#[derive(Clone, Debug, PartialEq)]
pub struct SparsePshMatrix {
    lmax: usize,
    input: Codomain,
    output: Codomain,
    /// The conventions of the input and output fields (those of the dense matrix).
    arguments: (FieldArgument, FieldArgument),
    /// Row `r` holds entries `row_start[r]..row_start[r + 1]`.
    row_start: Vec<usize>,
    column: Vec<u32>,
    value: Vec<f64>,
}

impl SparsePshMatrix {
    /// The entries of `m` from the components of `input` to those of `output`, zeros
    /// dropped, and with [`Sparsity::Isotropic`] the entries PSH (52) says vanish.
    pub fn new(m: &PshMatrix, input: Codomain, output: Codomain, sparsity: Sparsity) -> Self {
        let n = num_coeffs(m.lmax());
        let (pin, pout) = (input.components(), output.components());
        let mut row_start = vec![0];
        let (mut column, mut value) = (Vec::new(), Vec::new());
        for jo in 0..n {
            let mo = lm_of_index(jo).1.abs();
            for &po in pout {
                for ji in 0..n {
                    if sparsity == Sparsity::Isotropic && lm_of_index(ji).1.abs() != mo {
                        continue;
                    }
                    for (k, &pi) in pin.iter().enumerate() {
                        let x = m.get(jo, ji, po, pi);
                        if x != 0.0 {
                            column.push((ji * pin.len() + k) as u32);
                            value.push(x);
                        }
                    }
                }
                row_start.push(column.len());
            }
        }
        Self {
            lmax: m.lmax(),
            input,
            output,
            arguments: (m.input(), m.output()),
            row_start,
            column,
            value,
        }
    }

    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// The number of stored entries.
    pub fn stored(&self) -> usize {
        self.value.len()
    }

    /// PSH (41) on every channel of `f`, the result in the output codomain and convention.
    /// Error: `f` of another band limit, codomain or convention than the input's.
    pub fn apply(&self, f: &PshVector) -> Result<PshVector> {
        if f.lmax() != self.lmax || f.codomain() != self.input {
            return Err(Error::invalid(
                "PSH vector",
                format!("lmax {}, {}", f.lmax(), f.codomain().name()),
                format!(
                    "the sparse matrix maps lmax {}, {}",
                    self.lmax,
                    self.input.name()
                ),
            ));
        }
        self.arguments
            .0
            .expect(f.argument(), "PSH vector", "the sparse matrix's input")?;
        let n = num_coeffs(self.lmax);
        let nin = n * self.input.components().len();
        let mut out = Vec::with_capacity(f.channels() * (self.row_start.len() - 1));
        for x in f.data().chunks_exact(nin) {
            out.extend(self.row_start.windows(2).map(|r| {
                self.column[r[0]..r[1]]
                    .iter()
                    .zip(&self.value[r[0]..r[1]])
                    .map(|(&j, v)| v * x[j as usize])
                    .sum::<f64>()
            }));
        }
        Ok(
            PshVector::from_data(self.lmax, self.output, f.channels(), out)?
                .labelled(self.arguments.1),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::random_psh;

    /// Restricted to every codomain, the sparse product equals the dense product read in
    /// that codomain when the input has only those components; the isotropic pattern of an
    /// isotropic matrix loses nothing.
    #[test]
    fn sparse_equals_dense() {
        let lmax = 5;
        let field = crate::optics::PolarizedPlastic::new(0.3, 1.5, 0.4).unwrap();
        let m = super::super::project_operator(
            &field,
            lmax,
            12,
            super::super::SpinBlock22::ComplexPair,
        )
        .unwrap();
        for cod in [Codomain::Intensity, Codomain::NoCircular, Codomain::Full] {
            let f = random_psh(lmax, cod, 2, 7).unwrap();
            let want = m.apply(&f).unwrap().with_codomain(cod);
            for sparsity in [Sparsity::General, Sparsity::Isotropic] {
                let s = SparsePshMatrix::new(&m, cod, cod, sparsity);
                let got = s.apply(&f).unwrap();
                let scale = want.data().iter().fold(0.0f64, |a, x| a.max(x.abs()));
                for (a, b) in got.data().iter().zip(want.data()) {
                    assert!(
                        (a - b).abs() <= 1e-13 * scale,
                        "{cod:?} {sparsity:?}: {a} vs {b}"
                    );
                }
            }
            let wrong = random_psh(lmax, Codomain::Linear, 1, 1).unwrap();
            assert!(SparsePshMatrix::new(&m, cod, cod, Sparsity::General)
                .apply(&wrong)
                .is_err());
        }
        let dense = SparsePshMatrix::new(&m, Codomain::Full, Codomain::Full, Sparsity::General);
        let iso = SparsePshMatrix::new(&m, Codomain::Full, Codomain::Full, Sparsity::Isotropic);
        assert!(iso.stored() < dense.stored());
    }
}
