//! Lab 12's exercises and their checks.
//!
//! The samplers are judged by their distributions, never by the directions one random number
//! gives: a correct sampler that maps its numbers another way passes. Where the answer key is
//! absent (a handout before the solution), what the checks need of it is recorded in `golden/`:
//! exact values for the deterministic functions, and for the BSDF sampler the key's histogram
//! and reflectance from many samples.

use std::sync::Arc;

use glam::Vec3;

use contracts::lab12::PathTracing;
use grading::{Exercise, GoldenFile, LabContext};

mod accumulation;
mod bsdf;
mod bsdf_sampling;
mod cornell;
mod light_sampling;
mod mis_roulette;
mod path_loop;
pub mod sky;

pub use accumulation::{GOLDEN_RELATIVE_ERROR, estimates, relative_error_inputs};
pub use bsdf::{
    BsdfInput, EXPONENTS, GOLDEN_BSDF, GOLDEN_LUMINANCE, bsdf_input, colour, luminance_inputs,
    material,
};
pub use bsdf_sampling::{
    BSDF_GRID, BSDF_SAMPLES, GOLDEN_SAMPLE_BSDF, KEY_BSDF_SAMPLES, PDF_GRID, SamplerCase,
    SamplerReference, SamplerRun, run_sampler, sampler_cases,
};
pub use cornell::{
    CORNELL_DEPTH, CORNELL_SETTINGS, CORNELL_TOLERANCE, REFERENCE_SEEDS, SNAPSHOT_CORNELL,
    STUDENT_SEEDS, convergence_rate, cornell_pipeline, cornell_statistics,
};
pub use light_sampling::{
    EmitterCase, GOLDEN_EMITTER_PDF, emitter_case, emitter_pdf_input, solid_angle,
};
pub use mis_roulette::{GOLDEN_POWER_HEURISTIC, density};
pub use path_loop::{FURNACES, Furnace, SUN};

use accumulation::{exercise_12_9, exercise_12_10};
use bsdf::{exercise_12_1, exercise_12_2};
use bsdf_sampling::exercise_12_3;
use light_sampling::{exercise_12_4, exercise_12_5};
use mis_roulette::{exercise_12_6, exercise_12_7};
use path_loop::exercise_12_8;
use sky::{exercise_12_11, exercise_12_12, exercise_12_13};

/// This lab.
pub const LAB: course::LabId = course::LabId::of(12);

/// Family-wise significance of each exercise's statistical tests, split over them by Šidák's
/// correction: a correct implementation fails one in a thousand seeds.
pub const SIGNIFICANCE: f64 = 1e-3;
/// Random inputs per property.
const CASES: u32 = 200;

/// The exercises of lab 12 (`labs/lab12/exercises.toml`), each with its check.
pub fn exercises() -> Vec<Exercise<dyn PathTracing>> {
    grading::exercises(
        LAB,
        grading::checks![
            exercise_12_1,
            exercise_12_2,
            exercise_12_3,
            exercise_12_4,
            exercise_12_5,
            exercise_12_6,
            exercise_12_7,
            exercise_12_8,
            exercise_12_9,
            exercise_12_10,
            exercise_12_11,
            exercise_12_12,
            exercise_12_13
        ],
    )
}

/// The answer key's code of this lab, where the context has it.
fn key(ctx: &LabContext) -> Option<Arc<dyn PathTracing>> {
    ctx.key().and_then(|k| k.part::<dyn PathTracing>())
}

fn load<I, O>(ctx: &LabContext, name: &str) -> Result<GoldenFile<I, O>, String>
where
    I: serde::Serialize + serde::de::DeserializeOwned,
    O: serde::Serialize + serde::de::DeserializeOwned,
{
    ctx.golden(name)
}

/// A unit direction on the side of `normal`, at least `min_cos` from its plane.
fn above(normal: Vec3, d: Vec3, min_cos: f32) -> Vec3 {
    let d = if d.dot(normal) < 0.0 { -d } else { d };
    if d.dot(normal) >= min_cos {
        d
    } else {
        (d + normal * (min_cos - d.dot(normal) + 1e-3)).normalize()
    }
}
