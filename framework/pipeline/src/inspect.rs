//! The pixel inspector: one sample of one pixel traced as the render computes it — every
//! contract method the integrator called (the exercise whose code it is, the arguments, the
//! result), every ray the framework traced with what it hit, and the call a magenta or cyan
//! pixel owes its colour to.
//!
//! [`inspect_pixel`] renders the sample with the [traced](Pipeline::traced) pipeline while
//! [`contracts::trace::record`] notes the calls on this thread, from the same random numbers as
//! the render's ([`render_sample`]): its radiance is that sample's, bit for bit.

use glam::Vec3;
use raylab_core::Error;
use raylab_core::render::{RenderSettings, resolution};
use raylab_core::scene::Scene;
use serde::Serialize;

use contracts::trace::{self, Call, Entry, Log, NonFinite, RayEvent};

use crate::Pipeline;
use crate::render::render_sample;

/// One sample of one pixel, traced.
#[derive(Clone, Debug, Serialize)]
pub struct Inspection {
    /// The scene's name.
    pub scene: String,
    /// The pixel's column.
    pub x: u32,
    /// The pixel's row (0 at the top).
    pub y: u32,
    /// Which of the pixel's samples.
    pub sample: u32,
    /// The integrator that rendered the sample.
    pub integrator: crate::Integrator,
    /// The sample's radiance (NaN where it panicked; NaN and infinities are `null` in JSON).
    pub radiance: Vec3,
    /// Whether the radiance holds a NaN or an infinity (the pixel is cyan).
    pub non_finite: Option<NonFinite>,
    /// The panic that stopped the sample, if any (the pixel is magenta).
    pub panic: Option<SamplePanic>,
    /// The calls and rays, in the order they began.
    pub steps: Vec<Step>,
    /// Steps left out past [`trace::ENTRY_LIMIT`] (a failing call is never left out).
    pub dropped: usize,
    /// The call the sample's failure comes from: the first (by the time it returned) that
    /// panicked, else the first that returned a NaN, else an infinity.
    pub culprit: Option<Culprit>,
}

/// A panic that stopped a sample.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct SamplePanic {
    /// Its message.
    pub message: String,
    /// `file:line:column` where it was raised, when known.
    pub location: Option<String>,
}

/// One step of an [`Inspection`].
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Step {
    /// A contract method's call.
    Call(CallStep),
    /// A ray the framework traced.
    Ray(RayEvent),
}

/// A contract method's call, with the exercise whose function it is.
#[derive(Clone, Debug, Serialize)]
pub struct CallStep {
    /// The call.
    #[serde(flatten)]
    pub call: Call,
    /// The exercise of the lab's table whose function the method is, if one is.
    pub exercise: Option<ExerciseRef>,
}

/// An exercise, by number and title.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct ExerciseRef {
    /// Its number, `"2.6"`.
    pub id: String,
    /// Its title.
    pub title: String,
}

/// What went wrong in the culprit's call.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Problem {
    /// It panicked.
    Panicked,
    /// It returned a NaN.
    Nan,
    /// It returned an infinity.
    Infinite,
}

/// The call a sample's failure comes from.
#[derive(Clone, Debug, Serialize)]
pub struct Culprit {
    /// Its index in [`Inspection::steps`].
    pub step: usize,
    /// Its lab.
    pub lab: u32,
    /// The method.
    pub method: String,
    /// Its exercise, if the lab's table has one for the method.
    pub exercise: Option<ExerciseRef>,
    /// What went wrong.
    pub problem: Problem,
    /// What went wrong, in a sentence naming the exercise.
    pub message: String,
}

/// Traces sample `sample` of pixel `(x, y)` of the render of `scene` through `pipeline` with
/// `settings` (a progressive render's pass: [`crate::render::pass_settings`]): the same
/// radiance as that sample has in the image. The pipeline is the render's, prepared as it
/// was (caustics, sky). A panic of the sample is part of the answer; an error only for a pixel
/// or sample the settings do not have.
pub fn inspect_pixel(
    scene: &Scene,
    pipeline: &Pipeline,
    settings: &RenderSettings,
    x: u32,
    y: u32,
    sample: u32,
) -> Result<Inspection, Error> {
    settings.validate()?;
    let outside = |what: String, limit: String| Error::Invalid {
        what,
        reason: format!("expected {limit}"),
    };
    if x >= settings.width || y >= settings.height {
        return Err(outside(
            format!("pixel ({x}, {y})"),
            format!(
                "a pixel of the {}×{} image: x below {}, y below {}",
                settings.width, settings.height, settings.width, settings.height
            ),
        ));
    }
    if sample >= settings.samples_per_pixel {
        return Err(outside(
            format!("sample {sample}"),
            format!(
                "a sample below {} (the samples per pixel)",
                settings.samples_per_pixel
            ),
        ));
    }
    let traced = pipeline.traced();
    let (outcome, log) = trace::record(|| {
        raylab_core::catch_panic(|| {
            let camera = traced.prepare_camera(scene, resolution(settings));
            render_sample(scene, &traced, &camera, settings, x, y, sample)
        })
    });
    let (radiance, panic) = match outcome {
        Ok(radiance) => (radiance, None),
        Err(caught) => (
            Vec3::NAN,
            Some(SamplePanic {
                message: caught.message,
                location: caught.location,
            }),
        ),
    };
    let non_finite = if radiance.is_nan() {
        Some(NonFinite::Nan)
    } else if !radiance.is_finite() {
        Some(NonFinite::Infinite)
    } else {
        None
    };
    let Log { entries, dropped } = log;
    let steps: Vec<Step> = entries
        .into_iter()
        .map(|entry| match entry {
            Entry::Call(call) => Step::Call(CallStep {
                exercise: exercise_of(call.lab, call.method),
                call,
            }),
            Entry::Ray(ray) => Step::Ray(ray),
        })
        .collect();
    let culprit = culprit(&steps);
    Ok(Inspection {
        scene: scene.name.clone(),
        x,
        y,
        sample,
        integrator: pipeline.integrator(),
        radiance,
        non_finite,
        panic,
        steps,
        dropped,
        culprit,
    })
}

/// The exercise of lab `lab` whose function is `method`.
fn exercise_of(lab: u32, method: &str) -> Option<ExerciseRef> {
    let lab = course::lab(course::LabId::new(lab)?).ok()?;
    let exercise = lab.exercises.iter().find(|e| e.function == method)?;
    Some(ExerciseRef {
        id: exercise.id.clone(),
        title: exercise.title.clone(),
    })
}

/// The call that panicked first (by the time it returned: the innermost), else the first that
/// returned a NaN, else the first that returned an infinity.
fn culprit(steps: &[Step]) -> Option<Culprit> {
    let problem = |call: &Call| match (&call.panic, call.non_finite) {
        (Some(_), _) => Some(Problem::Panicked),
        (None, Some(NonFinite::Nan)) => Some(Problem::Nan),
        (None, Some(NonFinite::Infinite)) => Some(Problem::Infinite),
        (None, None) => None,
    };
    let (step, call, problem) = steps
        .iter()
        .enumerate()
        .filter_map(|(i, step)| match step {
            Step::Call(c) => Some((i, c, problem(&c.call)?)),
            Step::Ray(_) => None,
        })
        .min_by_key(|(_, c, problem)| (*problem as u8, c.call.finished))?;
    let call_ = &call.call;
    let who = match &call.exercise {
        Some(e) => format!("Exercise {} ({}, lab {})", e.id, call_.method, call_.lab),
        None => format!("`{}` of lab {}", call_.method, call_.lab),
    };
    let message = match problem {
        Problem::Panicked => format!(
            "{who} panicked: {}",
            call_.panic.as_deref().unwrap_or_default()
        ),
        Problem::Nan | Problem::Infinite => format!(
            "{who} returned {}: {}",
            if problem == Problem::Nan {
                "a NaN"
            } else {
                "an infinity"
            },
            call_.result.as_deref().unwrap_or_default()
        ),
    };
    Some(Culprit {
        step,
        lab: call_.lab,
        method: call_.method.to_string(),
        exercise: call.exercise.clone(),
        problem,
        message,
    })
}
