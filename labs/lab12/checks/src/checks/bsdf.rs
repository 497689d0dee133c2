//! Exercises 12.1 and 12.2: luminance and the glossy BSDF's values.

use std::f64::consts::{PI, TAU};
use std::sync::Arc;

use glam::{DVec3, Vec3};
use proptest::prelude::*;

use contracts::lab12::{BsdfValue, PathMaterial, PathTracing};
use contracts::math::Onb;
use grading::strategies::unit_vector;
use grading::{GoldenFile, LabContext, compare_f32, compare_vec3, for_all};

use super::{CASES, above, key, load};

/// Golden file of Exercise 12.1.
pub const GOLDEN_LUMINANCE: &str = "luminance.json";
/// Golden file of Exercise 12.2.
pub const GOLDEN_BSDF: &str = "bsdf.json";

/// A linear RGB colour with channels of unequal size, from 10⁻⁴ to 10³.
pub fn colour() -> impl Strategy<Value = Vec3> + Clone {
    (0.0f32..1.0, 0.0f32..1.0, 0.0f32..1.0, -4.0f32..3.0)
        .prop_map(|(r, g, b, e)| Vec3::new(r, g, b) * 10f32.powf(e))
}

/// The glossy exponents the checks use: from a lobe as wide as the hemisphere to a near mirror.
pub const EXPONENTS: [f32; 6] = [0.0, 1.0, 5.0, 20.0, 100.0, 1000.0];

/// A material whose reflectances add up to at most one per channel, with unequal channels.
pub fn material() -> impl Strategy<Value = PathMaterial> + Clone {
    (
        (0.0f32..1.0, 0.0f32..1.0, 0.0f32..1.0),
        (0.0f32..1.0, 0.0f32..1.0, 0.0f32..1.0),
        0.0f32..1.0,
        prop::sample::select(EXPONENTS.to_vec()),
    )
        .prop_map(|((r, g, b), (sr, sg, sb), share, exponent)| {
            let total = Vec3::new(r, g, b);
            PathMaterial {
                diffuse: total * (1.0 - share),
                glossy: total * share * Vec3::new(sr, sg, sb).max(Vec3::splat(0.2)),
                exponent,
            }
        })
}

/// Input of Exercise 12.2: a material, a tilted normal and a pair of directions above it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BsdfInput {
    /// The material.
    pub material: PathMaterial,
    /// The shading normal.
    pub normal: Vec3,
    /// Towards the viewer.
    pub wo: Vec3,
    /// Towards the light.
    pub wi: Vec3,
}

/// Inputs of Exercise 12.2: half of the `wi` near the mirror direction of `wo`, where the lobe
/// is not negligible, the rest anywhere above the surface.
pub fn bsdf_input() -> impl Strategy<Value = BsdfInput> + Clone {
    (
        material(),
        unit_vector(),
        unit_vector(),
        unit_vector(),
        0.0f32..0.3,
        any::<bool>(),
    )
        .prop_map(|(material, normal, wo, d, spread, near)| {
            let wo = above(normal, wo, 0.02);
            let mirror = 2.0 * normal.dot(wo) * normal - wo;
            let wi = if near {
                above(normal, (mirror + d * spread).normalize(), 1e-3)
            } else {
                above(normal, d, 1e-3)
            };
            BsdfInput {
                material,
                normal,
                wo,
                wi,
            }
        })
}

/// Exercise 12.1: a grey is its own luminance; then the student's luminance equals the key's
/// on random colours where the key is present, and the golden cases' everywhere.
pub(super) fn exercise_12_1(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
    for g in [1e-4f32, 0.5, 1.0, 1e3] {
        compare_f32(
            &format!("luminance of the grey ({g}, {g}, {g})"),
            s.luminance(Vec3::splat(g)),
            g,
            0.0,
            1e-5,
        )?;
    }
    if let Some(key) = key(ctx) {
        for_all(CASES, colour(), |c| {
            compare_f32(
                &format!("luminance({c})"),
                s.luminance(c),
                key.luminance(c),
                0.0,
                1e-5,
            )
        })?;
    }
    let golden: GoldenFile<Vec3, f32> = load(ctx, GOLDEN_LUMINANCE)?;
    for case in &golden.cases {
        compare_f32(
            &format!("luminance({})", case.input),
            s.luminance(case.input),
            case.expected,
            0.0,
            1e-5,
        )?;
    }
    Ok(())
}

/// `∫ g(ω) dω` over the hemisphere of `normal`, by Simpson's rule on `theta_steps` intervals
/// of θ (fine enough for a lobe of exponent 1000 about the normal) and `phi_steps` of φ.
fn hemisphere_integral(
    normal: Vec3,
    theta_steps: usize,
    phi_steps: usize,
    g: &dyn Fn(Vec3) -> DVec3,
) -> DVec3 {
    let onb = Onb::from_w(normal);
    let h = PI / 2.0 / theta_steps as f64;
    let mut total = DVec3::ZERO;
    for i in 0..=theta_steps {
        let theta = i as f64 * h;
        let weight = match i {
            0 => 1.0,
            i if i == theta_steps => 1.0,
            i if i % 2 == 1 => 4.0,
            _ => 2.0,
        };
        let mut ring = DVec3::ZERO;
        for j in 0..phi_steps {
            let phi = (j as f64 + 0.5) * TAU / phi_steps as f64;
            let local = DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            ring += g(onb.to_world(local.as_vec3()).normalize());
        }
        total += weight * theta.sin() * ring * (TAU / phi_steps as f64);
    }
    total * h / 3.0
}

/// Exercise 12.2: zero below the surface; a reciprocal value; at normal incidence the
/// reflectance is `ρ_d + ρ_s` and the density integrates to one, at other angles the
/// reflectance is no more; then the key's values (where present) and the golden cases'.
pub(super) fn exercise_12_2(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
    let call = |i: &BsdfInput| {
        format!(
            "bsdf(material = {:?}, normal = {}, wo = {}, wi = {})",
            i.material, i.normal, i.wo, i.wi
        )
    };
    // Below the surface, on either side.
    for_all(CASES, bsdf_input(), |i| {
        for (wo, wi, which) in [
            (i.wo, -i.wi, "wi is"),
            (-i.wo, i.wi, "wo is"),
            (-i.wo, -i.wi, "both are"),
        ] {
            let below = BsdfInput { wo, wi, ..i };
            let got = s.bsdf(&below.material, below.normal, below.wo, below.wi);
            if got.value != Vec3::ZERO || got.pdf != 0.0 {
                return Err(format!(
                    "{} is {got:?} where {which} below the surface: return a zero value and density there",
                    call(&below)
                ));
            }
        }
        Ok(())
    })?;
    // Reciprocity: f(wo, wi) = f(wi, wo).
    for_all(CASES, bsdf_input(), |i| {
        let there = s.bsdf(&i.material, i.normal, i.wo, i.wi).value;
        let back = s.bsdf(&i.material, i.normal, i.wi, i.wo).value;
        compare_vec3(
            &format!("the value with wo and wi swapped, of {}", call(&i)),
            back,
            there,
            1e-6,
            1e-3,
        )
        .map_err(|e| format!("{e}: the BSDF is reciprocal, and so is the lobe about the mirror direction (r(wo)·wi = r(wi)·wo)"))
    })?;
    // At normal incidence the whole lobe is above the surface.
    let normal = Vec3::new(0.36, 0.48, 0.8);
    for exponent in EXPONENTS {
        for (diffuse, glossy) in [
            (Vec3::new(0.6, 0.3, 0.1), Vec3::ZERO),
            (Vec3::ZERO, Vec3::new(0.9, 0.5, 0.2)),
            (Vec3::new(0.3, 0.2, 0.1), Vec3::new(0.2, 0.5, 0.8)),
        ] {
            let m = PathMaterial {
                diffuse,
                glossy,
                exponent,
            };
            let albedo = hemisphere_integral(normal, 4000, 8, &|wi| {
                s.bsdf(&m, normal, normal, wi).value.as_dvec3() * f64::from(wi.dot(normal))
            });
            compare_vec3(
                &format!("∫ f cos θ dω, the reflectance at normal incidence of {m:?}"),
                albedo.as_vec3(),
                diffuse + glossy,
                2e-4,
                2e-3,
            )
            .map_err(|e| format!("{e} (ρ_d + ρ_s): the lobe's factor (n + 2)/(2π) makes its reflectance ρ_s there, the diffuse factor 1/π makes ρ_d"))?;
            let mass = hemisphere_integral(normal, 4000, 8, &|wi| {
                DVec3::splat(f64::from(s.bsdf(&m, normal, normal, wi).pdf))
            })
            .x;
            compare_f32(
                &format!("∫ pdf dω at normal incidence of {m:?}"),
                mass as f32,
                1.0,
                0.0,
                2e-3,
            )
            .map_err(|e| {
                format!("{e}: a density integrates to one (the lobe's factor is (n + 1)/(2π))")
            })?;
        }
    }
    // Elsewhere part of the lobe is below the surface: no more than ρ_d + ρ_s is reflected.
    for (k, exponent) in [1.0f32, 5.0, 20.0].into_iter().enumerate() {
        let m = PathMaterial {
            diffuse: Vec3::new(0.5, 0.4, 0.1),
            glossy: Vec3::new(0.5, 0.6, 0.9),
            exponent,
        };
        let cos = [0.8f32, 0.4, 0.1][k];
        let tangent = Onb::from_w(normal).u;
        let wo = (normal * cos + tangent * (1.0 - cos * cos).sqrt()).normalize();
        let albedo = hemisphere_integral(normal, 600, 160, &|wi| {
            s.bsdf(&m, normal, wo, wi).value.as_dvec3() * f64::from(wi.dot(normal))
        });
        if albedo.max_element() > 1.0 + 3e-3 {
            return Err(format!(
                "∫ f cos θ dω of {m:?} seen from wo = {wo} (cos θ_o = {cos}) is {albedo}: more light leaves than arrives"
            ));
        }
    }
    if let Some(key) = key(ctx) {
        for_all(CASES * 2, bsdf_input(), |i| {
            let got = s.bsdf(&i.material, i.normal, i.wo, i.wi);
            let expected = key.bsdf(&i.material, i.normal, i.wo, i.wi);
            compare_bsdf(&call(&i), got, expected)
        })?;
    }
    let golden: GoldenFile<BsdfInput, BsdfValue> = load(ctx, GOLDEN_BSDF)?;
    for case in &golden.cases {
        let i = &case.input;
        compare_bsdf(
            &call(i),
            s.bsdf(&i.material, i.normal, i.wo, i.wi),
            case.expected,
        )?;
    }
    Ok(())
}

pub(super) fn compare_bsdf(call: &str, got: BsdfValue, expected: BsdfValue) -> Result<(), String> {
    compare_vec3(
        &format!("the value of {call}"),
        got.value,
        expected.value,
        1e-6,
        2e-3,
    )?;
    compare_f32(
        &format!("the density of {call}"),
        got.pdf,
        expected.pdf,
        1e-6,
        2e-3,
    )
}

/// Exercise 12.1's golden inputs, exposed for the generator.
pub fn luminance_inputs() -> Vec<Vec3> {
    grading::strategies::samples(colour(), 64, 12)
}
