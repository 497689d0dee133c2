use std::path::PathBuf;
use std::sync::Arc;

use super::checks::*;
use contracts::lab10::Fresnel;
use grading::strategies::samples;
use grading::{GoldenFile, LabContext};
use raylab_core::Error;

/// Writes lab 10's golden cases and snapshots from `reference` into the lab's directory.
///
/// The transmitted cosines come from the base's lab 04 `refract`; cases within 0.1% of the
/// critical angle, where two correct implementations may decide differently, are left out.
pub fn generate_golden(
    reference: &Arc<dyn Fresnel>,
    ctx: &LabContext,
) -> Result<Vec<PathBuf>, Error> {
    let r = reference.as_ref();
    let base = ctx.base.code::<dyn contracts::lab04::Reflection>();
    let base = base.as_ref();
    let mut written = Vec::new();

    let pairs = |seed: u8| -> Vec<PairInput> {
        samples(reflectance_strategy(), 400, seed)
            .into_iter()
            .filter_map(|input| pair_of(base, input))
            .take(96)
            .collect()
    };
    for (name, id, seed, f) in [
        (
            GOLDEN_R_S,
            "10.1",
            101,
            (|r: &dyn Fresnel, (c1, c2, e1, e2): PairInput| r.fresnel_r_s(c1, c2, e1, e2))
                as fn(&dyn Fresnel, PairInput) -> f32,
        ),
        (GOLDEN_R_P, "10.2", 102, |r, (c1, c2, e1, e2)| {
            r.fresnel_r_p(c1, c2, e1, e2)
        }),
        (GOLDEN_R, "10.3", 103, |r, (c1, c2, e1, e2)| {
            r.fresnel_R(c1, c2, e1, e2)
        }),
    ] {
        let path = ctx.golden_path(name);
        GoldenFile::record(id, &pairs(seed), |&input| f(r, input)).save(&path)?;
        written.push(path);
    }

    let reflectance: Vec<ReflectanceInput> = samples(reflectance_strategy(), 400, 104)
        .into_iter()
        .filter(reflectance_is_clear)
        .take(128)
        .collect();
    let path = ctx.golden_path(GOLDEN_REFLECTANCE);
    GoldenFile::record("10.4", &reflectance, |&(c, e1, e2)| {
        r.fresnel_reflectance(c, e1, e2)
    })
    .save(&path)?;
    written.push(path);

    let transmittance: Vec<TransmittanceInput> = samples(transmittance_strategy(), 128, 105);
    let path = ctx.golden_path(GOLDEN_TRANSMITTANCE);
    GoldenFile::record("10.5", &transmittance, |&(d, rho)| {
        r.transmittance(d, &volume_material(rho))
    })
    .save(&path)?;
    written.push(path);

    for shot in Shot::ALL {
        let (part, _) = Part::ALL
            .iter()
            .find(|(_, shots)| shots.contains(&shot))
            .expect("every shot belongs to a part");
        let film = render_shot(shot, &part_pipeline(*part, reference, &ctx.base))?;
        let path = ctx.snapshot_path(&format!("{}.exr", shot.name()));
        raylab_core::film::write_exr(&film, &path)?;
        written.push(path);
    }
    Ok(written)
}
