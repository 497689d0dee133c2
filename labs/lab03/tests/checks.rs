//! Lab 03's checks, one test per exercise.
//!
//! `cargo test -p lab03` checks your code in `src/lib.rs`;
//! `cargo test -p lab03 --features reference` checks the reference solution instead.
//! Each exercise is checked with the reference for everything else, so one unfinished
//! exercise does not fail the others.

use std::path::Path;
use std::sync::Arc;

use framework::grading::{LabContext, assert_exercise};
use framework::labs::lab03::{Shadows, checks};

fn subject() -> Arc<dyn Shadows> {
    #[cfg(feature = "reference")]
    return Arc::new(reference::lab03::Lab03);
    #[cfg(not(feature = "reference"))]
    return Arc::new(lab03::Student);
}

fn check(id: &str) {
    let ctx = LabContext::new(
        3,
        Path::new(env!("CARGO_MANIFEST_DIR")),
        reference::pipeline(3),
    )
    .with_key_labs(reference::KEYS);
    assert_exercise(&checks::exercises(), id, &subject(), &ctx);
}

#[test]
fn exercise_3_1_shadow_ray() {
    check("3.1");
}

#[test]
fn exercise_3_2_stratified_samples() {
    check("3.2");
}

#[test]
fn exercise_3_3_sample_triangle() {
    check("3.3");
}

#[test]
fn exercise_3_4_area_light_sample() {
    check("3.4");
}
