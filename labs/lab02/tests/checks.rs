//! Lab 02's checks: one test per exercise of the table in `labs/lab02/exercises.toml` (checks in `labs/lab02/checks`).
//!
//! `cargo test -p lab02` checks your code in `src/lib.rs`, `cargo test -p lab02 exercise_2_2`
//! just Exercise 2.2.
//! `cargo test -p lab02 --features reference` checks the reference solution instead, where
//! the tree holds it. Each exercise runs with `reference::pipeline` for everything else: the
//! answer key where the tree holds it (so one unfinished exercise does not fail the others),
//! and in a handout, for this lab before its solution is released, your own code; a check
//! that needs another lab whose solution is not released yet says it waits for that lab.

use std::sync::Arc;

use contracts::lab02::Lab02;
use grading::harness::{self, LabChecks};
use lab02_checks::checks;

fn subject() -> Arc<dyn Lab02> {
    #[cfg(feature = "reference")]
    return Arc::new(reference::lab02::Lab02);
    #[cfg(not(feature = "reference"))]
    return Arc::new(lab02::Student);
}

fn main() {
    harness::run(LabChecks {
        lab: checks::LAB,
        lab_dir: env!("CARGO_MANIFEST_DIR"),
        exercises: checks::exercises(),
        subject: subject(),
        base: reference::pipeline(2),
        key_labs: reference::KEYS,
        hidden: cfg!(feature = "hidden-exercises"),
        #[cfg(feature = "report")]
        report: Some(lab02_checks::report::make),
        #[cfg(not(feature = "report"))]
        report: None,
        generate_golden: lab02_checks::generate_golden,
    })
}
