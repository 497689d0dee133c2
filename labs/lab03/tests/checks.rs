//! Lab 03's checks: one test per exercise of the table in `labs/lab03/exercises.toml` (checks in `labs/lab03/checks`).
//!
//! `cargo test -p lab03` checks your code in `src/lib.rs`, `cargo test -p lab03 exercise_3_2`
//! just Exercise 3.2.
//! `cargo test -p lab03 --features reference` checks the reference solution instead, where
//! the tree holds it. Each exercise runs with `reference::pipeline` for everything else: the
//! answer key where the tree holds it (so one unfinished exercise does not fail the others),
//! and in a handout, for this lab before its solution is released, your own code; a check
//! that needs another lab whose solution is not released yet says it waits for that lab.

use std::sync::Arc;

use contracts::lab03::Shadows;
use grading::harness::{self, LabChecks};
use lab03_checks::checks;

fn subject() -> Arc<dyn Shadows> {
    #[cfg(feature = "reference")]
    return Arc::new(reference::lab03::Lab03);
    #[cfg(not(feature = "reference"))]
    return Arc::new(lab03::Student);
}

fn main() {
    harness::run(LabChecks {
        lab: checks::LAB,
        lab_dir: env!("CARGO_MANIFEST_DIR"),
        exercises: checks::exercises(),
        subject: subject(),
        base: reference::pipeline(3),
        key_labs: reference::KEYS,
        hidden: cfg!(feature = "hidden-exercises"),
        #[cfg(feature = "report")]
        report: Some(lab03_checks::report::make),
        #[cfg(not(feature = "report"))]
        report: None,
        generate_golden: lab03_checks::generate_golden,
    })
}
