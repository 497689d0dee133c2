//! Lab 10's checks: one test per exercise of the table in `labs/lab10/exercises.toml` (checks in `labs/lab10/checks`).
//!
//! `cargo test -p lab10` checks your code in `src/lib.rs`, `cargo test -p lab10 exercise_10_4`
//! just Exercise 10.4.
//! `cargo test -p lab10 --features reference` checks the reference solution instead, where
//! the tree holds it. Each exercise runs with `reference::pipeline` for everything else: the
//! answer key where the tree holds it (so one unfinished exercise does not fail the others),
//! and in a handout, for this lab before its solution is released, your own code; a check
//! that needs another lab whose solution is not released yet says it waits for that lab.

use std::sync::Arc;

use contracts::lab10::Fresnel;
use grading::harness::{self, LabChecks};
use lab10_checks::checks;

fn subject() -> Arc<dyn Fresnel> {
    #[cfg(feature = "reference")]
    return Arc::new(reference::lab10::Lab10);
    #[cfg(not(feature = "reference"))]
    return Arc::new(lab10::Student);
}

fn main() {
    harness::run(LabChecks {
        lab: checks::LAB,
        lab_dir: env!("CARGO_MANIFEST_DIR"),
        exercises: checks::exercises(),
        subject: subject(),
        base: reference::pipeline(10),
        key_labs: reference::KEYS,
        hidden: cfg!(feature = "hidden-exercises"),
        #[cfg(feature = "report")]
        report: Some(lab10_checks::report::make),
        #[cfg(not(feature = "report"))]
        report: None,
        generate_golden: lab10_checks::generate_golden,
    })
}
