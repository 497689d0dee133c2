//! Lab 04's checks: one test per exercise of the table in `labs/lab04/exercises.toml` (checks in `labs/lab04/checks`).
//!
//! `cargo test -p lab04` checks your code in `src/lib.rs`, `cargo test -p lab04 exercise_4_2`
//! just Exercise 4.2.
//! `cargo test -p lab04 --features reference` checks the reference solution instead, where
//! the tree holds it. Each exercise runs with `reference::pipeline` for everything else: the
//! answer key where the tree holds it (so one unfinished exercise does not fail the others),
//! and in a handout, for this lab before its solution is released, your own code; a check
//! that needs another lab whose solution is not released yet says it waits for that lab.

use std::sync::Arc;

use contracts::lab04::Reflection;
use grading::harness::{self, LabChecks};
use lab04_checks::checks;

fn subject() -> Arc<dyn Reflection> {
    #[cfg(feature = "reference")]
    return Arc::new(reference::lab04::Lab04);
    #[cfg(not(feature = "reference"))]
    return Arc::new(lab04::Student);
}

fn main() {
    harness::run(LabChecks {
        lab: checks::LAB,
        lab_dir: env!("CARGO_MANIFEST_DIR"),
        exercises: checks::exercises(),
        subject: subject(),
        base: reference::pipeline(4),
        key_labs: reference::KEYS,
        hidden: cfg!(feature = "hidden-exercises"),
        #[cfg(feature = "report")]
        report: Some(lab04_checks::report::make),
        #[cfg(not(feature = "report"))]
        report: None,
        generate_golden: lab04_checks::generate_golden,
    })
}
