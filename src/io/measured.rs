//! Measured pBRDF tables from either format: Mitsuba 3's `.pbsdf` ([`super::read_pbsdf`])
//! or the KAIST dataset's MATLAB data file with its info file ([`super::read_kaist`]),
//! told apart by their first bytes.

use super::input::open_input;
use super::malformed;
use crate::error::Result;
use crate::optics::TabulatedPbrdf;
use std::io::Read;
use std::path::Path;

/// A table read from a file, with what reading it did to the Stokes frames.
#[derive(Clone, Debug)]
pub struct MeasuredTable {
    /// The table in the convention of [`TabulatedPbrdf`].
    pub table: TabulatedPbrdf,
    /// Samples whose frames an info file gives and whose matrices were turned into the
    /// convention's frames (0 without one).
    pub turned: usize,
    /// Samples whose `x` axis the info file leaves undefined (NaN), taken in the
    /// convention's limit frames.
    pub undefined_frames: usize,
    /// The largest frame angle `|psi|` of a turned sample, radians, modulo `pi` (a turn by
    /// `pi` leaves Stokes components unchanged): how far the file's frames are from the
    /// convention.
    pub largest_turn: f64,
}

/// Reads the measured table `path`: a `.pbsdf` (a Mitsuba 3 tensor file) or a KAIST data
/// file (a level-5 MAT-file) with the frames of the info file `info` if given. Errors: a
/// file of neither kind, an info file beside a `.pbsdf`, and the readers' own.
pub fn read_measured_pbrdf(path: impl AsRef<Path>, info: Option<&Path>) -> Result<MeasuredTable> {
    let path = path.as_ref();
    let mut head = Vec::new();
    open_input(path)?
        .0
        .take(20)
        .read_to_end(&mut head)
        .map_err(|e| malformed(path, e.to_string()))?;
    if head.starts_with(b"MATLAB 5.0 MAT-file") {
        return super::read_kaist(path, info);
    }
    if !head.starts_with(b"tensor_file\0") {
        return Err(malformed(
            path,
            "neither a Mitsuba 3 .pbsdf (tensor_file) nor a KAIST MAT-file (MATLAB 5.0)",
        ));
    }
    if let Some(info) = info {
        return Err(malformed(
            info,
            format!(
                "an info file gives a KAIST MAT-file's frames; {} is a .pbsdf (frames by convention)",
                path.display()
            ),
        ));
    }
    Ok(MeasuredTable {
        table: super::read_pbsdf(path)?,
        turned: 0,
        undefined_frames: 0,
        largest_turn: 0.0,
    })
}
