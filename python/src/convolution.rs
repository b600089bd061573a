//! Polarized spherical convolution (PSH Sec. 6.4): kernels `k(theta)` (PSH (61)-(62))
//! from a numpy table, a Python callable or a CSV file, their coefficients `G_l`
//! (PSH (68a)-(68e)) and the convolution theorem PSH (69a)-(69c).

use crate::arrays::{f64_array, owned, slice};
use crate::errors::{bad, IntoPy};
use crate::vector::PshVector;
use numpy::prelude::*;
use numpy::PyArrayDyn;
use psh::polarized::KernelValue;
use pyo3::prelude::*;
use std::sync::{Arc, Mutex};

/// `(n, 4, 4)` values as 4 x 4 kernel values.
fn kernel_values(a: &numpy::PyReadonlyArrayDyn<'_, f64>, name: &str) -> PyResult<Vec<KernelValue>> {
    if a.shape().len() != 3 || a.shape()[1..] != [4, 4] {
        return Err(bad(
            name,
            format!("shape {:?}, expected (n, 4, 4)", a.shape()),
        ));
    }
    let (m, _) = slice(a)?.as_chunks::<16>();
    Ok(m.iter()
        .map(|v| std::array::from_fn(|r| std::array::from_fn(|c| v[4 * r + c])))
        .collect())
}

/// A 4 x 4 kernel value as a `(4, 4)` array.
fn value_array<'py>(py: Python<'py>, k: &KernelValue) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    owned(py, &[4, 4], k.iter().flatten().copied().collect())
}

/// A convolution kernel `k: [0, pi] -> R^{4x4}` (PSH (62)), rows the output Stokes
/// component, read between the frames whose `x` axes run along the great circle from the
/// input to the output direction (PSH (61)).
#[pyclass(module = "psh", frozen)]
pub struct ConvolutionKernel {
    source: Source,
}

/// Where a kernel's values come from.
enum Source {
    /// A table or a built-in kernel.
    Native(psh::polarized::ConvolutionKernel),
    /// A Python callable, wrapped anew for each call so that what it raises belongs to
    /// that call alone (two threads using one kernel each see their own exception).
    Callable(Py<PyAny>),
}

impl ConvolutionKernel {
    fn wrap(kernel: psh::polarized::ConvolutionKernel) -> Self {
        Self {
            source: Source::Native(kernel),
        }
    }

    /// Runs `body` with the kernel; a callable's first exception (or bad return value)
    /// during this call is raised instead of the result.
    fn with_kernel<T>(
        &self,
        body: impl FnOnce(&psh::polarized::ConvolutionKernel) -> T,
    ) -> PyResult<T> {
        match &self.source {
            Source::Native(k) => Ok(body(k)),
            Source::Callable(f) => {
                let raised: Arc<Mutex<Option<PyErr>>> = Arc::default();
                let slot = raised.clone();
                let f = Python::attach(|py| f.clone_ref(py));
                let kernel =
                    psh::polarized::ConvolutionKernel::from_fn(move |t| call_kernel(&f, t, &slot));
                let out = body(&kernel);
                let first = raised.lock().unwrap_or_else(|p| p.into_inner()).take();
                match first {
                    Some(e) => Err(e),
                    None => Ok(out),
                }
            }
        }
    }
}

/// `f(theta)` as a kernel value; the first problem is kept in `raised`.
fn call_kernel(f: &Py<PyAny>, theta: f64, raised: &Mutex<Option<PyErr>>) -> KernelValue {
    let value = Python::attach(|py| -> PyResult<KernelValue> {
        let out = f.call1(py, (theta,))?;
        let a = f64_array(out.bind(py))?;
        if a.shape() != [4, 4] {
            return Err(bad(
                "kernel value",
                format!("shape {:?} at theta = {theta}, expected (4, 4)", a.shape()),
            ));
        }
        let s = slice(&a)?;
        Ok(std::array::from_fn(|r| {
            std::array::from_fn(|c| s[4 * r + c])
        }))
    });
    value.unwrap_or_else(|e| {
        raised
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .get_or_insert(e);
        [[f64::NAN; 4]; 4]
    })
}

#[pymethods]
impl ConvolutionKernel {
    /// A kernel tabulated at angles `theta` `(n,)` (strictly increasing from 0 to pi)
    /// with values `(n, 4, 4)`, linearly interpolated.
    #[staticmethod]
    fn from_table(theta: &Bound<'_, PyAny>, values: &Bound<'_, PyAny>) -> PyResult<Self> {
        let t = f64_array(theta)?;
        let v = f64_array(values)?;
        let kernel = psh::polarized::ConvolutionKernel::from_table(
            slice(&t)?.to_vec(),
            kernel_values(&v, "kernel values")?,
        )
        .py_err()?;
        Ok(Self::wrap(kernel))
    }

    /// A kernel from a Python callable `f(theta) -> (4, 4)` array-like. An exception it
    /// raises (or a value of another shape) is raised again by `coefficients`.
    #[staticmethod]
    fn from_callable(f: Py<PyAny>) -> Self {
        Self {
            source: Source::Callable(f),
        }
    }

    /// The built-in kernel `linear-zenith` of `psh convolve`.
    #[staticmethod]
    fn linear_zenith() -> Self {
        Self::wrap(psh::polarized::ConvolutionKernel::linear_zenith())
    }

    /// A kernel table from a CSV file (`psh convolve --kernel` format).
    #[staticmethod]
    fn read_csv(path: std::path::PathBuf) -> PyResult<Self> {
        Ok(Self::wrap(psh::io::read_kernel_csv(path).py_err()?))
    }

    /// `k(theta)` as a `(4, 4)` array.
    fn value<'py>(&self, py: Python<'py>, theta: f64) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let k = self.with_kernel(|k| k.value(theta))?;
        value_array(py, &k.py_err()?)
    }

    /// The convolution coefficients `G_l`, `l <= lmax` (PSH (68a)-(68e), composite
    /// Gauss-Legendre quadrature in theta).
    fn coefficients(&self, py: Python<'_>, lmax: usize) -> PyResult<KernelCoefficients> {
        let g = py.detach(|| self.with_kernel(|k| psh::polarized::kernel_coefficients(k, lmax)))?;
        Ok(KernelCoefficients { g: g.py_err()? })
    }
}

/// Convolution coefficients `G_l` of a kernel (PSH (68a)-(68e)), applied to PSH vectors
/// by the convolution theorem PSH (69a)-(69c).
#[pyclass(module = "psh", frozen)]
pub struct KernelCoefficients {
    g: psh::polarized::KernelCoefficients,
}

#[pymethods]
impl KernelCoefficients {
    /// From the real forms `g_l` `(lmax+1, 4, 4)`.
    #[staticmethod]
    fn from_real_form(g: &Bound<'_, PyAny>) -> PyResult<Self> {
        let a = f64_array(g)?;
        let g =
            psh::polarized::KernelCoefficients::from_real_form(&kernel_values(&a, "real forms")?)
                .py_err()?;
        Ok(Self { g })
    }

    /// The band limit.
    #[getter]
    fn lmax(&self) -> usize {
        self.g.lmax()
    }

    /// The quadrature's error estimate (zero when built from real forms).
    #[getter]
    fn error_estimate(&self) -> f64 {
        self.g.error_estimate()
    }

    /// The real forms `g_l = A^-1 G_l A` of every band, `(lmax+1, 4, 4)`.
    fn real_form<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let n = self.g.lmax() + 1;
        let data: Vec<f64> = (0..n)
            .flat_map(|l| self.g.real_form(l).into_iter().flatten().flatten())
            .collect();
        owned(py, &[n, 4, 4], data)
    }

    /// The band-limited kernel of these coefficients at `theta`, `(4, 4)`.
    fn synthesize<'py>(
        &self,
        py: Python<'py>,
        theta: f64,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        value_array(py, &self.g.synthesize(theta).py_err()?)
    }

    /// The PSH coefficients of `k * f` (PSH (69a)-(69c)), all four Stokes components,
    /// indexed as `f` is.
    fn convolve(&self, py: Python<'_>, f: &PshVector) -> PyResult<PshVector> {
        py.detach(|| self.g.convolve(&f.v))
            .py_err()
            .map(PshVector::wrap)
    }
}
