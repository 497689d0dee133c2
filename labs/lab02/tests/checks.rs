//! Lab 02's checks, one test per exercise.
//!
//! `cargo test -p lab02` checks your code in `src/lib.rs`;
//! `cargo test -p lab02 --features reference` checks the reference solution instead.
//! Each exercise is checked with the reference for everything else, so one unfinished
//! exercise does not fail the others.

use std::path::Path;
use std::sync::Arc;

use framework::grading::{LabContext, assert_exercise};
use framework::labs::lab02::{Lab02, checks};

fn subject() -> Arc<dyn Lab02> {
    #[cfg(feature = "reference")]
    return Arc::new(reference::lab02::Lab02);
    #[cfg(not(feature = "reference"))]
    return Arc::new(lab02::Student);
}

fn check(id: &str) {
    let ctx = LabContext::new(
        2,
        Path::new(env!("CARGO_MANIFEST_DIR")),
        reference::pipeline(2),
    )
    .with_key_labs(reference::KEYS);
    assert_exercise(&checks::exercises(), id, &subject(), &ctx);
}

#[test]
fn exercise_2_1_intersect_plane() {
    check("2.1");
}

#[test]
fn exercise_2_2_intersect_triangle() {
    check("2.2");
}

#[test]
fn exercise_2_3_intersect_sphere() {
    check("2.3");
}

#[test]
fn exercise_2_4_sample_point_light() {
    check("2.4");
}

#[test]
fn exercise_2_5_sample_directional_light() {
    check("2.5");
}

#[test]
fn exercise_2_6_shade_lambertian() {
    check("2.6");
}
