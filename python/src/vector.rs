//! PSH coefficient vectors PSH (34) `(channels, (lmax+1)^2, components)` with their
//! codomain and argument convention, and the frame fields their Stokes vectors are
//! read in.

use crate::arrays::{checked_len, directions, f64_array, owned, slice, Reduced};
use crate::errors::{bad, IntoPy};
use crate::rotation::rotation_of;
use numpy::prelude::*;
use numpy::PyArrayDyn;
use psh::geometry::FrameField as _;
use psh::geometry::{CubeMapFrameField, Frame, PerspectiveFrameField, ThetaPhiFrameField};
use psh::polarized::{Codomain, FieldArgument, PshEvaluator};
use psh::stokes::FrameChange;
use pyo3::prelude::*;
use rayon::prelude::*;

/// Directions per parallel task.
const CHUNK: usize = 256;

/// A field's argument convention from its name: `"towards-source"` or `"travel"`.
pub fn argument_of(name: &str) -> PyResult<FieldArgument> {
    [FieldArgument::TowardsSource, FieldArgument::Travel]
        .into_iter()
        .find(|a| a.name() == name)
        .ok_or_else(|| {
            bad(
                "argument",
                format!("{name:?} (expected \"towards-source\" or \"travel\")"),
            )
        })
}

/// A frame field: the Stokes frame assigned to each direction.
#[derive(Clone, Copy)]
pub enum Field {
    ThetaPhi,
    CubeMap,
    Perspective(PerspectiveFrameField),
}

impl psh::geometry::FrameField for Field {
    fn frame(&self, w: [f64; 3]) -> psh::Result<Frame> {
        match self {
            Field::ThetaPhi => ThetaPhiFrameField::new().frame(w),
            Field::CubeMap => CubeMapFrameField.frame(w),
            Field::Perspective(p) => p.frame(w),
        }
    }
}

/// A frame field (PSH Sec. 5.1): the theta-phi field PSH (28) (`x = e_theta`,
/// `y = e_phi`), the cube-map field of the shared maps, or a perspective camera's.
#[pyclass(module = "psh", frozen)]
#[derive(Clone)]
pub struct FrameField {
    field: Field,
}

#[pymethods]
impl FrameField {
    /// The theta-phi frame field PSH (28), psh's and polarsh's frames of coefficients.
    #[staticmethod]
    fn theta_phi() -> Self {
        Self {
            field: Field::ThetaPhi,
        }
    }

    /// The cube-map frame field: on each face the 90-degree camera's frame (x
    /// image-right, y image-down), as the shared EXR cube maps store their texels.
    #[staticmethod]
    fn cube_map() -> Self {
        Self {
            field: Field::CubeMap,
        }
    }

    /// The frame field of a perspective camera looking along `forward` with image-up
    /// `up` (x image-right, y image-down, z the pixel's direction).
    #[staticmethod]
    fn perspective(forward: &Bound<'_, PyAny>, up: &Bound<'_, PyAny>) -> PyResult<Self> {
        let f = crate::arrays::direction(forward, "forward")?;
        let u = crate::arrays::fixed::<3>(up, "up")?;
        Ok(Self {
            field: Field::Perspective(PerspectiveFrameField::look(f, u).py_err()?),
        })
    }

    /// The frame `[x, y, z]` (rows) at unit direction `w`.
    fn frame<'py>(
        &self,
        py: Python<'py>,
        w: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let w = crate::arrays::direction(w, "direction")?;
        let f = psh::geometry::FrameField::frame(&self.field, w).py_err()?;
        let axes = [f.x(), f.y(), f.z()];
        owned(
            py,
            &[3, 3],
            axes.iter().flat_map(|a| [a.x, a.y, a.z]).collect(),
        )
    }
}

impl FrameField {
    /// The theta-phi field unless another is given.
    pub fn or_theta_phi(f: Option<&FrameField>) -> Field {
        f.map_or(Field::ThetaPhi, |f| f.field)
    }
}

/// The polarsh codomain name of `p` components per coefficient.
fn codomain_of(name: &str) -> PyResult<Codomain> {
    Codomain::from_name(name).py_err()
}

/// A PSH coefficient vector PSH (34): real coefficients `coeffs[channel, l*l + l + m, k]`
/// of the Stokes components of the codomain (`k` runs over them: `SCALAR` {s0},
/// `POLAR2` {s1, s2}, `POLAR3` {s0, s1, s2}, `POLAR4` {s0, s1, s2, s3}), in the
/// theta-phi frame field; `argument` says whether directions point towards the light's
/// source or along its travel (polarsh's files).
#[pyclass(module = "psh", frozen)]
#[derive(Clone)]
pub struct PshVector {
    pub v: psh::polarized::PshVector,
}

impl PshVector {
    pub fn wrap(v: psh::polarized::PshVector) -> Self {
        Self { v }
    }
}

#[pymethods]
impl PshVector {
    /// From `coeffs` of shape `(channels, (lmax+1)^2, components)` or
    /// `((lmax+1)^2, components)` (one channel); coefficients outside the index set
    /// PSH (31) (spin 2 below `l = 2`) must be zero.
    #[new]
    #[pyo3(signature = (coeffs, codomain = "POLAR4", argument = "towards-source"))]
    fn new(coeffs: &Bound<'_, PyAny>, codomain: &str, argument: &str) -> PyResult<Self> {
        let codomain = codomain_of(codomain)?;
        let argument = argument_of(argument)?;
        let a = f64_array(coeffs)?;
        let np = codomain.components().len();
        let (channels, n) = match a.shape() {
            [c, n, p] if *p == np => (*c, *n),
            [n, p] if *p == np => (1, *n),
            s => {
                return Err(bad(
                    "coeffs",
                    format!(
                        "shape {s:?}, expected (channels, (lmax+1)^2, {np}) for {}",
                        codomain.name()
                    ),
                ))
            }
        };
        let l = (n as f64).sqrt().round() as usize;
        if n == 0 || l * l != n {
            return Err(bad(
                "coeffs",
                format!("{n} coefficients per component, not (lmax+1)^2"),
            ));
        }
        let v =
            psh::polarized::PshVector::from_data(l - 1, codomain, channels, slice(&a)?.to_vec())
                .py_err()?;
        Ok(Self::wrap(v.labelled(argument)))
    }

    /// Reads a polarsh `.npz` coefficient file (its field is indexed by the direction of
    /// travel, `argument == "travel"`).
    #[staticmethod]
    fn read_npz(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Self> {
        Ok(Self::wrap(
            py.detach(|| psh::io::read_psh_npz(&path)).py_err()?,
        ))
    }

    /// Writes a polarsh `.npz` file (converted to the travel convention if needed).
    fn write_npz(&self, py: Python<'_>, path: std::path::PathBuf) -> PyResult<()> {
        py.detach(|| psh::io::write_psh_npz(&path, &self.v))
            .py_err()
    }

    /// One vector of the channels of `parts` (same band limit, codomain and argument).
    #[staticmethod]
    fn from_channels(parts: Vec<PyRef<'_, PshVector>>) -> PyResult<Self> {
        let parts: Vec<_> = parts.iter().map(|p| p.v.clone()).collect();
        Ok(Self::wrap(
            psh::polarized::PshVector::from_channels(&parts).py_err()?,
        ))
    }

    /// The band limit.
    #[getter]
    fn lmax(&self) -> usize {
        self.v.lmax()
    }

    /// The number of channels.
    #[getter]
    fn channels(&self) -> usize {
        self.v.channels()
    }

    /// The polarsh codomain name (`SCALAR`, `POLAR2`, `POLAR3`, `POLAR4`).
    #[getter]
    fn codomain(&self) -> &'static str {
        self.v.codomain().name()
    }

    /// The Stokes components `k` runs over (0 = s0, ..., 3 = s3).
    #[getter]
    fn components(&self) -> Vec<usize> {
        self.v.codomain().components().to_vec()
    }

    /// `"towards-source"` or `"travel"`.
    #[getter]
    fn argument(&self) -> &'static str {
        self.v.argument().name()
    }

    /// The coefficients, a read-only copy of shape `(channels, (lmax+1)^2, components)`
    /// (the vector is immutable: writing raises instead of changing nothing; build a new
    /// vector from `coeffs.copy()`).
    #[getter]
    fn coeffs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let shape = [
            self.v.channels(),
            psh::sh::num_coeffs(self.v.lmax()),
            self.v.codomain().components().len(),
        ];
        let a = owned(py, &shape, self.v.data().to_vec())?;
        a.call_method1("setflags", (false,))?;
        Ok(a)
    }

    /// Pickling, `copy.copy` and `copy.deepcopy`: the constructor, from the coefficients,
    /// codomain and argument.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Reduced<'py>> {
        Ok((
            py.get_type::<Self>().into_any(),
            (self.coeffs(py)?, self.codomain(), self.argument()),
        ))
    }

    /// `v + w`: same band limit, codomain, channels and argument (else `ValueError`).
    fn __add__(&self, other: PyRef<'_, PshVector>) -> PyResult<Self> {
        Ok(Self::wrap(self.v.combined(1.0, &other.v, 1.0).py_err()?))
    }

    /// `v - w`, as `v + w`.
    fn __sub__(&self, other: PyRef<'_, PshVector>) -> PyResult<Self> {
        Ok(Self::wrap(self.v.combined(1.0, &other.v, -1.0).py_err()?))
    }

    /// `v * s` for a number `s`.
    fn __mul__(&self, s: f64) -> PyResult<Self> {
        Ok(Self::wrap(self.v.scaled(s).py_err()?))
    }

    /// `s * v` for a number `s`.
    fn __rmul__(&self, s: f64) -> PyResult<Self> {
        self.__mul__(s)
    }

    /// `v / s` for a non-zero number `s`.
    fn __truediv__(&self, s: f64) -> PyResult<Self> {
        if s == 0.0 {
            return Err(pyo3::exceptions::PyZeroDivisionError::new_err(
                "PshVector divided by zero",
            ));
        }
        self.__mul__(1.0 / s)
    }

    /// `-v`.
    fn __neg__(&self) -> PyResult<Self> {
        self.__mul__(-1.0)
    }

    /// The Stokes components `[s0, s1, s2, s3]` PSH (30) of every channel at unit
    /// directions `dirs` `(..., 3)`, in the frames of `frames` (theta-phi by default):
    /// shape `(channels, ..., 4)`. Directions mean what `argument` says.
    #[pyo3(signature = (dirs, frames = None))]
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        dirs: &Bound<'py, PyAny>,
        frames: Option<&FrameField>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let (lead, w) = directions(dirs, "directions")?;
        let out = evaluate_at(py, &self.v, &w, FrameField::or_theta_phi(frames))?;
        owned(py, &[vec![self.v.channels()], lead, vec![4]].concat(), out)
    }

    /// The coefficients of the field turned by `rotation` (PSH (35)-(37): Wigner blocks
    /// on each component, spin 2 rotating as a spin-weighted function), the blocks streamed
    /// one degree at a time.
    fn rotated(&self, py: Python<'_>, rotation: &Bound<'_, PyAny>) -> PyResult<Self> {
        let r = rotation_of(rotation)?;
        py.detach(|| self.v.rotated(&r)).py_err().map(Self::wrap)
    }

    /// The same field under the other argument convention (`"travel"` or
    /// `"towards-source"`, `proofs/travel-convention.md`).
    fn converted(&self, argument: &str) -> PyResult<Self> {
        Ok(Self::wrap(self.v.converted(argument_of(argument)?)))
    }

    /// The coefficients of degrees `l <= lmax`.
    fn truncated(&self, lmax: usize) -> PyResult<Self> {
        Ok(Self::wrap(self.v.truncated(lmax).py_err()?))
    }

    /// Channel `c` alone.
    fn channel(&self, c: usize) -> PyResult<Self> {
        Ok(Self::wrap(self.v.channel(c).py_err()?))
    }

    /// The same coefficients with another codomain (missing components zero, extra ones
    /// dropped).
    fn with_codomain(&self, codomain: &str) -> PyResult<Self> {
        Ok(Self::wrap(self.v.with_codomain(codomain_of(codomain)?)))
    }

    /// The energy of each degree `E_l = sum_{c,m,p} f_lmp^2` (Parseval: the squared L2
    /// norm of band `l`).
    fn band_energies<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let e = self.v.band_energies().py_err()?;
        owned(py, &[e.len()], e)
    }

    fn __repr__(&self) -> String {
        format!(
            "PshVector(lmax={}, channels={}, codomain={}, argument={})",
            self.v.lmax(),
            self.v.channels(),
            self.v.codomain().name(),
            self.v.argument().name()
        )
    }
}

/// The Stokes components of every channel of `v` at `w` in the frames of `field`,
/// `[channel][direction][component]` flattened: PSH (30) over a chunk of directions at
/// once ([`PshEvaluator::evaluate_batch`], in the theta-phi frames PSH (28)), then one
/// frame change PSH (14) per direction for all channels.
pub fn evaluate_at(
    py: Python<'_>,
    v: &psh::polarized::PshVector,
    w: &[[f64; 3]],
    field: Field,
) -> PyResult<Vec<f64>> {
    let nch = v.channels();
    checked_len("Stokes values", &[nch, w.len(), 4])?;
    let mut per_dir = vec![[0.0; 4]; w.len() * nch];
    py.detach(|| {
        w.par_chunks(CHUNK)
            .zip(per_dir.par_chunks_mut(CHUNK * nch))
            .try_for_each(|(d, s)| {
                let mut eval = PshEvaluator::new(v.lmax())?;
                eval.evaluate_batch(v, d, s)?;
                if matches!(field, Field::ThetaPhi) {
                    return Ok(());
                }
                for (&w, s) in d.iter().zip(s.chunks_exact_mut(nch)) {
                    let from = ThetaPhiFrameField::new().frame(w)?;
                    let change = FrameChange::between(&from, &field.frame(w)?)?;
                    s.iter_mut().for_each(|x| *x = change.components(*x));
                }
                psh::Result::Ok(())
            })
    })
    .py_err()?;
    let mut out = Vec::with_capacity(nch * w.len() * 4);
    for c in 0..nch {
        out.extend(per_dir.chunks_exact(nch).flat_map(|s| s[c]));
    }
    Ok(out)
}
