//! The answer key: one module per lab implementing that lab's contract from
//! `framework::contracts`, and [`pipeline`], the reference [`Pipeline`] every check and render
//! starts from.

pub mod lab01;
pub mod lab02;
pub mod lab03;
pub mod lab04;
pub mod lab07;

use std::sync::Arc;

use framework::pipeline::{Pipeline, View};

/// The reference pipeline with every lab enabled up to `lab`.
pub fn pipeline(lab: u32) -> Pipeline {
    Pipeline {
        camera: Arc::new(lab01::Lab01),
        intersection: None,
        shading: Arc::new(lab02::Lab02),
        shadows: Arc::new(lab03::Lab03),
        reflection: Arc::new(lab04::Lab04),
        antialiasing: Arc::new(lab07::Lab07),
        lab,
        view: View::Shaded,
        area_light_samples: 4,
        max_depth: 10,
    }
}

/// The labs whose solution this crate holds: the slots of [`pipeline`] that are the answer
/// key. Checks compare a student's function with the key's where it is present
/// (`LabContext::with_key_labs`), and judge by golden cases and properties elsewhere.
pub const KEYS: &[u32] = &framework::labs::NUMBERS;
