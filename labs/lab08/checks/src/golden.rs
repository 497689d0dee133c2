use std::path::PathBuf;
use std::sync::Arc;

use super::checks::*;
use contracts::lab08::PhotonMapping;
use grading::strategies::samples;
use grading::{GoldenFile, LabContext};
use raylab_core::Error;
use raylab_core::sampling::Rng;
use raylab_core::scene::PointLight;

/// Writes lab 08's golden cases from `reference` into the lab's directory.
pub fn generate_golden(
    reference: &Arc<dyn PhotonMapping>,
    ctx: &LabContext,
) -> Result<Vec<PathBuf>, Error> {
    let r = reference.as_ref();
    let mut written = Vec::new();

    let inputs: Vec<PointInput> = samples(point_input(), 24, 81);
    let path = ctx.golden_path(GOLDEN_POINT);
    GoldenFile::record("8.1", &inputs, |&(position, intensity, n)| {
        let light = PointLight {
            position,
            intensity,
        };
        r.emit_point_light(&light, n, &mut Rng::new(11, 0)).power
    })
    .save(&path)?;
    written.push(path);

    let inputs: Vec<AreaInput> = samples(area_input(), 24, 82);
    let path = ctx.golden_path(GOLDEN_AREA);
    GoldenFile::record("8.2", &inputs, |&(position, normal, radiance, area, n)| {
        r.emit_area_light(position, normal, radiance, area, n, &mut Rng::new(11, 0))
            .power
    })
    .save(&path)?;
    written.push(path);

    let inputs: Vec<RadianceInput> = samples(radiance_input(), 32, 84);
    let path = ctx.golden_path(GOLDEN_RADIANCE);
    GoldenFile::record(
        "8.4",
        &inputs,
        |(diffuse, normal, photons, k, max_radius)| {
            r.caustic_radiance(*diffuse, *normal, photons, *k, *max_radius)
        },
    )
    .save(&path)?;
    written.push(path);

    let pipeline = part_pipeline(Part::Roulette, reference, &ctx.base);
    let counts = caustic_counts(&glass_caustic(&pipeline, CAUSTIC_GOLDEN_SEED).map_err(
        |reason| Error::Failed {
            what: "the glass caustic".into(),
            reason,
        },
    )?);
    let path = ctx.golden_path(GOLDEN_CAUSTIC);
    GoldenFile::record("8.3", &[CAUSTIC_GOLDEN_SEED], |_| counts).save(&path)?;
    written.push(path);
    Ok(written)
}
