//! Measured pBRDF tables (`psh::optics::TabulatedPbrdf`; Mitsuba 3 `.pbsdf` files, KAIST
//! MAT-files): read,
//! described, converted to RGB and projected to isotropic PSH matrices.

use crate::errors::IntoPy;
use crate::pbrdf::IsotropicMatrix;
use psh::polarized::project_isotropic_with;
use pyo3::prelude::*;

/// A measured pBRDF table: Mueller matrices on a Rusinkiewicz grid per wavelength.
#[pyclass(module = "psh", frozen)]
pub struct MeasuredPbrdf {
    t: psh::optics::TabulatedPbrdf,
}

#[pymethods]
impl MeasuredPbrdf {
    /// The wavelengths (nm), one per channel.
    #[getter]
    fn wavelengths(&self) -> Vec<f64> {
        self.t.wavelengths_nm().to_vec()
    }

    /// The `(phi_d, theta_d, theta_h)` sample counts.
    #[getter]
    fn shape(&self) -> (usize, usize, usize) {
        (
            self.t.phi_d().len(),
            self.t.theta_d().len(),
            self.t.theta_h().len(),
        )
    }

    /// The fraction of samples marked invalid (NaN).
    #[getter]
    fn invalid_fraction(&self) -> f64 {
        self.t.invalid_fraction()
    }

    /// The table in linear sRGB from the KAIST dataset's five bands, as its own code
    /// converts them.
    fn to_rgb(&self) -> PyResult<Self> {
        Ok(Self {
            t: self.t.to_rgb().py_err()?,
        })
    }

    /// Isotropic PSH matrices (PSH (40), (52)) of band limit `lmax`, one channel per
    /// wavelength, on the exact grid of band `grid_lmax` (default `max(lmax, 19)` rounded
    /// up to odd: an even number of rings, none on the horizon, where a pBRDF steps to
    /// zero, and at least the table's resolution);
    /// `tolerance` the largest isotropy defect accepted (a table is isotropic by
    /// construction: the defect is the quadrature's aliasing of a piecewise-linear table;
    /// those entries are dropped). Ctrl-C interrupts it.
    #[pyo3(signature = (lmax, grid_lmax = None, tolerance = 1e-3))]
    fn project(
        &self,
        py: Python<'_>,
        lmax: usize,
        grid_lmax: Option<usize>,
        tolerance: f64,
    ) -> PyResult<IsotropicMatrix> {
        let grid = grid_lmax.unwrap_or(psh::polarized::table_grid(lmax));
        let m = crate::interrupt::interruptible(py, |progress| {
            let channels = (0..self.t.wavelengths_nm().len())
                .map(|k| self.t.channel(k))
                .collect::<psh::Result<Vec<_>>>()?;
            let fields: Vec<&dyn psh::stokes::MuellerField> =
                channels.iter().map(|c| c as _).collect();
            project_isotropic_with(&fields, lmax, grid, tolerance, progress).map(|p| p.matrix)
        })?;
        Ok(IsotropicMatrix { m })
    }

    fn __repr__(&self) -> String {
        let (p, d, h) = self.shape();
        format!(
            "MeasuredPbrdf(phi_d={p}, theta_d={d}, theta_h={h}, wavelengths={:?})",
            self.t.wavelengths_nm()
        )
    }
}

/// Reads a measured pBRDF table: a Mitsuba 3 `.pbsdf`, or a KAIST dataset MAT data file
/// with the Stokes frames of its `info` file (without one, in the convention of psh's
/// tables).
#[pyfunction]
#[pyo3(signature = (path, info = None))]
fn read_measured_pbrdf(
    path: std::path::PathBuf,
    info: Option<std::path::PathBuf>,
) -> PyResult<MeasuredPbrdf> {
    Ok(MeasuredPbrdf {
        t: psh::io::read_measured_pbrdf(path, info.as_deref())
            .py_err()?
            .table,
    })
}

/// Adds the class and function of this file to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<MeasuredPbrdf>()?;
    m.add_function(wrap_pyfunction!(read_measured_pbrdf, m)?)?;
    Ok(())
}
