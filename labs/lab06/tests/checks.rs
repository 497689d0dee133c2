//! Lab 06's checks: one test per exercise of the table in `labs/lab06/exercises.toml` (checks in `labs/lab06/checks`).
//!
//! `cargo test -p lab06` checks your code in `src/lib.rs`, `cargo test -p lab06 exercise_6_6`
//! just Exercise 6.6.
//! `cargo test -p lab06 --features reference` checks the reference solution instead, where
//! the tree holds it. Each exercise runs with `reference::pipeline` for everything else: the
//! answer key where the tree holds it (so one unfinished exercise does not fail the others),
//! and in a handout, for this lab before its solution is released, your own code; a check
//! that needs another lab whose solution is not released yet says it waits for that lab.

use std::sync::Arc;

use contracts::lab06::Radiosity;
use grading::harness::{self, LabChecks};
use lab06_checks::checks;

fn subject() -> Arc<dyn Radiosity> {
    #[cfg(feature = "reference")]
    return Arc::new(reference::lab06::Lab06);
    #[cfg(not(feature = "reference"))]
    return Arc::new(lab06::Student);
}

fn main() {
    harness::run(LabChecks {
        lab: checks::LAB,
        lab_dir: env!("CARGO_MANIFEST_DIR"),
        exercises: checks::exercises(),
        subject: subject(),
        base: reference::pipeline(6),
        key_labs: reference::KEYS,
        hidden: cfg!(feature = "hidden-exercises"),
        #[cfg(feature = "report")]
        report: Some(lab06_checks::report::make),
        #[cfg(not(feature = "report"))]
        report: None,
        generate_golden: lab06_checks::generate_golden,
    })
}
