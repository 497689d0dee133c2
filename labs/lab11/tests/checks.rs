//! Lab 11's checks: one test per exercise of the table in `labs/lab11/exercises.toml` (checks in `labs/lab11/checks`).
//!
//! `cargo test -p lab11` checks your code in `src/lib.rs`, `cargo test -p lab11 exercise_11_3`
//! just Exercise 11.3.
//! `cargo test -p lab11 --features reference` checks the reference solution instead, where
//! the tree holds it. No check of one exercise calls your code for another, so you can do them
//! in any order.

use std::sync::Arc;

use contracts::lab11::AmbientOcclusion;
use grading::harness::{self, LabChecks};
use lab11_checks::checks;

fn subject() -> Arc<dyn AmbientOcclusion> {
    #[cfg(feature = "reference")]
    return Arc::new(reference::lab11::Lab11);
    #[cfg(not(feature = "reference"))]
    return Arc::new(lab11::Student);
}

fn main() {
    harness::run(LabChecks {
        lab: checks::LAB,
        lab_dir: env!("CARGO_MANIFEST_DIR"),
        exercises: checks::exercises(),
        subject: subject(),
        base: reference::pipeline(11),
        key_labs: reference::KEYS,
        hidden: cfg!(feature = "hidden-exercises"),
        #[cfg(feature = "report")]
        report: Some(lab11_checks::report::make),
        #[cfg(not(feature = "report"))]
        report: None,
        generate_golden: lab11_checks::generate_golden,
    })
}
