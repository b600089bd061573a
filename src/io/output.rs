//! Outputs that are never half-written: every file is written to a temporary sibling
//! (`.psh-PID-N.partial`, same directory, a name that fits wherever the target's does)
//! and renamed over its target once complete, so a failed write leaves an existing file
//! as it was. Inside [`all_or_nothing`] the renames wait until the whole output (the four
//! component files of a map and its pictures, say) has been written: a failure while
//! writing any of them leaves every target untouched, and the renames of concurrent
//! groups into a directory do not interleave (each holds a lock on the directory while
//! it renames). The group may name the files it reads; a write over one of them is
//! refused.
//!
//! **What an output may name** ([`check_output`]): a new file, or an existing regular
//! file, replaced. A symlink is followed: the file it points to is replaced, the link is
//! kept. Directories, devices, FIFOs, sockets and dangling links are refused.
//!
//! **Temporary files** are removed when a write fails, by
//! [`remove_partial_outputs`] (the command line calls it on SIGINT and SIGTERM), and,
//! left by a process that was killed, on the next write into their directory by any psh
//! process (a `.psh-PID-N.partial` whose process is gone from this machine's `/proc`: a
//! directory shared with other machines may hold their writers' files, which this rule
//! would remove; write such outputs to a local directory).

use super::io_error;
use crate::error::{clip, Error, Result};
use std::cell::RefCell;
use std::collections::HashSet;
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

/// The temporary files being written by this process (removed on a signal).
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The directories already cleared of stale temporary files by this process.
static CLEARED: Mutex<Option<HashSet<PathBuf>>> = Mutex::new(None);

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
        let mut live = LIVE.lock().unwrap_or_else(|e| e.into_inner());
        live.retain(|p| *p != self.temp);
    }
}

/// Removes every temporary file this process is writing: for a signal handler that then
/// exits (the targets stay as they were).
pub fn remove_partial_outputs() {
    let live = LIVE.lock().unwrap_or_else(|e| e.into_inner());
    for p in live.iter() {
        let _ = std::fs::remove_file(p);
    }
}

/// The process id in a temporary file's name (`.psh-PID-N.partial`, or the older
/// `.NAME.psh-PID-N.partial`).
fn partial_pid(name: &str) -> Option<u32> {
    let stem = name.strip_prefix('.')?.strip_suffix(".partial")?;
    let (_, ids) = stem.rsplit_once("psh-")?;
    ids.split_once('-')?.0.parse().ok()
}

/// Removes, once per process and directory, the temporary files in `dir` of processes
/// that no longer run (killed while writing). Where processes cannot be looked up (no
/// `/proc`), nothing is removed.
fn clear_stale_partials(dir: &Path) {
    let key = dir.canonicalize().unwrap_or_else(|_| dir.to_path_buf());
    {
        let mut cleared = CLEARED.lock().unwrap_or_else(|e| e.into_inner());
        if !cleared.get_or_insert_with(HashSet::new).insert(key) {
            return;
        }
    }
    if !Path::new("/proc/self").exists() {
        return;
    }
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(pid) = name.to_str().and_then(partial_pid) else {
            continue;
        };
        let regular = entry.file_type().is_ok_and(|t| t.is_file());
        if regular && !Path::new(&format!("/proc/{pid}")).exists() {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// The file an output path names: `path` itself when new or a regular file, the file a
/// symlink points to. Errors: a directory, device, FIFO or socket (or a link to one), a
/// dangling link, no file name, a directory that does not exist.
pub fn check_output(path: impl AsRef<Path>) -> Result<PathBuf> {
    let path = path.as_ref();
    let refuse = |reason: &str| {
        Error::invalid(
            "output file",
            clip(&path.display().to_string()),
            format!("{reason}; psh creates or replaces regular files only"),
        )
    };
    let target = match std::fs::symlink_metadata(path) {
        Err(_) => path.to_path_buf(),
        Ok(meta) if meta.file_type().is_symlink() => path
            .canonicalize()
            .map_err(|_| refuse("a symlink to nothing"))?,
        Ok(_) => path.to_path_buf(),
    };
    match std::fs::metadata(&target) {
        Ok(meta) if !meta.is_file() => {
            return Err(refuse(
                "not a regular file (a directory, device, FIFO or socket)",
            ))
        }
        _ => {}
    }
    if target.file_name().is_none() {
        return Err(refuse("no file name"));
    }
    let dir = parent_dir(&target);
    if !dir.is_dir() {
        return Err(io_error(
            &target,
            std::io::Error::new(
                std::io::ErrorKind::NotFound,
                format!("no directory {}", clip(&dir.display().to_string())),
            ),
        ));
    }
    Ok(target)
}

/// The directory a file is written into (`.` for a bare name).
fn parent_dir(file: &Path) -> PathBuf {
    match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Renames `staged` over their targets, holding a lock on each of their directories
/// (in one order, so concurrent groups cannot deadlock): the renames of two groups into
/// a directory never interleave.
fn rename_all(staged: Vec<Staged>) -> Result<()> {
    let mut dirs: Vec<PathBuf> = staged.iter().map(|s| parent_dir(&s.target)).collect();
    dirs.sort();
    dirs.dedup();
    let mut locks = Vec::with_capacity(dirs.len());
    for dir in &dirs {
        let handle = File::open(dir).map_err(|e| io_error(dir, e))?;
        handle.lock().map_err(|e| io_error(dir, e))?;
        locks.push(handle);
    }
    for s in staged {
        s.rename()?;
    }
    Ok(())
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
    rename_all(group.staged)?;
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

/// Writes the file `path` ([`check_output`]) with `write`: into a temporary sibling,
/// renamed over `path` when `write` succeeds (or, inside [`all_or_nothing`], when the
/// whole output has). The temporary file takes the permissions of the file it replaces.
pub fn write_file(
    path: impl AsRef<Path>,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
) -> Result<()> {
    let target = check_output(path.as_ref())?;
    let inputs = GROUP.with(|g| g.borrow().as_ref().map(|g| g.inputs.clone()));
    refuse_input(inputs.as_deref().unwrap_or(&[]), &target)?;
    clear_stale_partials(&parent_dir(&target));
    let temp = target.with_file_name(format!(
        ".psh-{}-{}.partial",
        std::process::id(),
        SERIAL.fetch_add(1, Ordering::Relaxed)
    ));
    let file = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&temp)
        .map_err(|e| io_error(&target, e))?;
    LIVE.lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(temp.clone());
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
    write_bytes(path, text.as_bytes())
}

/// Writes `bytes` to the file `path` as [`write_file`]; returns the path.
pub fn write_bytes(path: impl AsRef<Path>, bytes: &[u8]) -> Result<PathBuf> {
    let path = path.as_ref();
    write_file(path, |w| w.write_all(bytes).map_err(|e| io_error(path, e)))?;
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

    /// Outputs create or replace regular files only: devices, FIFOs and directories are
    /// refused before anything is written; a symlink's target is replaced, the link kept.
    #[cfg(unix)]
    #[test]
    fn outputs_are_regular_files() {
        use std::os::unix::fs::FileTypeExt;
        // Devices are only checked, never written to, even by a broken build.
        for special in ["/dev/null", "/dev/zero", "/"] {
            let e = check_output(special).unwrap_err().to_string();
            assert!(e.contains("regular files only"), "{special}: {e}");
        }
        let d = dir("special");
        let e = write_text(&d, "x").unwrap_err().to_string();
        assert!(e.contains("regular files only"), "{e}");
        let fifo = d.join("fifo");
        if std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .is_ok_and(|s| s.success())
        {
            assert!(write_text(&fifo, "x").is_err());
            assert!(std::fs::symlink_metadata(&fifo)
                .unwrap()
                .file_type()
                .is_fifo());
        }
        let real = d.join("real.txt");
        write_text(&real, "old").unwrap();
        let link = d.join("link.txt");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        write_text(&link, "new").unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "new");
        let dangling = d.join("dangling.txt");
        std::os::unix::fs::symlink(d.join("nothing"), &dangling).unwrap();
        assert!(write_text(&dangling, "x").is_err());
        let e = check_output(d.join("no/such/dir.txt"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("no directory"), "{e}");
        // A name of 255 bytes, the longest a file system takes, is written.
        write_text(d.join("n".repeat(255)), "x").unwrap();
    }

    /// Temporary files of a process that no longer runs are removed by the next write
    /// into their directory; a live process's are kept.
    #[test]
    fn stale_temporaries_are_removed() {
        if !Path::new("/proc/self").exists() {
            return;
        }
        let d = dir("stale");
        // No process has this id (above the kernel's pid_max limit, 2^22).
        let stale = d.join(".psh-4999999-0.partial");
        let old_style = d.join(".a.npz.psh-4999999-3.partial");
        let live = d.join(format!(".psh-{}-999999.partial", std::process::id()));
        for p in [&stale, &old_style, &live] {
            std::fs::write(p, "partial").unwrap();
        }
        write_text(d.join("out.txt"), "x").unwrap();
        assert!(!stale.exists() && !old_style.exists());
        assert!(live.exists());
        assert_eq!(partial_pid(".psh-12-3.partial"), Some(12));
        assert_eq!(partial_pid("psh-12-3.partial"), None);
    }

    /// Two writers of the same three files, at once, leave one writer's set.
    #[test]
    fn concurrent_groups_do_not_mix() {
        let d = dir("concurrent");
        let files: Vec<PathBuf> = (0..3).map(|k| d.join(format!("f{k}"))).collect();
        for _ in 0..100 {
            std::thread::scope(|s| {
                for writer in ["a", "b"] {
                    let files = &files;
                    s.spawn(move || {
                        all_or_nothing(&[], || {
                            for f in files {
                                write_text(f, writer)?;
                            }
                            Ok(())
                        })
                        .unwrap()
                    });
                }
            });
            let read: Vec<String> = files
                .iter()
                .map(|f| std::fs::read_to_string(f).unwrap())
                .collect();
            assert!(read.iter().all(|r| *r == read[0]), "{read:?}");
        }
    }
}
