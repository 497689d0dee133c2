use std::path::PathBuf;
use std::sync::Arc;

use super::checks::*;
use contracts::lab07::Antialiasing;
use grading::strategies::samples;
use grading::{GoldenFile, LabContext};
use raylab_core::Error;

/// Writes lab 07's golden cases and snapshots from `reference` into the lab's directory.
pub fn generate_golden(
    reference: &Arc<dyn Antialiasing>,
    ctx: &LabContext,
) -> Result<Vec<PathBuf>, Error> {
    let r = reference.as_ref();
    let mut written = Vec::new();

    let pixels: Vec<PixelInput> = samples(pixel_input(), 32, 71);
    let path = ctx.golden_path(GOLDEN_PIXEL);
    GoldenFile::record("7.2", &pixels, |(pixel, jitters)| {
        r.compute_pixel(*pixel, jitters, &mut probe_radiance)
    })
    .save(&path)?;
    written.push(path);

    // The converged image, and the reference's own error against it at each subdivision.
    let jitters = part_pipeline(Part::Jitters, reference, &ctx.base);
    let converged = render_default(&jitters, CONVERGED_SUBDIVISIONS, CONVERGED_SEED)?;
    let path = ctx.snapshot_path(&format!("{SNAPSHOT_CONVERGED}.exr"));
    raylab_core::film::write_exr(&converged, &path)?;
    written.push(path);

    let mut errors = Vec::new();
    for s in ERROR_SUBDIVISIONS {
        errors.push((s, image_error(&jitters, s, &converged)?));
    }
    let path = ctx.golden_path(GOLDEN_IMAGE_ERROR);
    GoldenFile::record("7.1", &ERROR_SUBDIVISIONS, |s| {
        errors
            .iter()
            .find(|(t, _)| t == s)
            .map(|(_, e)| *e)
            .expect("every subdivision was rendered")
    })
    .save(&path)?;
    written.push(path);

    let film = render_default(
        &part_pipeline(Part::Pixel, reference, &ctx.base),
        PIXEL_SNAPSHOT_SUBDIVISIONS,
        SNAPSHOT_SETTINGS.seed,
    )?;
    let path = ctx.snapshot_path(&format!("{SNAPSHOT_PIXEL}.exr"));
    raylab_core::film::write_exr(&film, &path)?;
    written.push(path);
    Ok(written)
}
