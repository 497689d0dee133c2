//! Runs of checks: the grader judges an exercise in several runs (the check on the student's
//! code, each callee's own check, each re-judge with parts of the key), and no state of the
//! student's code may pass from one run to the next. The judge marks each new run here; a
//! [`Transport`](super::Transport) that keeps the student's code alive between calls (an
//! instance of a WebAssembly module) discards what it made under an older run. Natively, where
//! the student's code is a plain object in this process, the mark changes nothing.

use std::sync::atomic::{AtomicU64, Ordering};

static RUN: AtomicU64 = AtomicU64::new(0);

/// Marks the start of a new run of checks in this process, and returns its number.
pub fn begin_run() -> u64 {
    RUN.fetch_add(1, Ordering::SeqCst) + 1
}

/// The number of the run under way: 0 before the first [`begin_run`].
pub fn current_run() -> u64 {
    RUN.load(Ordering::SeqCst)
}

/// The start of the panic message with which a transport stops a call whose code ran past its
/// budget of work (an endless loop): the checks report the exercise as timed out.
pub const OUT_OF_WORK: &str = "the code ran past its budget of work";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_run_has_a_number_of_its_own() {
        let first = begin_run();
        assert!(current_run() >= first);
        let second = begin_run();
        assert!(second > first);
        assert!(current_run() >= second);
    }
}
