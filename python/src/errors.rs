//! psh's errors as Python exceptions, with psh's message: `OSError` for files
//! (unreadable, malformed, missing shared data), `MemoryError` for work over the memory
//! budget (`psh::budget`), `KeyboardInterrupt` for interrupted work, `ValueError` for
//! every other bad value.

use pyo3::exceptions::{PyKeyboardInterrupt, PyMemoryError, PyOSError, PyValueError};
use pyo3::PyErr;

/// The Python exception of a psh error.
pub fn to_py(e: psh::Error) -> PyErr {
    match e {
        psh::Error::Io { .. }
        | psh::Error::MalformedFile { .. }
        | psh::Error::DataMissing { .. } => PyOSError::new_err(e.to_string()),
        psh::Error::MemoryBudget { .. } => PyMemoryError::new_err(e.to_string()),
        psh::Error::Interrupted { .. } => PyKeyboardInterrupt::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// `Result` of psh into `PyResult`.
pub trait IntoPy<T> {
    /// The value, or the psh error as a Python exception.
    fn py_err(self) -> pyo3::PyResult<T>;
}

impl<T> IntoPy<T> for psh::Result<T> {
    fn py_err(self) -> pyo3::PyResult<T> {
        self.map_err(to_py)
    }
}

/// A `ValueError` naming the argument and what was wrong with it.
pub fn bad(name: &str, reason: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("invalid {name}: {reason}"))
}
