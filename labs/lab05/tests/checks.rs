//! Lab 05's checks: one test per exercise of the table in `labs/lab05/exercises.toml` (checks in `labs/lab05/checks`).
//!
//! `cargo test -p lab05` checks your code in `src/lib.rs`, `cargo test -p lab05 exercise_5_8`
//! just Exercise 5.8.
//! `cargo test -p lab05 --features reference` checks the reference solution instead, where
//! the tree holds it. No check of one exercise calls your code for another, so you can do them
//! in any order.

use std::sync::Arc;

use contracts::lab05::Radiometry;
use grading::harness::{self, LabChecks};
use lab05_checks::checks;

fn subject() -> Arc<dyn Radiometry> {
    #[cfg(feature = "reference")]
    return Arc::new(reference::lab05::Lab05);
    #[cfg(not(feature = "reference"))]
    return Arc::new(lab05::Student);
}

fn main() {
    harness::run(LabChecks {
        lab: checks::LAB,
        lab_dir: env!("CARGO_MANIFEST_DIR"),
        exercises: checks::exercises(),
        subject: subject(),
        base: reference::pipeline(5),
        key_labs: reference::KEYS,
        hidden: cfg!(feature = "hidden-exercises"),
        #[cfg(feature = "report")]
        report: Some(lab05_checks::report::make),
        #[cfg(not(feature = "report"))]
        report: None,
        generate_golden: lab05_checks::generate_golden,
    })
}
