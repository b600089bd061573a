//! pBRDF coefficient matrices (PSH Sec. 6.3): analytic models projected to PSH matrices
//! PSH (40) with the complex-pair 2-to-2 block (PSH (51b)-(51c)), the isotropic sparse
//! form of polarsh's `ISOBI2` files (PSH (52)-(53)), their products PSH (41), and the
//! triple products of shadowing PSH (54)-(56).

use crate::arrays::{checked_len, f64_array, owned, slice, Reduced};
use crate::errors::{bad, IntoPy};
use crate::rotation::rotation_of;
use crate::vector::{argument_of, PshVector};
use numpy::prelude::*;
use numpy::PyArrayDyn;
use psh::optics::{Channel, Material};
use psh::polarized::{Codomain, SpinBlock22};
use pyo3::prelude::*;

/// The colour channel of a name: `"red"` (650 nm), `"green"` (550 nm), `"blue"` (450 nm).
fn channel_of(name: &str) -> PyResult<Channel> {
    Channel::ALL
        .into_iter()
        .zip(["red", "green", "blue"])
        .find(|(_, n)| n.eq_ignore_ascii_case(name.trim()))
        .map(|(c, _)| c)
        .ok_or_else(|| {
            bad(
                "channel",
                format!("{name:?} (expected \"red\", \"green\" or \"blue\")"),
            )
        })
}

/// A conductor: GGX microfacet specular reflection with the Fresnel Mueller matrix of a
/// complex index of refraction (PSH Sec. 7, PF Table 1 materials).
#[pyclass(module = "psh", frozen)]
pub struct Conductor {
    model: psh::optics::Conductor,
}

#[pymethods]
impl Conductor {
    /// GGX roughness `alpha` and either a PF Table 1 `material` ("gold", "silver",
    /// "copper", "aluminum", ...) at `channel`, or a complex index `n + i k`.
    #[new]
    #[pyo3(signature = (alpha, material = None, channel = "red", n = None, k = None))]
    fn new(
        alpha: f64,
        material: Option<&str>,
        channel: &str,
        n: Option<f64>,
        k: Option<f64>,
    ) -> PyResult<Self> {
        let model = match (material, n, k) {
            (Some(m), None, None) => psh::optics::Conductor::from_material(
                alpha,
                Material::from_name(m).py_err()?,
                channel_of(channel)?,
            ),
            (None, Some(n), Some(k)) => psh::optics::Conductor::new(alpha, n, k),
            _ => {
                return Err(bad(
                    "conductor",
                    "give either material (and channel) or both n and k",
                ))
            }
        };
        Ok(Self {
            model: model.py_err()?,
        })
    }

    fn __repr__(&self) -> String {
        let s = self.model.specular();
        format!(
            "Conductor(alpha={}, n={}, k={})",
            s.ggx().alpha(),
            s.ior().n(),
            s.ior().k()
        )
    }
}

/// Polarized plastic: GGX specular reflection of a dielectric of index `n` over a
/// Lambertian base of albedo `albedo`.
#[pyclass(module = "psh", frozen)]
pub struct PolarizedPlastic {
    model: psh::optics::PolarizedPlastic,
}

#[pymethods]
impl PolarizedPlastic {
    #[new]
    fn new(alpha: f64, n: f64, albedo: f64) -> PyResult<Self> {
        Ok(Self {
            model: psh::optics::PolarizedPlastic::new(alpha, n, albedo).py_err()?,
        })
    }

    fn __repr__(&self) -> String {
        let s = self.model.specular();
        format!(
            "PolarizedPlastic(alpha={}, n={}, albedo={})",
            s.ggx().alpha(),
            s.ior().n(),
            self.model.diffuse().albedo()
        )
    }
}

/// A PSH coefficient matrix PSH (40), full Stokes in and out.
#[pyclass(module = "psh", frozen)]
#[derive(Clone)]
pub struct PshMatrix {
    m: psh::polarized::PshMatrix,
}

#[pymethods]
impl PshMatrix {
    /// From entries `(n, n, 4, 4)` `[j_o, j_i, p_o, p_i]` (`j = l*l + l + m`,
    /// `n = (lmax+1)^2`), input indexed towards the source and output along travel
    /// unless `input`/`output` say otherwise.
    #[staticmethod]
    #[pyo3(signature = (data, input = "towards-source", output = "travel"))]
    fn from_data(data: &Bound<'_, PyAny>, input: &str, output: &str) -> PyResult<Self> {
        let a = f64_array(data)?;
        let n = match a.shape() {
            [n, n2, 4, 4] if n == n2 => *n,
            s => {
                return Err(bad(
                    "matrix data",
                    format!("shape {s:?}, expected (n, n, 4, 4)"),
                ))
            }
        };
        let l = (n as f64).sqrt().round() as usize;
        if n == 0 || l * l != n {
            return Err(bad("matrix data", format!("{n} rows, not (lmax+1)^2")));
        }
        let m = psh::polarized::PshMatrix::from_data(l - 1, slice(&a)?.to_vec()).py_err()?;
        Ok(Self {
            m: m.labelled(argument_of(input)?, argument_of(output)?),
        })
    }

    /// The band limit.
    #[getter]
    fn lmax(&self) -> usize {
        self.m.lmax()
    }

    /// The input field's argument convention.
    #[getter]
    fn input(&self) -> &'static str {
        self.m.input().name()
    }

    /// The output field's argument convention.
    #[getter]
    fn output(&self) -> &'static str {
        self.m.output().name()
    }

    /// The entries, a new array `(n, n, 4, 4)` `[j_o, j_i, p_o, p_i]`.
    #[getter]
    fn data<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let n = psh::sh::num_coeffs(self.m.lmax());
        owned(py, &[n, n, 4, 4], self.m.data().to_vec())
    }

    /// The product PSH (41) with a one-channel vector indexed as the input.
    fn apply(&self, py: Python<'_>, f: &PshVector) -> PyResult<PshVector> {
        py.detach(|| self.m.apply(&f.v))
            .py_err()
            .map(PshVector::wrap)
    }

    /// The operator turned by `rotation`, `D P D^T` (PSH (59), (35)-(37)).
    fn rotated(&self, py: Python<'_>, rotation: &Bound<'_, PyAny>) -> PyResult<Self> {
        let r = rotation_of(rotation)?;
        let m = py.detach(|| self.m.rotated(&r)).py_err()?;
        Ok(Self { m })
    }

    /// The same operator taking its input under the convention `input`.
    fn with_input(&self, input: &str) -> PyResult<Self> {
        Ok(Self {
            m: self.m.with_input(argument_of(input)?).py_err()?,
        })
    }

    /// The entries of degrees `l <= lmax`.
    fn truncated(&self, lmax: usize) -> PyResult<Self> {
        Ok(Self {
            m: self.m.truncated(lmax).py_err()?,
        })
    }

    /// `P @ f`: [`Self::apply`].
    fn __matmul__(&self, py: Python<'_>, f: PyRef<'_, PshVector>) -> PyResult<PshVector> {
        self.apply(py, &f)
    }

    /// Pickling, `copy.copy` and `copy.deepcopy`: `PshMatrix.from_data` of the entries and
    /// conventions.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Reduced<'py>> {
        let from = py.get_type::<Self>().getattr("from_data")?;
        Ok((from, (self.data(py)?, self.input(), self.output())))
    }

    fn __repr__(&self) -> String {
        format!(
            "PshMatrix(lmax={}, input={}, output={})",
            self.m.lmax(),
            self.input(),
            self.output()
        )
    }
}

/// Isotropic pBRDF matrices in polarsh's `ISOBI2` sparse layout (PSH (52)-(53)), one per
/// colour channel.
#[pyclass(module = "psh", frozen)]
pub struct IsotropicMatrix {
    pub(crate) m: psh::polarized::IsotropicMatrix,
}

#[pymethods]
impl IsotropicMatrix {
    /// Reads a polarsh `ISOBI2` `.npz` file (as `SHMat_6_gold_ds1_L20_ISOBI2.npz`).
    #[staticmethod]
    fn read_npz(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Self> {
        Ok(Self {
            m: py.detach(|| psh::io::read_isotropic_npz(&path)).py_err()?,
        })
    }

    /// Writes the matrices as a polarsh `ISOBI2` `.npz` file.
    fn write_npz(&self, py: Python<'_>, path: std::path::PathBuf) -> PyResult<()> {
        py.detach(|| psh::io::write_isotropic_npz(&path, &self.m))
            .py_err()
    }

    /// The sparse form of an isotropic matrix; error if its isotropy defect PSH (52)-(53)
    /// exceeds `tolerance`.
    #[staticmethod]
    #[pyo3(signature = (m, tolerance = 1e-12))]
    fn from_dense(m: &PshMatrix, tolerance: f64) -> PyResult<Self> {
        Ok(Self {
            m: psh::polarized::IsotropicMatrix::from_dense(&m.m, tolerance).py_err()?,
        })
    }

    /// One matrix of the channels of `parts`.
    #[staticmethod]
    fn from_channels(parts: Vec<PyRef<'_, IsotropicMatrix>>) -> PyResult<Self> {
        let parts: Vec<_> = parts.iter().map(|p| p.m.clone()).collect();
        Ok(Self {
            m: psh::polarized::IsotropicMatrix::from_channels(&parts).py_err()?,
        })
    }

    /// The band limit.
    #[getter]
    fn lmax(&self) -> usize {
        self.m.lmax()
    }

    /// The number of colour channels.
    #[getter]
    fn channels(&self) -> usize {
        self.m.channels()
    }

    /// The input field's argument convention.
    #[getter]
    fn input(&self) -> &'static str {
        self.m.input().name()
    }

    /// The output field's argument convention.
    #[getter]
    fn output(&self) -> &'static str {
        self.m.output().name()
    }

    /// The blocks `(channels, pairs, 4, 4)`: block `k` is the entry `[j_o, j_i]` of
    /// `isotropic_pairs(lmax)[k]`.
    fn blocks<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let b = self.m.blocks();
        let c = self.m.channels();
        owned(py, &[c, b.len() / (16 * c), 4, 4], b)
    }

    /// The dense matrix of channel `c`.
    fn to_dense(&self, c: usize) -> PyResult<PshMatrix> {
        Ok(PshMatrix {
            m: self.m.to_dense(c).py_err()?,
        })
    }

    /// The same operator taking its input under the convention `input`.
    fn with_input(&self, input: &str) -> PyResult<Self> {
        Ok(Self {
            m: self.m.with_input(argument_of(input)?).py_err()?,
        })
    }

    /// The product PSH (41), channel by channel (a one-channel vector is applied to
    /// every channel).
    fn apply(&self, py: Python<'_>, f: &PshVector) -> PyResult<PshVector> {
        py.detach(|| self.m.apply(&f.v))
            .py_err()
            .map(PshVector::wrap)
    }

    /// `P @ f`: [`Self::apply`].
    fn __matmul__(&self, py: Python<'_>, f: PyRef<'_, PshVector>) -> PyResult<PshVector> {
        self.apply(py, &f)
    }

    /// From `blocks` `(channels, pairs, 4, 4)` in the order of `isotropic_pairs(lmax)`
    /// (what `blocks()` returns), with the argument conventions of input and output.
    #[staticmethod]
    #[pyo3(signature = (blocks, input = "towards-source", output = "travel"))]
    fn from_blocks(blocks: &Bound<'_, PyAny>, input: &str, output: &str) -> PyResult<Self> {
        let a = f64_array(blocks)?;
        let (channels, pairs) = match a.shape() {
            [c, k, 4, 4] => (*c, *k),
            s => {
                return Err(bad(
                    "blocks",
                    format!("shape {s:?}, expected (channels, pairs, 4, 4)"),
                ))
            }
        };
        let lmax = psh::polarized::isotropic_lmax(pairs).ok_or_else(|| {
            bad(
                "blocks",
                format!("{pairs} pairs: no band limit's isotropic layout has that many"),
            )
        })?;
        let m =
            psh::polarized::IsotropicMatrix::from_blocks(lmax, channels, slice(&a)?).py_err()?;
        Ok(Self {
            m: m.labelled(argument_of(input)?, argument_of(output)?),
        })
    }

    /// Pickling, `copy.copy` and `copy.deepcopy`: `IsotropicMatrix.from_blocks` of the
    /// blocks and conventions.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Reduced<'py>> {
        let from = py.get_type::<Self>().getattr("from_blocks")?;
        Ok((from, (self.blocks(py)?, self.input(), self.output())))
    }

    fn __repr__(&self) -> String {
        format!(
            "IsotropicMatrix(lmax={}, channels={}, input={}, output={})",
            self.m.lmax(),
            self.m.channels(),
            self.input(),
            self.output()
        )
    }
}

/// The flat index pairs `(j_o, j_i)` the isotropic layout of band limit `lmax` stores, in
/// its order.
#[pyfunction]
fn isotropic_pairs(lmax: usize) -> PyResult<Vec<(usize, usize)>> {
    // Each pair a tuple of two Python ints: about 96 bytes (12 words).
    let count = psh::polarized::isotropic_pair_count(lmax).unwrap_or(usize::MAX);
    checked_len("isotropic pairs", &[count, 12])?;
    Ok(psh::polarized::isotropic_pairs(lmax))
}

/// The PSH matrix PSH (40) of a pBRDF model (`Conductor` or `PolarizedPlastic`, in the
/// local frame of a surface with normal +z), band limit `lmax`, integrated on the exact
/// grid of band `grid_lmax` (default `max(lmax, 2)`); the 2-to-2 block by the complex
/// pair (PSH (51b)-(51c)) or by `"four-integrals"` (PSH (40) as written).
#[pyfunction]
#[pyo3(signature = (model, lmax, grid_lmax = None, block = "complex-pair"))]
fn project_pbrdf(
    py: Python<'_>,
    model: &Bound<'_, PyAny>,
    lmax: usize,
    grid_lmax: Option<usize>,
    block: &str,
) -> PyResult<PshMatrix> {
    let block = match block {
        "complex-pair" => SpinBlock22::ComplexPair,
        "four-integrals" => SpinBlock22::FourIntegrals,
        b => {
            return Err(bad(
                "block",
                format!("{b:?} (expected \"complex-pair\" or \"four-integrals\")"),
            ))
        }
    };
    let grid = grid_lmax.unwrap_or(lmax.max(2));
    let project = |field: &(dyn psh::stokes::MuellerField + Sync)| {
        crate::interrupt::interruptible(py, |progress| {
            psh::polarized::project_operator_with(field, lmax, grid, block, progress)
        })
    };
    let m = if let Ok(c) = model.cast::<Conductor>() {
        project(&c.get().model)
    } else if let Ok(p) = model.cast::<PolarizedPlastic>() {
        project(&p.get().model)
    } else {
        return Err(bad(
            "model",
            "expected psh.Conductor or psh.PolarizedPlastic",
        ));
    };
    Ok(PshMatrix { m: m? })
}

/// Precomputed couplings of shadowing triple products PSH (54)-(56): visibilities of
/// degree `<= lv`, transfer matrices of band limit `lmax`.
#[pyclass(module = "psh", frozen)]
pub struct TripleTable {
    t: psh::polarized::TripleTable,
}

#[pymethods]
impl TripleTable {
    #[new]
    #[pyo3(signature = (lv, lmax, codomain = "POLAR4"))]
    fn new(py: Python<'_>, lv: usize, lmax: usize, codomain: &str) -> PyResult<Self> {
        let codomain = Codomain::from_name(codomain).py_err()?;
        let t = py
            .detach(|| psh::polarized::TripleTable::for_codomain(lv, lmax, codomain))
            .py_err()?;
        Ok(Self { t })
    }

    /// The PSH matrix of `f -> V f` for the visibility `v` (one-channel `SCALAR` vector).
    fn transfer(&self, py: Python<'_>, v: &PshVector) -> PyResult<PshMatrix> {
        let m = py.detach(|| self.t.transfer(&v.v)).py_err()?;
        Ok(PshMatrix { m })
    }

    /// The coefficients of `V f` (PSH (54)).
    fn shadow(&self, py: Python<'_>, v: &PshVector, f: &PshVector) -> PyResult<PshVector> {
        py.detach(|| self.t.shadow(&v.v, &f.v))
            .py_err()
            .map(PshVector::wrap)
    }
}

/// The PSH matrix of `f -> V f` (PSH (54)-(56)) for the visibility `v`, band limit `lmax`.
#[pyfunction]
fn visibility_transfer(py: Python<'_>, v: &PshVector, lmax: usize) -> PyResult<PshMatrix> {
    let m = py
        .detach(|| psh::polarized::visibility_transfer(&v.v, lmax))
        .py_err()?;
    Ok(PshMatrix { m })
}

/// Adds the functions of this file to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(isotropic_pairs, m)?)?;
    m.add_function(wrap_pyfunction!(project_pbrdf, m)?)?;
    m.add_function(wrap_pyfunction!(visibility_transfer, m)?)?;
    Ok(())
}
