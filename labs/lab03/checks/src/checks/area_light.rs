//! Exercise 3.4: samples of an area light with their direction, distance and density.

use std::sync::Arc;

use glam::Vec3;
use proptest::prelude::*;

use contracts::lab02::LightSample;
use contracts::lab03::Shadows;
use grading::strategies::{point, scale, unit_vector};
use grading::{GoldenFile, LabContext, compare_f32, compare_vec3, for_all};

use super::irradiance::check_irradiance;
use super::soft_shadows::check_area_snapshot;
use super::{AreaSampleInput, GOLDEN_AREA_SAMPLE, Part};

/// Random inputs of Exercise 3.4.
pub fn area_sample_strategy() -> impl Strategy<Value = AreaSampleInput> {
    (
        point(3.0),
        point(3.0),
        unit_vector(),
        (0.0f32..20.0, 0.0f32..20.0, 0.0f32..20.0),
        prop_oneof![0.05f32..1.0, 1.0f32..50.0],
    )
        .prop_filter("light point away from the surface point", |(p, q, ..)| {
            (*q - *p).length() > 0.1
        })
        .prop_map(|(p, q, n, (r, g, b), pdf)| (p, q, n, Vec3::new(r, g, b), pdf))
}

/// Compares an area-light sample with the expected one; `unit` is the size of the
/// configuration (the distance's absolute tolerance is `1e-5·unit`).
fn compare_area_sample(
    input: &AreaSampleInput,
    got: LightSample,
    expected: LightSample,
    unit: f32,
) -> Result<(), String> {
    let (p, q, n, le, pdf) = input;
    let call = format!(
        "area_light_sample(position = {p}, light_point = {q}, light_normal = {n}, emission = {le}, pdf_area = {pdf})"
    );
    compare_vec3(
        &format!("the direction of {call}"),
        got.direction,
        expected.direction,
        1e-5,
        0.0,
    )?;
    compare_f32(
        &format!("the distance of {call}"),
        got.distance,
        expected.distance,
        1e-5 * unit,
        1e-5,
    )?;
    let cos_light = -n.dot(expected.direction);
    let hint = if cos_light <= 0.0 {
        format!(
            " (the point is behind the light: cos θ' = −n'·ω = {cos_light:.3} ≤ 0, so no light reaches it)"
        )
    } else {
        format!(
            " = L_e·cos θ'/(r²·p_A) with cos θ' = −n'·ω = {cos_light:.4}, r = {}, p_A = {pdf}",
            expected.distance
        )
    };
    compare_vec3(
        &format!("the radiance of {call}"),
        got.radiance,
        expected.radiance,
        1e-6,
        1e-4,
    )
    .map_err(|e| format!("{e}{hint}"))
}

/// The relations an area-light sample satisfies whatever its value: it points at the light
/// point from `r` away (to `1e-4·unit`, `unit` the size of the configuration); no light leaves
/// the back of the light, and some leaves its front; and its radiance is linear in `L_e`,
/// inversely proportional to `p_A` and to `r²` (the position moved back along the
/// direction), and proportional to `cos θ' = −n'·ω` (the light's normal tilted).
fn check_area_relations(s: &dyn Shadows, input: &AreaSampleInput, unit: f32) -> Result<(), String> {
    let &(p, q, n, le, pdf) = input;
    let call = format!(
        "area_light_sample(position = {p}, light_point = {q}, light_normal = {n}, emission = {le}, pdf_area = {pdf})"
    );
    let got = s.area_light_sample(p, q, n, le, pdf);
    compare_f32(
        &format!("the length of the direction of {call}"),
        got.direction.length(),
        1.0,
        1e-5,
        0.0,
    )?;
    compare_vec3(
        &format!("position + distance·direction of {call} (the light point)"),
        p + got.distance * got.direction,
        q,
        1e-4 * unit,
        1e-5,
    )
    .map_err(|e| format!("{e}: the sample points from the position to the light point"))?;
    let radiance =
        |p: Vec3, n: Vec3, le: Vec3, pdf: f32| s.area_light_sample(p, q, n, le, pdf).radiance;
    let towards = (q - p).normalize();
    if n.dot(towards) >= 0.0 {
        if got.radiance != Vec3::ZERO {
            return Err(format!(
                "the radiance of {call} is {}: the position is behind the light (−n'·ω = {:.4} ≤ 0), and a light emits from its front only",
                got.radiance,
                -n.dot(towards)
            ));
        }
        return Ok(());
    }
    let cos = -n.dot(towards);
    if cos > 1e-4 && (got.radiance.cmple(Vec3::ZERO) & le.cmpgt(Vec3::ZERO)).any() {
        return Err(format!(
            "the radiance of {call} is {}: the position is in front of the light (−n'·ω = {cos:.4} > 0) and the light emits {le}, so some of it must arrive, however close or small the light (no clamp or cut-off on r)",
            got.radiance
        ));
    }
    let related = [
        (
            "twice the emission",
            radiance(p, n, 2.0 * le, pdf),
            2.0 * got.radiance,
            "the radiance is linear in L_e",
        ),
        (
            "half the pdf",
            radiance(p, n, le, 0.5 * pdf),
            2.0 * got.radiance,
            "the estimate divides by the density p_A",
        ),
        (
            "the position moved back to twice the distance",
            radiance(q - 2.0 * (q - p), n, le, pdf),
            0.25 * got.radiance,
            "the solid angle of a patch falls as 1/r²",
        ),
    ];
    for (change, value, expected, law) in related {
        compare_vec3(
            &format!("the radiance of {call} with {change}"),
            value,
            expected,
            1e-6,
            1e-3,
        )
        .map_err(|e| format!("{e}: {law}"))?;
    }
    // Tilt the light's normal towards the position: the radiance grows with cos θ'.
    if cos < 0.9 {
        let facing = -towards;
        if let Some(tilted) = (n + facing).try_normalize() {
            let cos_tilted = tilted.dot(facing);
            compare_vec3(
                &format!("the radiance of {call} with the light normal tilted to {tilted} (cos θ' from {cos:.4} to {cos_tilted:.4})"),
                radiance(p, tilted, le, pdf),
                got.radiance * (cos_tilted / cos),
                1e-6,
                1e-3,
            )
            .map_err(|e| format!("{e}: the light leaving the patch towards the position falls with cos θ' = −n'·ω"))?;
        }
    }
    Ok(())
}

pub(super) fn exercise_3_4(s: &Arc<dyn Shadows>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx.key().map(|k| k.code::<dyn contracts::lab03::Shadows>());
    let judge = |input: AreaSampleInput, unit: f32| {
        check_area_relations(s.as_ref(), &input, unit)?;
        let Some(key) = &key else {
            return Ok(());
        };
        let (p, q, n, le, pdf) = input;
        compare_area_sample(
            &input,
            s.area_light_sample(p, q, n, le, pdf),
            key.area_light_sample(p, q, n, le, pdf),
            unit,
        )
    };
    for_all(300, area_sample_strategy(), |input| judge(input, 1.0))?;
    // The same configurations at every scale, from a lamp of 10⁻⁴ units seen from close by to
    // one of 10³ seen from far away. The density per unit area of a light of k times the size
    // is 1/k² of the original's, so the radiance stays what it is at scale 1: a clamp or
    // cut-off on r tuned to metre-sized scenes shows at the small end.
    for_all(
        300,
        (area_sample_strategy(), scale()),
        |((p, q, n, le, pdf), k)| judge((k * p, k * q, n, le, pdf / (k * k)), k),
    )?;
    let golden: GoldenFile<AreaSampleInput, LightSample> = ctx.golden(GOLDEN_AREA_SAMPLE)?;
    for case in &golden.cases {
        let (p, q, n, le, pdf) = case.input;
        compare_area_sample(
            &case.input,
            s.area_light_sample(p, q, n, le, pdf),
            case.expected,
            1.0,
        )?;
    }
    check_irradiance(Part::AreaSample, s, &ctx.base)?;
    check_area_snapshot(Part::AreaSample, s, ctx)
}
