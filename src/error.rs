//! The one error type of the crate: every variant names the offending value.

use std::path::PathBuf;
use thiserror::Error;

/// Everything that can go wrong in psh, with the value that was wrong.
#[derive(Debug, Error)]
pub enum Error {
    /// A real input (angle, coordinate, weight) was NaN or infinite.
    #[error("{name} must be finite, got {value}")]
    NonFinite {
        /// What the value is.
        name: &'static str,
        /// The value given.
        value: f64,
    },

    /// A direction was expected to be a unit vector.
    #[error("direction {value:?} is not a unit vector (norm {norm})")]
    NonUnitDirection {
        /// The direction given.
        value: [f64; 3],
        /// Its Euclidean norm.
        norm: f64,
    },

    /// Two frames (or Stokes vectors, or Mueller transforms) that must belong to the same
    /// ray have different ray directions (their `z` axes differ by more than `tolerance`
    /// in Euclidean distance). PSH (17), (18), (22) are defined only within one ray.
    #[error("{what}: frames of different rays, z = {first:?} and {second:?} (distance {distance:e} > tolerance {tolerance:e})")]
    DifferentRays {
        /// The operation that needed one ray.
        what: &'static str,
        /// The `z` axis (ray direction) of the first frame.
        first: [f64; 3],
        /// The `z` axis of the second frame.
        second: [f64; 3],
        /// `|first - second|`.
        distance: f64,
        /// The largest distance accepted as the same ray.
        tolerance: f64,
    },

    /// A degree (band index) beyond what the routine supports.
    #[error("degree {name} = {value} out of range: {reason}")]
    DegreeOutOfRange {
        /// What the degree is (`l`, `lmax`, ...).
        name: &'static str,
        /// The degree given.
        value: i128,
        /// The range supported, in words.
        reason: String,
    },

    /// An order m with |m| > l, or a spin with |s| > l.
    #[error("order {name} = {m} out of range for degree l = {l} (need |{name}| <= l)")]
    OrderOutOfRange {
        /// What the order is (`m`, `s`, ...).
        name: &'static str,
        /// The degree.
        l: i64,
        /// The order (or spin) given.
        m: i64,
    },

    /// A rotation that cannot be built (zero or non-finite rotation vector, non-orthogonal matrix).
    #[error("invalid rotation {value}: {reason}")]
    InvalidRotation {
        /// The rotation given, as text.
        value: String,
        /// Why it is not a rotation.
        reason: String,
    },

    /// A sampling grid too coarse for the requested band limit.
    #[error("grid too small: {reason}")]
    GridTooSmall {
        /// What the grid needs, in words.
        reason: String,
    },

    /// A buffer or array whose length does not match what the operation needs.
    #[error("length mismatch for {name}: expected {expected}, got {got}")]
    LengthMismatch {
        /// What the buffer is.
        name: &'static str,
        /// The length needed.
        expected: usize,
        /// The length given.
        got: usize,
    },

    /// Any other invalid argument, with its value and the reason.
    #[error("invalid {name} = {value}: {reason}")]
    InvalidArgument {
        /// What the argument is.
        name: &'static str,
        /// The value given, as text.
        value: String,
        /// What a valid value is, in words.
        reason: String,
    },

    /// A file that could not be read or parsed.
    #[error("malformed file {}: {reason}", path.display())]
    MalformedFile {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },

    /// Shared data a computation needs (`../shared/data`, or `$PSH_DATA_DIR`) is absent.
    #[error("shared data missing: {} (set PSH_DATA_DIR)", path.display())]
    DataMissing {
        /// The file or directory looked for.
        path: PathBuf,
    },

    /// An allocation that the input asks for exceeds the memory budget
    /// ([`crate::budget`]); `bytes` saturates at `u128::MAX`.
    #[error("{what} needs {bytes} bytes, over the memory budget of {budget} bytes (raise it with PSH_MAX_MEMORY, e.g. 16G, or --max-memory)")]
    MemoryBudget {
        /// What was to be allocated.
        what: String,
        /// The bytes it needs (saturating at `u128::MAX`).
        bytes: u128,
        /// The budget in bytes.
        budget: u64,
    },

    /// The caller asked the computation to stop ([`crate::progress::Progress::cancelled`]).
    #[error("{what} was interrupted")]
    Interrupted {
        /// The computation.
        what: String,
    },

    /// An I/O failure on a named file.
    #[error("I/O error on {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
}

/// `Result` with [`enum@Error`].
pub type Result<T> = std::result::Result<T, Error>;

/// Longest text taken from input (a file's string, an argument) into a message.
pub const MAX_MESSAGE_TEXT: usize = 120;

/// `text` for a message: at most [`MAX_MESSAGE_TEXT`] characters, with `...` and the
/// total length when it is cut.
pub fn clip(text: &str) -> String {
    clip_to(text, MAX_MESSAGE_TEXT)
}

/// Longest reason a malformed file's error gives (a parser's message may quote the file).
pub const MAX_REASON_TEXT: usize = 600;

/// `text` cut to `max` characters, with `...` and the total length when it is cut.
pub fn clip_to(text: &str, max: usize) -> String {
    match text.char_indices().nth(max) {
        None => text.to_string(),
        Some((i, _)) => format!("{}... ({} characters)", &text[..i], text.chars().count()),
    }
}

/// Checks that `value` is finite, naming it in the error otherwise.
pub fn finite(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::NonFinite { name, value })
    }
}

/// Checks that every value is finite, naming the first that is not.
pub fn finite_all<'a>(name: &'static str, values: impl IntoIterator<Item = &'a f64>) -> Result<()> {
    match values.into_iter().find(|x| !x.is_finite()) {
        Some(&value) => Err(Error::NonFinite { name, value }),
        None => Ok(()),
    }
}

/// [`finite_all`] over the real and imaginary parts of complex values.
pub fn finite_complex(name: &'static str, values: &[num_complex::Complex64]) -> Result<()> {
    finite_all(name, values.iter().flat_map(|z| [&z.re, &z.im]))
}

/// Checks that `len == expected`.
pub fn check_len(name: &'static str, expected: usize, got: usize) -> Result<()> {
    if expected == got {
        Ok(())
    } else {
        Err(Error::LengthMismatch {
            name,
            expected,
            got,
        })
    }
}
impl Error {
    /// [`Error::InvalidArgument`]: the argument `name`, the `value` given, and what a
    /// valid value is (`reason`).
    pub fn invalid(
        name: &'static str,
        value: impl Into<String>,
        reason: impl Into<String>,
    ) -> Self {
        Error::InvalidArgument {
            name,
            value: value.into(),
            reason: reason.into(),
        }
    }

    /// [`Error::MalformedFile`]: the file `path` and what is wrong with it.
    pub fn malformed(path: impl Into<PathBuf>, reason: impl Into<String>) -> Self {
        Error::MalformedFile {
            path: path.into(),
            reason: reason.into(),
        }
    }
}

/// Replaces the context of a `DifferentRays` error.
pub(crate) fn relabel(e: Error, what: &'static str) -> Error {
    match e {
        Error::DifferentRays {
            first,
            second,
            distance,
            tolerance,
            ..
        } => Error::DifferentRays {
            what,
            first,
            second,
            distance,
            tolerance,
        },
        other => other,
    }
}
