//! Progress reporting for long jobs, without tying the library to a terminal.

/// Receives progress from a long job. The CLI shows a bar; tests and the regression
/// runner pass [`NoProgress`].
/// Implementations are shared with a watcher thread while a search runs, hence `Sync`.
pub trait Progress: Sync {
    /// A new phase of `total` steps begins.
    fn start(&self, total: u64, message: &str);
    /// `n` more steps are done.
    fn advance(&self, n: u64);
    /// `position` steps are done in all (for work measured, not counted step by step:
    /// expansions, simulated time).
    fn set(&self, position: u64);
    /// The phase goes on under another name (a search that found no plan, looking for
    /// why).
    fn rename(&self, _message: &str) {}
    /// The phase is over.
    fn finish(&self);
}

/// Reports nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoProgress;

impl Progress for NoProgress {
    fn start(&self, _total: u64, _message: &str) {}
    fn advance(&self, _n: u64) {}
    fn set(&self, _position: u64) {}
    fn finish(&self) {}
}
