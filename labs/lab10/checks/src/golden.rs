use std::path::PathBuf;
use std::sync::Arc;

use super::checks::*;
use contracts::lab10::Fresnel;
use grading::LabContext;
use grading::part_snapshots::PartSnapshots;
use grading::strategies::samples;
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
        written.push(ctx.record_golden(name, id, &pairs(seed), |&input| f(r, input))?);
    }

    let reflectance: Vec<ReflectanceInput> = samples(reflectance_strategy(), 400, 104)
        .into_iter()
        .filter(reflectance_is_clear)
        .take(128)
        .collect();
    written.push(
        ctx.record_golden(GOLDEN_REFLECTANCE, "10.4", &reflectance, |&(c, e1, e2)| {
            r.fresnel_reflectance(c, e1, e2)
        })?,
    );

    let transmittance: Vec<TransmittanceInput> = samples(transmittance_strategy(), 128, 105);
    written.push(ctx.record_golden(
        GOLDEN_TRANSMITTANCE,
        "10.5",
        &transmittance,
        |&(d, rho)| r.transmittance(d, &volume_material(rho)),
    )?);

    written.extend(Part::save_snapshots(&Shot::ALL, reference, ctx)?);
    Ok(written)
}
