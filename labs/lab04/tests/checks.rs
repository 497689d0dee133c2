//! Lab 04's checks, one test per exercise.
//!
//! `cargo test -p lab04` checks your code in `src/lib.rs`;
//! `cargo test -p lab04 --features reference` checks the reference solution instead.
//! Each exercise is checked with the reference for everything else, so one unfinished
//! exercise does not fail the others.

use std::path::Path;
use std::sync::Arc;

use framework::grading::{LabContext, assert_exercise};
use framework::labs::lab04::{Reflection, checks};

fn subject() -> Arc<dyn Reflection> {
    #[cfg(feature = "reference")]
    return Arc::new(reference::lab04::Lab04);
    #[cfg(not(feature = "reference"))]
    return Arc::new(lab04::Student);
}

fn check(id: &str) {
    let ctx = LabContext::new(
        4,
        Path::new(env!("CARGO_MANIFEST_DIR")),
        reference::pipeline(4),
    )
    .with_key_labs(reference::KEYS);
    assert_exercise(&checks::exercises(), id, &subject(), &ctx);
}

#[test]
fn exercise_4_1_reflect() {
    check("4.1");
}

#[test]
fn exercise_4_2_reflected_ray() {
    check("4.2");
}

#[test]
fn exercise_4_3_interface() {
    check("4.3");
}

#[test]
fn exercise_4_4_refract() {
    check("4.4");
}

#[test]
fn exercise_4_5_refracted_ray() {
    check("4.5");
}

#[test]
fn exercise_4_6_shade_phong() {
    check("4.6");
}
