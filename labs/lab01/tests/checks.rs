//! Lab 01's checks: one test per exercise of the table in `labs/lab01/exercises.toml` (checks in `labs/lab01/checks`).
//!
//! `cargo test -p lab01` checks your code in `src/lib.rs`, `cargo test -p lab01 exercise_1_2`
//! just Exercise 1.2.
//! `cargo test -p lab01 --features reference` checks the reference solution instead, where
//! the tree holds it. Each exercise runs with `reference::pipeline` for everything else: the
//! answer key where the tree holds it (so one unfinished exercise does not fail the others),
//! and in a handout, for this lab before its solution is released, your own code; a check
//! that needs another lab whose solution is not released yet says it waits for that lab.

use std::sync::Arc;

use contracts::lab01::CameraRays;
use grading::harness::{self, LabChecks};
use lab01_checks::checks;

fn subject() -> Arc<dyn CameraRays> {
    #[cfg(feature = "reference")]
    return Arc::new(reference::lab01::Lab01);
    #[cfg(not(feature = "reference"))]
    return Arc::new(lab01::Student);
}

fn main() {
    harness::run(LabChecks {
        lab: checks::LAB,
        lab_dir: env!("CARGO_MANIFEST_DIR"),
        exercises: checks::exercises(),
        subject: subject(),
        base: reference::pipeline(1),
        key_labs: reference::KEYS,
        hidden: cfg!(feature = "hidden-exercises"),
        #[cfg(feature = "report")]
        report: Some(lab01_checks::report::make),
        #[cfg(not(feature = "report"))]
        report: None,
        generate_golden: lab01_checks::generate_golden,
    })
}
