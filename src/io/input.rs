//! Input files: only regular files are read, and their size is checked against the
//! memory budget ([`crate::budget`]) before a byte is read. A directory, device, FIFO or
//! socket named as an input is an error naming it, not an endless read or a wait for a
//! writer.

use super::io_error;
use crate::error::{Error, Result};
use std::fs::File;
use std::path::Path;

/// Opens the regular file `path` for reading: the file and its length. Error: it does not
/// exist or cannot be read, or it is not a regular file (checked before it is opened, so
/// a FIFO does not block, and again on the open file).
pub(crate) fn open_input(path: &Path) -> Result<(File, u64)> {
    let regular = |meta: &std::fs::Metadata| {
        if meta.is_file() {
            Ok(())
        } else {
            Err(Error::invalid(
                "input",
                path.display().to_string(),
                "not a regular file (a directory, device, FIFO or socket); psh reads regular files only",
            ))
        }
    };
    regular(&std::fs::metadata(path).map_err(|e| io_error(path, e))?)?;
    let file = File::open(path).map_err(|e| io_error(path, e))?;
    let meta = file.metadata().map_err(|e| io_error(path, e))?;
    regular(&meta)?;
    Ok((file, meta.len()))
}

/// The bytes of the regular file `path` ([`open_input`]), its size checked against the
/// memory budget first.
pub(crate) fn read_input(path: &Path) -> Result<Vec<u8>> {
    use std::io::Read;
    let (file, len) = open_input(path)?;
    let len = usize::try_from(len).unwrap_or(usize::MAX);
    crate::budget::check(&format!("the file {}", path.display()), &[len], 1)?;
    let mut bytes = Vec::with_capacity(len);
    // A file that grows while read is read to its size when opened.
    file.take(len as u64)
        .read_to_end(&mut bytes)
        .map_err(|e| io_error(path, e))?;
    Ok(bytes)
}

/// The text of the regular file `path` ([`read_input`]), without a leading UTF-8 byte
/// order mark. Error: not UTF-8.
pub(crate) fn read_input_text(path: &Path) -> Result<String> {
    let text = String::from_utf8(read_input(path)?)
        .map_err(|e| super::malformed(path, format!("not UTF-8 text: {e}")))?;
    Ok(match text.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_string(),
        None => text,
    })
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    /// Devices, directories and FIFOs are refused without reading or blocking.
    #[test]
    fn only_regular_files_are_read() {
        for p in ["/dev/zero", "/dev/null", "/"] {
            let e = read_input(Path::new(p)).unwrap_err().to_string();
            assert!(e.contains("not a regular file") && e.contains(p), "{e}");
        }
        let dir = std::env::temp_dir().join(format!("psh-input-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fifo = dir.join("fifo");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|s| s.success()) {
            let e = read_input(&fifo).unwrap_err().to_string();
            assert!(e.contains("not a regular file"), "{e}");
        }
        let bom = dir.join("bom.csv");
        std::fs::write(&bom, "\u{feff}0,1\n").unwrap();
        assert_eq!(read_input_text(&bom).unwrap(), "0,1\n");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
