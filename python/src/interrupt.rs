//! Long calls that Ctrl-C stops: the work runs on another thread while Python's main
//! thread waits without the GIL and checks for signals (after 0.1 ms, then at doubling
//! intervals up to every 50 ms). A signal's exception
//! (`KeyboardInterrupt` for Ctrl-C) sets the flag that the work's
//! [`psh::progress::Progress::cancelled`] reports; the work ends at its next unit and the
//! exception is raised as itself.

use crate::errors::IntoPy;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// The progress of interruptible work: silent, cancelled once the flag is set.
struct Cancel<'a>(&'a AtomicBool);

impl psh::progress::Progress for Cancel<'_> {
    fn advance(&self, _: u64) {}

    fn cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// Runs `work` with a progress that Python's signals cancel; its result, or the signal's
/// exception.
pub fn interruptible<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(&dyn psh::progress::Progress) -> psh::Result<T> + Send,
) -> PyResult<T> {
    let flag = AtomicBool::new(false);
    let progress = Cancel(&flag);
    std::thread::scope(|s| {
        let handle = s.spawn(|| work(&progress));
        let mut raised = None;
        // Short calls return within a fraction of a millisecond of their end; long ones
        // are looked at every 50 ms.
        let mut wait = Duration::from_micros(100);
        while !handle.is_finished() {
            py.detach(|| std::thread::sleep(wait));
            wait = (wait * 2).min(Duration::from_millis(50));
            if raised.is_none() {
                if let Err(e) = py.check_signals() {
                    raised = Some(e);
                    flag.store(true, Ordering::Relaxed);
                }
            }
        }
        let out = py
            .detach(|| handle.join())
            .map_err(|_| PyRuntimeError::new_err("psh's work panicked"))?;
        match raised {
            Some(e) => Err(e),
            None => out.py_err(),
        }
    })
}
