use std::path::PathBuf;
use std::sync::Arc;

use glam::Vec3;

use super::checks::*;
use contracts::lab04::Reflection;
use grading::LabContext;
use grading::part_snapshots::PartSnapshots;
use grading::strategies::{samples, unit_vector};
use raylab_core::Error;

/// Writes lab 04's golden cases and snapshots from `reference` into the lab's directory.
///
/// Cases where two correct implementations may decide differently in floating point — a
/// direction within 0.1% of the critical angle, or almost tangent to the surface — are left
/// out.
pub fn generate_golden(
    reference: &Arc<dyn Reflection>,
    ctx: &LabContext,
) -> Result<Vec<PathBuf>, Error> {
    let r = reference.as_ref();
    let mut written = Vec::new();

    let reflect: Vec<ReflectInput> = samples((unit_vector(), unit_vector()), 64, 41);
    written.push(ctx.record_golden(GOLDEN_REFLECT, "4.1", &reflect, |&(w, n)| r.reflect(w, n))?);

    let sides: Vec<SideInput> = samples(side_strategy(), 96, 43);
    written.push(
        ctx.record_golden(GOLDEN_INTERFACE, "4.3", &sides, |&input| {
            let (w, n, hit_ior, material_ior) = input;
            r.interface(
                w,
                &hit_at(Vec3::new(0.5, -1.0, 2.0), n, n, hit_ior),
                material_ior,
            )
        })?,
    );

    let refract: Vec<RefractInput> = samples(refract_strategy(), 400, 44)
        .into_iter()
        .filter(|&(w, n, ei, et)| refract_is_clear(w, n, ei, et))
        .take(128)
        .collect();
    written.push(
        ctx.record_golden(GOLDEN_REFRACT, "4.4", &refract, |&(w, n, ei, et)| {
            r.refract(w, n, ei, et)
        })?,
    );

    let rays: Vec<SideInput> = samples(side_strategy(), 400, 45)
        .into_iter()
        .filter(side_is_clear)
        .take(128)
        .collect();
    written.push(
        ctx.record_golden(GOLDEN_REFRACTED_RAY, "4.5", &rays, |&input| {
            let (w, n, hit_ior, material_ior) = input;
            let hit = hit_at(Vec3::new(0.5, -1.0, 2.0), n, n, hit_ior);
            r.refracted_ray(&incoming_ray(hit.position, w, 2.0), &hit, material_ior)
                .map(|(ray, ior)| (ray.direction, ior))
        })?,
    );

    let phong: Vec<PhongInput> = samples(phong_strategy(), 96, 46);
    written.push(ctx.record_golden(
        GOLDEN_PHONG,
        "4.6",
        &phong,
        |(rho_d, rho_s, s, n, v, lights)| {
            r.shade_phong(*rho_d, *rho_s, *s, *n, *v, &samples_of(lights))
        },
    )?);

    written.extend(Part::save_snapshots(&Shot::ALL, reference, ctx)?);
    Ok(written)
}
