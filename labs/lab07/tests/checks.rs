//! Lab 07's checks, one test per exercise.
//!
//! `cargo test -p lab07` checks your code in `src/lib.rs`;
//! `cargo test -p lab07 --features reference` checks the reference solution instead.
//! Each exercise is checked with the reference for everything else, so one unfinished
//! exercise does not fail the others.

use std::path::Path;
use std::sync::Arc;

use framework::grading::{LabContext, assert_exercise};
use framework::labs::lab07::{Antialiasing, checks};

fn subject() -> Arc<dyn Antialiasing> {
    #[cfg(feature = "reference")]
    return Arc::new(reference::lab07::Lab07);
    #[cfg(not(feature = "reference"))]
    return Arc::new(lab07::Student);
}

fn check(id: &str) {
    let ctx = LabContext::new(
        7,
        Path::new(env!("CARGO_MANIFEST_DIR")),
        reference::pipeline(7),
    )
    .with_key_labs(reference::KEYS);
    assert_exercise(&checks::exercises(), id, &subject(), &ctx);
}

#[test]
fn exercise_7_1_compute_jitters() {
    check("7.1");
}

#[test]
fn exercise_7_2_compute_pixel() {
    check("7.2");
}
