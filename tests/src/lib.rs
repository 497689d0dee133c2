//! Workspace-level test support: the mutant corpus (realistic wrong implementations each lab's
//! checks must reject, and alternative correct ones they must accept) and helpers to run a
//! lab's exercises on any implementation.

pub mod mutants;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use framework::grading::{Exercise, LabContext, run_exercise};

/// The directory of lab `lab`'s crate.
pub fn lab_dir(lab: u32) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("labs")
        .join(format!("lab{lab:02}"))
}

/// The grading context of lab `lab` with the reference for everything else.
pub fn context(lab: u32) -> LabContext {
    let mut ctx = LabContext::new(lab, &lab_dir(lab), reference::pipeline(lab));
    ctx.failure_dir = std::env::temp_dir()
        .join(format!("raylab-tests-{}", std::process::id()))
        .join(format!("lab{lab:02}"));
    ctx
}

/// Runs every exercise on `subject`: `(exercise id, Ok or the failure message)`.
pub fn run_all<S: ?Sized>(
    exercises: &[Exercise<S>],
    subject: &Arc<S>,
    ctx: &LabContext,
) -> Vec<(&'static str, Result<(), String>)> {
    exercises
        .iter()
        .map(|e| (e.id, run_exercise(e, subject, ctx)))
        .collect()
}
