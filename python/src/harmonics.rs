//! Evaluation of the bases at arrays of directions: real and complex SH (PSH (12), (1)),
//! spin-weighted SH (PSH (26)), and Wigner D blocks, complex and real (PSH (9), (13)).

use crate::arrays::{checked_len, directions, owned};
use crate::errors::IntoPy;
use crate::rotation::rotation_of;
use num_complex::Complex64;
use numpy::PyArrayDyn;
use psh::geometry::direction_angles;
use psh::sh::{num_coeffs, RealWignerD, ShEvaluator, WignerD};
use psh::swsh::SpinEvaluator;
use pyo3::prelude::*;
use rayon::prelude::*;

/// Real SH `Y^R_lm` PSH (12) for all `l <= lmax` at unit directions `dirs` of shape
/// `(..., 3)`: shape `(..., (lmax+1)^2)`, flat index `l*l + l + m`.
#[pyfunction]
fn sh_real<'py>(
    py: Python<'py>,
    lmax: usize,
    dirs: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let eval = ShEvaluator::new(lmax).py_err()?;
    let (lead, w) = directions(dirs, "directions")?;
    let n = num_coeffs(lmax);
    let mut out = vec![0.0; checked_len("SH values", &[w.len(), n])?];
    // real_batch runs blocks of directions in parallel itself.
    py.detach(|| eval.real_batch(&w, &mut out)).py_err()?;
    owned(py, &[lead, vec![n]].concat(), out)
}

/// Complex values per direction of a basis of `(lmax+1)^2` functions of `(theta, phi)`.
fn complex_basis<'py>(
    py: Python<'py>,
    lmax: usize,
    dirs: &Bound<'py, PyAny>,
    f: impl Fn(f64, f64, &mut [Complex64]) -> psh::Result<()> + Sync,
) -> PyResult<Bound<'py, PyArrayDyn<Complex64>>> {
    let (lead, w) = directions(dirs, "directions")?;
    let n = num_coeffs(lmax);
    let mut out = vec![Complex64::default(); checked_len("SH values", &[w.len(), n, 2])? / 2];
    py.detach(|| {
        out.par_chunks_mut(n)
            .zip(w.par_iter())
            .try_for_each(|(o, &d)| {
                let (theta, phi) = direction_angles(d)?;
                f(theta, phi, o)
            })
    })
    .py_err()?;
    owned(py, &[lead, vec![n]].concat(), out)
}

/// Complex SH `Y_lm` PSH (1) for all `l <= lmax` at unit directions `(..., 3)`:
/// complex128 of shape `(..., (lmax+1)^2)`, flat index `l*l + l + m`.
#[pyfunction]
fn sh_complex<'py>(
    py: Python<'py>,
    lmax: usize,
    dirs: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArrayDyn<Complex64>>> {
    let eval = ShEvaluator::new(lmax).py_err()?;
    complex_basis(py, lmax, dirs, |t, p, o| eval.complex(t, p, o))
}

/// Spin-weighted SH `sY_lm` PSH (26)-(27) for all `l <= lmax` at unit directions
/// `(..., 3)`: complex128 of shape `(..., (lmax+1)^2)`, zeros where `l < |spin|`; spin 0
/// is the complex SH `Y_lm`.
#[pyfunction]
fn swsh<'py>(
    py: Python<'py>,
    spin: i64,
    lmax: usize,
    dirs: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArrayDyn<Complex64>>> {
    if spin == 0 {
        return sh_complex(py, lmax, dirs);
    }
    let eval = SpinEvaluator::new(spin, lmax).py_err()?;
    complex_basis(py, lmax, dirs, |t, p, o| eval.values(t, p, o))
}

/// Checks the memory of the `O(lmax^3)` blocks and their arrays before any is allocated:
/// `sum (2l+1)^2 < (4/3) (lmax+1)^3` complex numbers twice, below `6 (lmax+1)^3` floats.
fn wigner_size(lmax: usize) -> PyResult<()> {
    let l = lmax.saturating_add(1);
    checked_len("Wigner D blocks and their arrays", &[l, l, l, 6]).map(|_| ())
}

/// The complex Wigner blocks `D^l_{m m'}(R)` PSH (9), `l <= lmax`: a list of complex128
/// arrays of shape `(2l+1, 2l+1)`, rows `m`, columns `m'` from `-l`.
#[pyfunction]
fn wigner_d<'py>(
    py: Python<'py>,
    rotation: &Bound<'py, PyAny>,
    lmax: usize,
) -> PyResult<Vec<Bound<'py, PyArrayDyn<Complex64>>>> {
    wigner_size(lmax)?;
    let r = rotation_of(rotation)?;
    let d = py.detach(|| WignerD::new(&r, lmax)).py_err()?;
    (0..=lmax)
        .map(|l| owned(py, &[2 * l + 1, 2 * l + 1], d.block(l).py_err()?.to_vec()))
        .collect()
}

/// The real Wigner blocks PSH (13) (rotation of real SH coefficients), `l <= lmax`: a
/// list of float64 arrays of shape `(2l+1, 2l+1)`, rows `m`, columns `m'` from `-l`.
#[pyfunction]
fn wigner_d_real<'py>(
    py: Python<'py>,
    rotation: &Bound<'py, PyAny>,
    lmax: usize,
) -> PyResult<Vec<Bound<'py, PyArrayDyn<f64>>>> {
    wigner_size(lmax)?;
    let r = rotation_of(rotation)?;
    let d = py.detach(|| RealWignerD::new(&r, lmax)).py_err()?;
    (0..=lmax)
        .map(|l| owned(py, &[2 * l + 1, 2 * l + 1], d.block(l).py_err()?.to_vec()))
        .collect()
}

/// Adds the functions of this file to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(sh_real, m)?)?;
    m.add_function(wrap_pyfunction!(sh_complex, m)?)?;
    m.add_function(wrap_pyfunction!(swsh, m)?)?;
    m.add_function(wrap_pyfunction!(wigner_d, m)?)?;
    m.add_function(wrap_pyfunction!(wigner_d_real, m)?)?;
    Ok(())
}
