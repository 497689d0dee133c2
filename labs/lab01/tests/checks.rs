//! Lab 01's checks, one test per exercise.
//!
//! `cargo test -p lab01` checks your code in `src/lib.rs`;
//! `cargo test -p lab01 --features reference` checks the reference solution instead.
//! Each exercise is checked with the reference for everything else, so one unfinished
//! exercise does not fail the others.

use std::path::Path;
use std::sync::Arc;

use framework::grading::{LabContext, assert_exercise};
use framework::labs::lab01::{CameraRays, checks};

fn subject() -> Arc<dyn CameraRays> {
    #[cfg(feature = "reference")]
    return Arc::new(reference::lab01::Lab01);
    #[cfg(not(feature = "reference"))]
    return Arc::new(lab01::Student);
}

fn check(id: &str) {
    let ctx = LabContext::new(
        1,
        Path::new(env!("CARGO_MANIFEST_DIR")),
        reference::pipeline(1),
    )
    .with_key_labs(reference::KEYS);
    assert_exercise(&checks::exercises(), id, &subject(), &ctx);
}

#[test]
fn exercise_1_1_image_plane_coords() {
    check("1.1");
}

#[test]
fn exercise_1_2_camera_basis() {
    check("1.2");
}

#[test]
fn exercise_1_3_field_of_view() {
    check("1.3");
}

#[test]
fn exercise_1_4_ray_direction() {
    check("1.4");
}

#[test]
fn exercise_1_5_camera_ray() {
    check("1.5");
}

#[test]
fn exercise_1_6_camera_image() {
    check("1.6");
}
