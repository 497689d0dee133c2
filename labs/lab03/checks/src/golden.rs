use std::path::PathBuf;
use std::sync::Arc;

use super::checks::*;
use contracts::lab03::Shadows;
use grading::strategies::samples;
use grading::{GoldenFile, LabContext};
use raylab_core::Error;

/// Writes lab 03's golden cases and snapshots from `reference` into the lab's directory: the
/// golden cases of Exercise 3.4, the hard-shadow snapshot (the Cornell box under its point
/// light), and the per-pixel mean and variance of the soft-shadow renders (the Cornell box
/// under its area light, one render per seed of [`REFERENCE_SEEDS`]).
pub fn generate_golden(
    reference: &Arc<dyn Shadows>,
    ctx: &LabContext,
) -> Result<Vec<PathBuf>, Error> {
    let r = reference.as_ref();
    let mut written = Vec::new();

    let inputs: Vec<AreaSampleInput> = samples(area_sample_strategy(), 64, 31);
    let path = ctx.golden_path(GOLDEN_AREA_SAMPLE);
    GoldenFile::record("3.4", &inputs, |&(p, q, n, le, pdf)| {
        r.area_light_sample(p, q, n, le, pdf)
    })
    .save(&path)?;
    written.push(path);

    let pipeline = part_pipeline(
        Part::ShadowRay,
        reference,
        &ctx.base,
        SNAPSHOT_LIGHT_SAMPLES,
    );
    let path = ctx.snapshot_path(&format!("{SNAPSHOT_POINT}.exr"));
    raylab_core::film::write_exr(&render_point_snapshot(&pipeline)?, &path)?;
    written.push(path);

    let stats = area_statistics(&pipeline, REFERENCE_SEEDS)?;
    written.extend(ctx.save_noisy_snapshot(SNAPSHOT_AREA, &stats)?);
    Ok(written)
}
