//! Outputs that are never half-written: every file is written to a temporary sibling
//! (`.name.psh-PID-N.partial`, same directory) and renamed over its target once complete,
//! so a failed write leaves an existing file as it was. Inside [`all_or_nothing`] the
//! renames wait until the whole output (the four component files of a map and its
//! pictures, say) has been written: a failure while writing any of them leaves every
//! target untouched (the renames at the end are same-directory moves).
//! The group may name the files it reads; a write over one of them is refused.

use super::io_error;
use crate::error::{clip, Error, Result};
use std::cell::RefCell;
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// A complete temporary file and the target it will replace; removed unless renamed.
struct Staged {
    temp: PathBuf,
    target: PathBuf,
    renamed: bool,
}

impl Staged {
    fn rename(mut self) -> Result<()> {
        std::fs::rename(&self.temp, &self.target).map_err(|e| io_error(&self.target, e))?;
        self.renamed = true;
        Ok(())
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        if !self.renamed {
            let _ = std::fs::remove_file(&self.temp);
        }
    }
}

/// The output being written by [`all_or_nothing`] on this thread.
struct Group {
    inputs: Vec<PathBuf>,
    staged: Vec<Staged>,
}

thread_local! {
    static GROUP: RefCell<Option<Group>> = const { RefCell::new(None) };
}

/// Serial number of temporary files within the process.
static SERIAL: AtomicU64 = AtomicU64::new(0);

/// Runs `body`; the files it writes ([`write_file`], and so every writer of
/// [`crate::io`]) appear together when it returns `Ok`, none when it fails. A write over
/// one of `inputs` is refused ([`refuse_input`]). Nested calls join the outer output.
pub fn all_or_nothing<T>(inputs: &[PathBuf], body: impl FnOnce() -> Result<T>) -> Result<T> {
    if GROUP.with(|g| g.borrow().is_some()) {
        return body();
    }
    /// Ends the group even when `body` panics.
    struct Active;
    impl Drop for Active {
        fn drop(&mut self) {
            GROUP.with(|g| g.borrow_mut().take());
        }
    }
    GROUP.with(|g| {
        *g.borrow_mut() = Some(Group {
            inputs: inputs.to_vec(),
            staged: Vec::new(),
        })
    });
    let active = Active;
    let result = body();
    let group = GROUP.with(|g| g.borrow_mut().take());
    drop(active);
    let value = result?;
    let group = group.expect("the group set above");
    for staged in group.staged {
        staged.rename()?;
    }
    Ok(value)
}

/// Error if `output` is the same file as one of `inputs` (psh never overwrites what it
/// reads: `project a_s%d.exr -o a_s0.exr` would replace an input by coefficients).
pub fn refuse_input(inputs: &[PathBuf], output: &Path) -> Result<()> {
    let Ok(out) = output.canonicalize() else {
        return Ok(()); // not there yet, so not an input
    };
    match inputs
        .iter()
        .find(|i| i.canonicalize().is_ok_and(|i| i == out))
    {
        Some(input) => Err(Error::invalid(
            "output file",
            clip(&output.display().to_string()),
            format!(
                "it is the input {}; psh does not overwrite the files it reads",
                clip(&input.display().to_string())
            ),
        )),
        None => Ok(()),
    }
}

/// Writes the file `path` with `write`: into a temporary sibling, renamed over `path`
/// when `write` succeeds (or, inside [`all_or_nothing`], when the whole output has).
/// The temporary file takes the permissions of the file it replaces.
pub fn write_file(
    path: impl AsRef<Path>,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
) -> Result<()> {
    let target = path.as_ref().to_path_buf();
    let inputs = GROUP.with(|g| g.borrow().as_ref().map(|g| g.inputs.clone()));
    refuse_input(inputs.as_deref().unwrap_or(&[]), &target)?;
    let name = target.file_name().ok_or_else(|| {
        Error::invalid(
            "output file",
            clip(&target.display().to_string()),
            "no file name",
        )
    })?;
    let temp = target.with_file_name(format!(
        ".{}.psh-{}-{}.partial",
        name.to_string_lossy(),
        std::process::id(),
        SERIAL.fetch_add(1, Ordering::Relaxed)
    ));
    let file = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&temp)
        .map_err(|e| io_error(&target, e))?;
    let staged = Staged {
        temp,
        target,
        renamed: false,
    };
    let mut out = BufWriter::new(file);
    write(&mut out)?;
    let file = out
        .into_inner()
        .map_err(|e| io_error(&staged.target, e.into_error()))?;
    file.sync_all().map_err(|e| io_error(&staged.target, e))?;
    if let Ok(meta) = std::fs::metadata(&staged.target) {
        let _ = file.set_permissions(meta.permissions());
    }
    drop(file);
    GROUP.with(|g| match g.borrow_mut().as_mut() {
        Some(group) => {
            group.staged.push(staged);
            Ok(())
        }
        None => staged.rename(),
    })
}

/// The error of a writer given a non-finite value (`what`, e.g. `coefficient 7`): psh
/// writes finite values only, and `path` is left as it was.
pub(crate) fn not_finite(path: &Path, what: String, value: f64) -> Error {
    Error::invalid(
        "value to write",
        format!("{what} = {value}"),
        format!(
            "{} not written: psh writes finite values only",
            clip(&path.display().to_string())
        ),
    )
}

/// Writes `text` to the file `path` as [`write_file`]; returns the path.
pub fn write_text(path: impl AsRef<Path>, text: &str) -> Result<PathBuf> {
    let path = path.as_ref();
    write_file(path, |w| {
        w.write_all(text.as_bytes()).map_err(|e| io_error(path, e))
    })?;
    Ok(path.to_path_buf())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("psh_output_{name}_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn failing() -> Result<()> {
        Err(Error::GridTooSmall {
            reason: "a failure in the middle of the output".into(),
        })
    }

    /// A failed write leaves the existing file and no temporary file behind.
    #[test]
    fn failed_writes_keep_existing_files() {
        let d = dir("single");
        let p = d.join("a.txt");
        write_text(&p, "old").unwrap();
        let e = write_file(&p, |w| {
            w.write_all(b"half of the new").unwrap();
            failing()
        });
        assert!(e.is_err());
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "old");
        assert_eq!(
            std::fs::read_dir(&d).unwrap().count(),
            1,
            "temporary file left"
        );
        write_text(&p, "new").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "new");
    }

    /// A group appears all together or not at all.
    #[test]
    fn groups_are_all_or_nothing() {
        let d = dir("group");
        let [a, b, c] = ["a", "b", "c"].map(|n| d.join(n));
        for p in [&a, &b, &c] {
            write_text(p, "old").map(drop).unwrap();
        }
        let e = all_or_nothing(&[], || {
            write_text(&a, "new")?;
            write_text(&b, "new")?;
            failing()
        });
        assert!(e.is_err());
        for p in [&a, &b, &c] {
            assert_eq!(std::fs::read_to_string(p).unwrap(), "old");
        }
        assert_eq!(
            std::fs::read_dir(&d).unwrap().count(),
            3,
            "temporary files left"
        );
        all_or_nothing(&[], || {
            write_text(&a, "new")?;
            // Not renamed before the group ends.
            assert_eq!(std::fs::read_to_string(&a).unwrap(), "old");
            write_text(&c, "new")
        })
        .unwrap();
        let read = |p: &Path| std::fs::read_to_string(p).unwrap();
        assert_eq!([read(&a), read(&b), read(&c)], ["new", "old", "new"]);
    }

    /// Writing over an input of the group is refused, under any spelling of its path.
    #[test]
    fn inputs_are_never_overwritten() {
        let d = dir("inputs");
        let input = d.join("in.txt");
        write_text(&input, "input").unwrap();
        let other = d.join("sub/../in.txt");
        std::fs::create_dir_all(d.join("sub")).unwrap();
        let e =
            all_or_nothing(std::slice::from_ref(&input), || write_text(&other, "x")).unwrap_err();
        assert!(e.to_string().contains("does not overwrite"), "{e}");
        assert_eq!(std::fs::read_to_string(&input).unwrap(), "input");
        all_or_nothing(&[input], || write_text(d.join("out.txt"), "x")).unwrap();
    }
}
