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
}

/// Reports nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Progress for Silent {
    fn advance(&self, _: u64) {}
}
