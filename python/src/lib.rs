//! `psh` for Python: a thin PyO3 layer over the Rust crate `psh` (package
//! `polarized-sh`). Every computation is the crate's; this layer converts numpy arrays
//! and Python values to the crate's types and back, maps `psh::Error` to Python
//! exceptions, and releases the GIL around long calls.

mod arrays;
mod convolution;
mod errors;
mod harmonics;
mod interrupt;
mod jobs;
mod maps;
mod measured;
mod pbrdf;
mod rotation;
mod vector;

use pyo3::prelude::*;

/// Polarized spherical harmonics (Yi et al., SIGGRAPH 2024): the Rust crate psh from numpy.
#[pymodule]
fn psh(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<rotation::Rotation>()?;
    m.add_class::<vector::FrameField>()?;
    m.add_class::<vector::PshVector>()?;
    m.add_class::<convolution::ConvolutionKernel>()?;
    m.add_class::<convolution::KernelCoefficients>()?;
    m.add_class::<pbrdf::Conductor>()?;
    m.add_class::<pbrdf::PolarizedPlastic>()?;
    m.add_class::<pbrdf::PshMatrix>()?;
    m.add_class::<pbrdf::IsotropicMatrix>()?;
    m.add_class::<pbrdf::TripleTable>()?;
    harmonics::register(m)?;
    maps::register(m)?;
    pbrdf::register(m)?;
    measured::register(m)?;
    jobs::register(m)?;
    Ok(())
}
