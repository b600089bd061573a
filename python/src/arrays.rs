//! numpy arrays in and out: inputs become C-contiguous float64 (no copy when they already
//! are) and are read in place; outputs are new arrays that own the crate's results.

use crate::errors::{bad, IntoPy};
use numpy::ndarray::{ArrayD, IxDyn};
use numpy::prelude::*;
use numpy::{IntoPyArray, PyArrayDyn, PyReadonlyArrayDyn};
use pyo3::prelude::*;

/// `obj` as a read-only C-contiguous float64 array (numpy.ascontiguousarray: no copy for
/// an array that already is one). Error: complex values (numpy would drop their
/// imaginary parts with only a warning).
pub fn f64_array<'py>(obj: &Bound<'py, PyAny>) -> PyResult<PyReadonlyArrayDyn<'py, f64>> {
    let py = obj.py();
    let np = py.import("numpy")?;
    if np.call_method1("iscomplexobj", (obj,))?.is_truthy()? {
        return Err(bad(
            "array",
            "complex values; psh takes real arrays (complex values as [re, im] pairs where a \
             function takes them)",
        ));
    }
    let kwargs = pyo3::types::PyDict::new(py);
    kwargs.set_item("dtype", np.getattr("float64")?)?;
    let a = np.call_method("ascontiguousarray", (obj,), Some(&kwargs))?;
    let a = a.cast_into::<PyArrayDyn<f64>>()?;
    Ok(a.readonly())
}

/// The values of a contiguous array.
pub fn slice<'a>(a: &'a PyReadonlyArrayDyn<'_, f64>) -> PyResult<&'a [f64]> {
    a.as_slice().map_err(|e| bad("array", e))
}

/// An `(..., k)` array as rows of `k` values, with the leading shape; error naming
/// `name` if the last axis is not `k` long.
pub fn rows<'a, const K: usize>(
    a: &'a PyReadonlyArrayDyn<'_, f64>,
    name: &str,
) -> PyResult<(Vec<usize>, &'a [[f64; K]])> {
    let shape = a.shape();
    if shape.last() != Some(&K) {
        return Err(bad(name, format!("shape {shape:?}, expected (..., {K})")));
    }
    let flat = slice(a)?;
    let (chunks, rest) = flat.as_chunks::<K>();
    debug_assert!(rest.is_empty());
    Ok((shape[..shape.len() - 1].to_vec(), chunks))
}

/// Largest `| |w| - 1 |` of a single-precision direction that is renormalized: a unit
/// vector rounded to float32 is within `3 eps_32 / 2 = 1.8e-7` of norm 1, and a vector
/// computed in float32 a few roundings further; float64 directions are taken as they
/// are (unit within `psh::geometry::UNIT_TOLERANCE`).
pub const SINGLE_PRECISION_UNIT_TOLERANCE: f64 = 1e-6;

/// Whether `obj` is an array of floats narrower than float64 (float32, float16).
fn single_precision(obj: &Bound<'_, PyAny>) -> PyResult<bool> {
    let Ok(dtype) = obj.getattr("dtype") else {
        return Ok(false);
    };
    let kind: String = dtype.getattr("kind")?.extract()?;
    let size: usize = dtype.getattr("itemsize")?.extract()?;
    Ok(kind == "f" && size < 8)
}

/// Unit directions `(..., 3)` with the leading shape; a float32 (float16) array's rows
/// are renormalized when within [`SINGLE_PRECISION_UNIT_TOLERANCE`] of unit norm, and
/// refused (naming the row and its norm) beyond it.
pub fn directions(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<(Vec<usize>, Vec<[f64; 3]>)> {
    let single = single_precision(obj)?;
    let a = f64_array(obj)?;
    let (lead, w) = rows::<3>(&a, name)?;
    if !single {
        return Ok((lead, w.to_vec()));
    }
    let w = w
        .iter()
        .map(|&w| renormalized(w, name))
        .collect::<PyResult<_>>()?;
    Ok((lead, w))
}

/// One unit direction `(3,)`, renormalized as in [`directions`] when single precision.
pub fn direction(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<[f64; 3]> {
    let w = fixed::<3>(obj, name)?;
    if single_precision(obj)? {
        renormalized(w, name)
    } else {
        Ok(w)
    }
}

/// `w / |w|` for a single-precision `w` within [`SINGLE_PRECISION_UNIT_TOLERANCE`] of
/// unit norm.
fn renormalized(w: [f64; 3], name: &str) -> PyResult<[f64; 3]> {
    let norm = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    if !norm.is_finite() || (norm - 1.0).abs() > SINGLE_PRECISION_UNIT_TOLERANCE {
        return Err(bad(
            name,
            format!(
                "{w:?} has norm {norm}: a single-precision direction must be unit within \
                 {SINGLE_PRECISION_UNIT_TOLERANCE:e} (it is renormalized)"
            ),
        ));
    }
    Ok(w.map(|c| c / norm))
}

/// What `__reduce__` returns for an object rebuilt from an array and two convention
/// names (pickling, `copy`): the constructor, and its arguments.
pub type Reduced<'py> = (
    Bound<'py, PyAny>,
    (Bound<'py, PyArrayDyn<f64>>, &'static str, &'static str),
);

/// A new numpy array of `shape` owning `data` (row-major).
pub fn owned<'py, T: numpy::Element>(
    py: Python<'py>,
    shape: &[usize],
    data: Vec<T>,
) -> PyResult<Bound<'py, PyArrayDyn<T>>> {
    let a = ArrayD::from_shape_vec(IxDyn(shape), data).map_err(|e| bad("array shape", e))?;
    Ok(a.into_pyarray(py))
}

/// A fixed-size vector from a 1-D array-like of `K` numbers.
pub fn fixed<const K: usize>(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<[f64; K]> {
    let a = f64_array(obj)?;
    let s = slice(&a)?;
    if a.shape() != [K] {
        return Err(bad(name, format!("shape {:?}, expected ({K},)", a.shape())));
    }
    let mut out = [0.0; K];
    out.copy_from_slice(s);
    Ok(out)
}

/// The number of float64 elements `product(factors)` of an output named `name`, checked
/// against psh's memory budget before anything is allocated (`MemoryError` over it).
pub fn checked_len(name: &'static str, factors: &[usize]) -> PyResult<usize> {
    psh::budget::check(name, factors, 8).py_err()
}
