//! Progress of long computations, reported to whoever runs them: the library calls a
//! [`Progress`], the command line draws it (with `indicatif`), a library user may log it
//! or pass [`Silent`].

/// Receives the progress of a computation; called from worker threads.
pub trait Progress: Sync {
    /// A stage of `total` units (`what`, e.g. "precompute" over vertices) begins.
    fn start(&self, what: &str, total: u64) {
        let _ = (what, total);
    }
    /// `n` more units of the stage are done.
    fn advance(&self, n: u64);
    /// The stage is over.
    fn finish(&self) {}
    /// Whether the caller asks the computation to stop (Ctrl-C in Python, say). Long
    /// stages ask between units and then end with [`crate::Error::Interrupted`].
    fn cancelled(&self) -> bool {
        false
    }
    /// [`crate::Error::Interrupted`] naming `what` when [`Progress::cancelled`].
    fn check_cancelled(&self, what: &str) -> crate::Result<()> {
        if self.cancelled() {
            return Err(crate::Error::Interrupted { what: what.into() });
        }
        Ok(())
    }
}

/// Reports nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Progress for Silent {
    fn advance(&self, _: u64) {}
}
