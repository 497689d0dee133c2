//! Lab 03's exercises and their checks.
//!
//! Every exercise is checked in four ways, in this order (the first failure is reported):
//!
//! 1. properties of the function alone, on inputs drawn by proptest from a fixed seed;
//! 2. for 3.1, tiny scenes where the right answer is known (a point in the open is lit exactly
//!    as without shadows, a point under an occluder is black); for 3.2 and 3.3, chi-square
//!    tests of the distribution of the samples; for 3.4, golden cases;
//! 3. for 3.2–3.4, the irradiance from a quad light estimated through the integrator's own
//!    area-light code, compared with the analytic irradiance as the samples grow;
//! 4. renders of the Cornell box: the hard shadows of the point light compared pixel by pixel
//!    (3.1, deterministic), and the soft shadows of the area light compared with the
//!    reference's per-pixel mean and variance by a Z-test (all exercises; see
//!    [`NoiseTolerance`]).
//!
//! Each check puts the student's function for its exercise, and only that one, into the
//! pipeline; everything else is the reference (`ctx.base`).
//!
//! [`NoiseTolerance`]: grading::stats::NoiseTolerance

use std::sync::Arc;

use glam::Vec3;

use contracts::lab03::Shadows;
use grading::Exercise;
use pipeline::{Pipeline, View};
use raylab_core::render::RenderSettings;

mod area_light;
mod cornell;
mod irradiance;
mod jitter;
mod shadow_rays;
mod soft_shadows;
mod triangle_sampling;

pub use area_light::area_sample_strategy;
pub use cornell::snapshot_scene;
pub use irradiance::{
    IRRADIANCE_ALPHA, IRRADIANCE_ESTIMATES, IRRADIANCE_LEVELS, MIN_STRATIFICATION_GAIN,
    check_irradiance, form_factor_parallel_corner, irradiance_parallel_rectangle,
};
pub use shadow_rays::{TMAX_SHORT_BY, TMIN_RANGE, render_point_snapshot};
pub use soft_shadows::{AREA_TOLERANCE, area_statistics, check_area_snapshot, render_area};

use area_light::exercise_3_4;
use jitter::exercise_3_2;
use shadow_rays::exercise_3_1;
use triangle_sampling::exercise_3_3;

/// Golden file of Exercise 3.4.
pub const GOLDEN_AREA_SAMPLE: &str = "area_light_sample.json";
/// Snapshot of the Cornell box lit by its point light only: hard shadows (deterministic).
pub const SNAPSHOT_POINT: &str = "cornell-point";
/// The Monte Carlo snapshot of the Cornell box lit by its area light only: the per-pixel mean
/// and variance (one render's) of the reference's renders, `cornell-area-mean.exr` and
/// `cornell-area-variance.exr` (`LabContext::check_noisy_snapshot`).
pub const SNAPSHOT_AREA: &str = "cornell-area";
/// Size and sampling of lab 03's snapshots (the seed is that of the hard-shadow snapshot; the
/// soft-shadow renders use [`REFERENCE_SEEDS`] and [`STUDENT_SEEDS`]).
pub const SNAPSHOT_SETTINGS: RenderSettings = RenderSettings::snapshot(3);
/// `n` of the `n × n` area-light samples of the soft-shadow renders.
pub const SNAPSHOT_LIGHT_SAMPLES: u32 = 4;
/// Seeds of the reference renders whose mean and variance the soft-shadow snapshot holds.
pub const REFERENCE_SEEDS: std::ops::Range<u64> = 1000..1064;
/// Seeds of the student's soft-shadow renders (disjoint from [`REFERENCE_SEEDS`]).
pub const STUDENT_SEEDS: std::ops::Range<u64> = 5000..5004;

/// Which student function a render or an estimate exercises; the rest is the base.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// Exercise 3.1, `shadow_ray`.
    ShadowRay,
    /// Exercise 3.2, `stratified_samples`.
    Stratified,
    /// Exercise 3.3, `sample_triangle`.
    Triangle,
    /// Exercise 3.4, `area_light_sample`.
    AreaSample,
}

impl Part {
    /// The contract method whose code this part is (the student's in a [`PartSlot`](pipeline::PartSlot)).
    pub fn function(self) -> &'static str {
        match self {
            Part::ShadowRay => "shadow_ray",
            Part::Stratified => "stratified_samples",
            Part::Triangle => "sample_triangle",
            Part::AreaSample => "area_light_sample",
        }
    }
}

/// Input of Exercise 3.4: surface point, light point, light normal, emission, pdf.
pub type AreaSampleInput = (Vec3, Vec3, Vec3, Vec3, f32);

/// This lab.
pub const LAB: course::LabId = course::LabId::of(3);

/// The exercises of lab 03 (`labs/lab03/exercises.toml`), each with its check.
pub fn exercises() -> Vec<Exercise<dyn Shadows>> {
    grading::exercises(
        LAB,
        grading::checks![exercise_3_1, exercise_3_2, exercise_3_3, exercise_3_4],
    )
}

/// The lab-3 pipeline with `student` in `part`'s slot and `base` everywhere else, shading
/// with `n × n` area-light samples.
pub fn part_pipeline(part: Part, student: &Arc<dyn Shadows>, base: &Pipeline, n: u32) -> Pipeline {
    let mut pipeline = base.with_student_function(part.function(), student);
    pipeline.view = View::Shaded;
    pipeline.area_light_samples = n;
    pipeline
}

/// Rejection level of the chi-square tests of 3.2 and 3.3 (each test; there are about ten).
pub const CHI_SQUARE_P: f64 = 1e-6;

/// Formats counts as a small table for messages.
fn format_counts(counts: &[u32]) -> String {
    counts
        .iter()
        .map(|c| c.to_string())
        .collect::<Vec<_>>()
        .join(" ")
}
