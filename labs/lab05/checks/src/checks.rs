//! Lab 05's exercises and their checks.
//!
//! The closed-form exercises (5.1–5.7) are checked in three ways, in this order (the first
//! failure is reported):
//!
//! 1. the physical laws as properties of the function alone, on inputs over many orders of
//!    magnitude drawn by proptest from a fixed seed: linearity in power or radiance, the
//!    inverse-square law, `Φ = B·A`, the relations between the quantities one call returns;
//!    for the quadrature of 5.7 also its sums on coarse grids (1–4 steps), against the
//!    midpoint rule's own sums there, computed here;
//! 2. where the answer key is present ([`LabContext::key`]), the student's function against
//!    the key's on the same random inputs;
//! 3. the golden cases (`labs/lab05/golden/*.json`), recorded from the reference by
//!    `raylab golden`, the worksheet's questions first: a mismatch on one of them names the
//!    question.
//!
//! The Monte Carlo exercises (5.8, 5.9) are checked statistically against the closed-form
//! irradiance of a Lambertian polygon (Lambert's formula, lab 03's
//! [`irradiance_polygon`], on the part of the light above the receiver's horizon): the mean of
//! many estimates within a Šidák-corrected z-bound of the exact value, at scales from 10⁻⁴ to
//! 10³ m, on lights seen from behind, edge-on and partly below the horizon, sheared
//! parallelograms and strongly tilted receivers as well as plain rectangles; the generator
//! advanced; and the variance of the estimates against the reference's, recorded in golden
//! data.
//!
//! No check calls another exercise's function: each exercise is judged alone.
//!
//! [`irradiance_polygon`]: grading::radiometry::irradiance_polygon

use proptest::prelude::*;
use serde::Serialize;

use contracts::lab05::Radiometry;
use grading::{Exercise, GoldenFile, LabContext, for_all};

mod closed_forms;
mod hemisphere_integral;
mod inputs;
mod lights;
mod monte_carlo;

pub use hemisphere_integral::{COARSE_STEPS, coarse_profiles, midpoint_in_mu, midpoint_in_theta};
pub use inputs::{
    BulbInput, EmitterInput, EquivalentInput, IlluminanceInput, ObservationInput, PhotonsInput,
    RadianceProfile, RadiosityInput, WORKSHEET_BULB, WORKSHEET_EMITTER, WORKSHEET_EQUIVALENT,
    WORKSHEET_ILLUMINANCE, WORKSHEET_OBSERVATION, WORKSHEET_PHOTONS, WORKSHEET_RADIOSITY,
    WORKSHEET_TABLE, bulb_strategy, emitter_strategy, equivalent_strategy, illuminance_strategy,
    magnitude, observation_strategy, photons_strategy, radiosity_strategy, wavelength,
};
pub use lights::{
    LightCase, MC_ESTIMATES, MC_ESTIMATES_TILTED, MC_SAMPLES, MC_SAMPLES_TILTED, light_cases,
    mean_cases,
};
pub use monte_carlo::{
    BIG_LIGHT, Estimator, EstimatorVariance, MC_ALPHA, MC_SCALES, VARIANCE_SLACK, estimate,
    estimates, mean_and_variance,
};

use closed_forms::{
    exercise_5_1, exercise_5_2, exercise_5_3, exercise_5_4, exercise_5_5, exercise_5_6,
};
use hemisphere_integral::exercise_5_7;
use monte_carlo::{exercise_5_8, exercise_5_9};

/// Golden file of Exercise 5.1.
pub const GOLDEN_PHOTONS: &str = "photons_per_second.json";
/// Golden file of Exercise 5.2.
pub const GOLDEN_BULB: &str = "spherical_bulb.json";
/// Golden file of Exercise 5.3.
pub const GOLDEN_OBSERVATION: &str = "observe_point_source.json";
/// Golden file of Exercise 5.4.
pub const GOLDEN_ILLUMINANCE: &str = "illuminance_lux.json";
/// Golden file of Exercise 5.5.
pub const GOLDEN_EQUIVALENT: &str = "equivalent_intensity_cd.json";
/// Golden file of Exercise 5.6.
pub const GOLDEN_EMITTER: &str = "diffuse_emitter.json";
/// Golden file of Exercise 5.7.
pub const GOLDEN_RADIOSITY: &str = "radiosity_from_radiance.json";
/// Golden file of Exercises 5.8 and 5.9: the variance of the reference's estimators.
pub const GOLDEN_VARIANCE: &str = "irradiance_variance.json";

/// Relative tolerance of the closed-form answers against golden cases and the key: the
/// rounding of another order of the same operations, far below any wrong constant (the
/// worksheet's `c = 3·10⁸ m/s` is 7·10⁻⁴ off).
pub const REL_TOL: f64 = 1e-9;
/// Relative tolerance of the properties (exact laws, up to rounding).
pub const LAW_TOL: f64 = 1e-9;
/// Relative tolerance of the hemisphere integral of 5.7 against the reference's at the same
/// `steps` (≥ 64): the midpoint rule's error there is below 10⁻⁴.
pub const QUADRATURE_TOL: f64 = 1e-3;
/// Random inputs per property.
const CASES: u32 = 128;

/// This lab.
pub const LAB: course::LabId = course::LabId::of(5);

/// The exercises of lab 05 (`labs/lab05/exercises.toml`), each with its check.
pub fn exercises() -> Vec<Exercise<dyn Radiometry>> {
    grading::exercises(
        LAB,
        grading::checks![
            exercise_5_1,
            exercise_5_2,
            exercise_5_3,
            exercise_5_4,
            exercise_5_5,
            exercise_5_6,
            exercise_5_7,
            exercise_5_8,
            exercise_5_9
        ],
    )
}

/// `Ok` when `got` is within `rel·|expected|` of `expected` (NaN never is).
fn rel_close(what: &str, got: f64, expected: f64, rel: f64) -> Result<(), String> {
    if (got - expected).abs() <= rel * expected.abs() {
        Ok(())
    } else {
        Err(format!(
            "{what} is {got:e}, expected {expected:e} (relative error {:.2e}, at most {rel:.0e} allowed)",
            ((got - expected) / expected).abs()
        ))
    }
}

/// Checks `student` against the golden cases of `file`: `compare(got, expected)`; a failure
/// on the worksheet's input names the worksheet question.
fn check_golden<I, O>(
    ctx: &LabContext,
    file: &str,
    worksheet: &[(I, &str)],
    student: impl Fn(&I) -> O,
    compare: impl Fn(&O, &O) -> Result<(), String>,
) -> Result<(), String>
where
    I: Serialize + serde::de::DeserializeOwned + PartialEq + std::fmt::Debug,
    O: Serialize + serde::de::DeserializeOwned,
{
    let golden: GoldenFile<I, O> = ctx.golden(file)?;
    for case in &golden.cases {
        let got = student(&case.input);
        compare(&got, &case.expected).map_err(|e| {
            match worksheet.iter().find(|(i, _)| *i == case.input) {
                Some((_, q)) => format!("on the worksheet's {q} (input {:?}): {e}", case.input),
                None => format!("on the golden case {:?}: {e}", case.input),
            }
        })?;
    }
    Ok(())
}

/// With the key present, `compare(student, key)` on `cases` random inputs of `strategy`.
fn check_against_key<S: Strategy>(
    ctx: &LabContext,
    cases: u32,
    strategy: S,
    compare: impl Fn(&dyn Radiometry, S::Value) -> Result<(), String>,
) -> Result<(), String>
where
    S::Value: std::fmt::Debug,
{
    match ctx.key() {
        Some(key) => {
            let key = key.code::<dyn contracts::lab05::Radiometry>();
            for_all(cases, strategy, |input| compare(key.as_ref(), input))
        }
        None => Ok(()),
    }
}
