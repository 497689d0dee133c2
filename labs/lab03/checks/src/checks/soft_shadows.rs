//! Soft-shadow renders under an area light: a Z-test against the reference's statistics.

use std::sync::Arc;

use contracts::lab03::Shadows;
use grading::LabContext;
use grading::stats::{NoiseTolerance, RenderStatistics};
use pipeline::Pipeline;
use pipeline::render::render;
use raylab_core::film::Film;
use raylab_core::render::RenderSettings;

use super::cornell::snapshot_scene;
use super::{
    Part, REFERENCE_SEEDS, SNAPSHOT_AREA, SNAPSHOT_LIGHT_SAMPLES, SNAPSHOT_SETTINGS, STUDENT_SEEDS,
    part_pipeline,
};

/// The tolerance of the soft-shadow snapshot.
pub const AREA_TOLERANCE: NoiseTolerance = NoiseTolerance {
    family_alpha: 1e-3,
    abs: 1e-4,
    rel: 1e-3,
    max_outlier_fraction: 0.003,
};

/// One soft-shadow render: the Cornell box lit by its area light, `seed`.
pub fn render_area(pipeline: &Pipeline, seed: u64) -> Result<Film, raylab_core::Error> {
    render(
        &snapshot_scene(false)?,
        pipeline,
        &RenderSettings {
            seed,
            ..SNAPSHOT_SETTINGS
        },
    )
}

/// Per-pixel mean and (unbiased) variance of renders with the given seeds.
pub fn area_statistics(
    pipeline: &Pipeline,
    seeds: std::ops::Range<u64>,
) -> Result<RenderStatistics, raylab_core::Error> {
    let films = seeds
        .map(|seed| render_area(pipeline, seed))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(RenderStatistics::of(&films))
}

/// The soft-shadow check of a part: the student's renders ([`STUDENT_SEEDS`]) against the
/// reference's ([`REFERENCE_SEEDS`]) under [`AREA_TOLERANCE`].
pub fn check_area_snapshot(
    part: Part,
    s: &Arc<dyn Shadows>,
    ctx: &LabContext,
) -> Result<(), String> {
    let pipeline = part_pipeline(part, s, &ctx.base, SNAPSHOT_LIGHT_SAMPLES);
    let student = area_statistics(&pipeline, STUDENT_SEEDS).map_err(|e| e.to_string())?;
    ctx.check_noisy_snapshot(
        SNAPSHOT_AREA,
        &student,
        (REFERENCE_SEEDS.end - REFERENCE_SEEDS.start) as u32,
        &AREA_TOLERANCE,
        &format!(
            "the soft shadows of the Cornell box (lit by its area light only, {n}×{n} light samples)",
            n = SNAPSHOT_LIGHT_SAMPLES
        ),
    )
}
