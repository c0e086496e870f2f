//! Stopping a run that is under way: a request any thread may make (the binary's signal
//! handler, Python's Ctrl-C), which every solver reads between its cycles, iterations and
//! steps and answers by returning [`Cancelled`] within about a second.
//!
//! The request is process-wide: a signal stops the whole process's work, every model of a
//! comparison at once. Whoever starts new work after an interrupt clears it ([`clear`]).

use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// The work was stopped on request before it finished: no answer, nothing written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("interrupted on request")]
pub struct Cancelled;

/// Asks every solve under way to stop at its next check.
pub fn request() {
    REQUESTED.store(true, Ordering::SeqCst);
}

/// Whether a stop was asked for.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}

/// Forgets a request: what a caller does before it starts new work.
pub fn clear() {
    REQUESTED.store(false, Ordering::SeqCst);
}

/// `Err(Cancelled)` once a stop was asked for: the check a loop makes between its iterations.
pub fn check() -> Result<(), Cancelled> {
    if requested() { Err(Cancelled) } else { Ok(()) }
}
