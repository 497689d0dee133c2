//! Lab 12's exercises and their checks.
//!
//! The samplers are judged by their distributions, never by the directions one random number
//! gives: a correct sampler that maps its numbers another way passes. Where the answer key is
//! absent (a handout before the solution), what the checks need of it is recorded in `golden/`:
//! exact values for the deterministic functions, and for the BSDF sampler the key's histogram
//! and reflectance from many samples.

use std::f64::consts::{PI, TAU};
use std::sync::Arc;

use glam::{DVec3, Vec3};
use proptest::prelude::*;

use contracts::lab12::{BsdfSample, BsdfValue, EmitterSample, PathMaterial, PathTracing};
use contracts::math::Onb;
use contracts::sampling::Rng;
use grading::chi2::{SphereGrid, chi_square_two_sample};
use grading::stats::{
    NoiseTolerance, RenderStatistics, family_z_limit, mean_and_standard_error, sidak,
};
use grading::strategies::unit_vector;
use grading::{Exercise, GoldenFile, LabContext, compare_f32, compare_vec3, for_all};
use pipeline::render::render;

use crate::sky::{exercise_12_11, exercise_12_12, exercise_12_13};
use pipeline::{PartSlot, Pipeline, View};
use raylab_core::film::Film;
use raylab_core::render::RenderSettings;

/// This lab.
pub const LAB: course::LabId = course::LabId::of(12);

/// Golden file of Exercise 12.1.
pub const GOLDEN_LUMINANCE: &str = "luminance.json";
/// Golden file of Exercise 12.2.
pub const GOLDEN_BSDF: &str = "bsdf.json";
/// Golden file of Exercise 12.3: the key's histogram and reflectance per case.
pub const GOLDEN_SAMPLE_BSDF: &str = "sample_bsdf.json";
/// Golden file of Exercise 12.5.
pub const GOLDEN_EMITTER_PDF: &str = "emitter_pdf.json";
/// Golden file of Exercise 12.6.
pub const GOLDEN_POWER_HEURISTIC: &str = "power_heuristic.json";

/// Family-wise significance of each exercise's statistical tests, split over them by Šidák's
/// correction: a correct implementation fails one in a thousand seeds.
pub const SIGNIFICANCE: f64 = 1e-3;
/// Random inputs per property.
const CASES: u32 = 200;
/// The student's draws per case of the BSDF sampler.
pub const BSDF_SAMPLES: usize = 20_000;
/// The key's draws per case, recorded in the golden file.
pub const KEY_BSDF_SAMPLES: usize = 400_000;
/// The cells the BSDF's samples are counted in, in the frame of the normal (the cells below
/// the surface stay empty), and one more for the draws that returned `None`.
pub const BSDF_GRID: SphereGrid = SphereGrid {
    cos_theta_cells: 20,
    phi_cells: 24,
};
/// The coarser cells of the test of the densities returned (`E[1/pdf]` over a cell is its solid
/// angle), so that each cell above the horizon band holds a hundred draws or more.
pub const PDF_GRID: SphereGrid = SphereGrid {
    cos_theta_cells: 10,
    phi_cells: 4,
};
/// Points drawn per case of the emitter checks.
const EMITTER_SAMPLES: usize = 4_000;

/// The exercises of lab 12 (`labs/lab12/exercises.toml`), each with its check.
pub fn exercises() -> Vec<Exercise<dyn PathTracing>> {
    grading::exercises(
        LAB,
        grading::checks![
            exercise_12_1,
            exercise_12_2,
            exercise_12_3,
            exercise_12_4,
            exercise_12_5,
            exercise_12_6,
            exercise_12_7,
            exercise_12_8,
            exercise_12_9,
            exercise_12_10,
            exercise_12_11,
            exercise_12_12,
            exercise_12_13
        ],
    )
}

/// The answer key's code of this lab, where the context has it.
fn key(ctx: &LabContext) -> Option<Arc<dyn PathTracing>> {
    ctx.key().and_then(|k| k.part::<dyn PathTracing>())
}

fn load<I, O>(ctx: &LabContext, name: &str) -> Result<GoldenFile<I, O>, String>
where
    I: serde::Serialize + serde::de::DeserializeOwned,
    O: serde::Serialize + serde::de::DeserializeOwned,
{
    ctx.golden(name)
}

// ---------------------------------------------------------------------------------------------
// Inputs

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

/// A unit direction on the side of `normal`, at least `min_cos` from its plane.
fn above(normal: Vec3, d: Vec3, min_cos: f32) -> Vec3 {
    let d = if d.dot(normal) < 0.0 { -d } else { d };
    if d.dot(normal) >= min_cos {
        d
    } else {
        (d + normal * (min_cos - d.dot(normal) + 1e-3)).normalize()
    }
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

/// A case of the BSDF sampler: a material seen from `wo` above the tilted `normal`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SamplerCase {
    /// The material.
    pub material: PathMaterial,
    /// The shading normal.
    pub normal: Vec3,
    /// Towards the viewer.
    pub wo: Vec3,
}

/// The cases of Exercise 12.3: diffuse, glossy and mixed, wide and narrow lobes, from head-on
/// to grazing, under tilted normals.
pub fn sampler_cases() -> Vec<SamplerCase> {
    let grey = |v: f32| Vec3::splat(v);
    let tint = Vec3::new(0.9, 0.6, 0.3);
    let cases = [
        (grey(0.8), Vec3::ZERO, 0.0, 0.7),
        (tint * 0.5, grey(0.4), 1.0, 0.9),
        (tint * 0.3, grey(0.6), 5.0, 0.3),
        (tint * 0.6, Vec3::new(0.2, 0.3, 0.35), 20.0, 0.6),
        (grey(0.2), tint * 0.8, 100.0, 0.95),
        (tint * 0.2, grey(0.7), 1000.0, 0.8),
        (Vec3::ZERO, grey(0.9), 0.0, 0.5),
        (Vec3::ZERO, tint, 20.0, 0.15),
        (grey(0.45), grey(0.45), 10.0, 0.05),
    ];
    let normals = grading::strategies::samples(unit_vector(), cases.len(), 12);
    let azimuths = grading::strategies::samples(unit_vector(), cases.len(), 13);
    cases
        .iter()
        .zip(normals.iter().zip(&azimuths))
        .map(|(&(diffuse, glossy, exponent, cos), (&normal, &side))| {
            // `wo` at the case's cosine from the normal, in a random azimuth.
            let tangent = (side - normal * side.dot(normal)).normalize_or(Onb::from_w(normal).u);
            let wo = (normal * cos + tangent * (1.0 - cos * cos).sqrt()).normalize();
            SamplerCase {
                material: PathMaterial {
                    diffuse,
                    glossy,
                    exponent,
                },
                normal,
                wo,
            }
        })
        .collect()
}

/// What the key's samples of a [`SamplerCase`] show, recorded in the golden file.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SamplerReference {
    /// Draws per cell of [`BSDF_GRID`] in the frame of the normal, then the draws that
    /// returned `None`.
    pub histogram: Vec<u64>,
    /// The mean of `f cos θ / pdf` per channel: the directional reflectance.
    pub reflectance: [f64; 3],
    /// Its standard error per channel.
    pub reflectance_error: [f64; 3],
}

/// What `samples` draws of `sampler` show: the histogram of [`SamplerReference`] and per
/// draw the direction, value and density (for the checks of each).
pub struct SamplerRun {
    /// The recorded summary.
    pub summary: SamplerReference,
    /// Each draw that returned a direction.
    pub draws: Vec<BsdfSample>,
}

/// Draws `samples` directions of `case` from `code` (from a generator seeded by the case),
/// checking each is a unit vector above the surface with finite value and positive density.
pub fn run_sampler(
    code: &dyn PathTracing,
    case: &SamplerCase,
    seed: u64,
    samples: usize,
) -> Result<SamplerRun, String> {
    let onb = Onb::from_w(case.normal);
    let mut rng = Rng::new(seed, 12);
    let mut histogram = vec![0u64; BSDF_GRID.len() + 1];
    let mut draws = Vec::with_capacity(samples);
    let (mut sum, mut sum_sq) = (DVec3::ZERO, DVec3::ZERO);
    let call = format!(
        "sample_bsdf(material = {:?}, normal = {}, wo = {})",
        case.material, case.normal, case.wo
    );
    for _ in 0..samples {
        let Some(s) = code.sample_bsdf(&case.material, case.normal, case.wo, &mut rng) else {
            histogram[BSDF_GRID.len()] += 1;
            continue;
        };
        let length = s.direction.length();
        let unit = (length - 1.0).abs() <= 1e-4;
        if !unit {
            return Err(format!(
                "{call} returned the direction {} of length {length}: return a unit vector",
                s.direction
            ));
        }
        let cos = s.direction.dot(case.normal);
        if cos <= 0.0 {
            return Err(format!(
                "{call} returned the direction {} below the surface (cos θ = {cos}): return `None` there",
                s.direction
            ));
        }
        if !(s.pdf > 0.0
            && s.pdf.is_finite()
            && s.value.is_finite()
            && s.value.min_element() >= 0.0)
        {
            return Err(format!(
                "{call} returned the direction {} with value {} and pdf {}: a direction drawn has a positive, finite density and a finite, non-negative value",
                s.direction, s.value, s.pdf
            ));
        }
        let cell = BSDF_GRID
            .cell(onb.to_local(s.direction))
            .expect("a unit vector has a cell");
        histogram[cell] += 1;
        let weight = s.value.as_dvec3() * f64::from(cos) / f64::from(s.pdf);
        sum += weight;
        sum_sq += weight * weight;
        draws.push(s);
    }
    let n = samples as f64;
    let mean = sum / n;
    let variance = (sum_sq / n - mean * mean).max(DVec3::ZERO) / (n - 1.0);
    Ok(SamplerRun {
        summary: SamplerReference {
            histogram,
            reflectance: mean.to_array(),
            reflectance_error: variance.to_array().map(f64::sqrt),
        },
        draws,
    })
}

/// A triangle, a point in front of it, at a scale of [`SCALES`] and moved away from the
/// origin.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EmitterCase {
    /// The emitting triangle.
    pub triangle: [Vec3; 3],
    /// The shaded point.
    pub position: Vec3,
}

/// Cases of the emitter checks: random triangles seen from random points in front, near (a
/// fifth of their size) and far (fifty times), head-on and at a grazing angle.
pub fn emitter_case() -> impl Strategy<Value = EmitterCase> + Clone {
    (
        grading::strategies::triangle_strategy(),
        unit_vector(),
        prop::sample::select(vec![0.2f32, 1.0, 5.0, 50.0]),
        grading::strategies::scale(),
        grading::strategies::point(1.0),
    )
        .prop_map(|([a, b, c], d, distance, scale, offset)| {
            let normal = (b - a).cross(c - a).normalize();
            let centre = (a + b + c) / 3.0;
            let d = above(normal, d, 0.05);
            let place = |p: Vec3| (p * scale) + offset * (scale * 20.0);
            EmitterCase {
                triangle: [place(a), place(b), place(c)],
                position: place(centre + d * distance * 2.0),
            }
        })
}

/// The solid angle of the triangle `[a, b, c]` seen from `p` (Van Oosterom and Strackee 1983).
pub fn solid_angle(p: DVec3, [a, b, c]: [DVec3; 3]) -> f64 {
    let (a, b, c) = (a - p, b - p, c - p);
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let numerator = a.dot(b.cross(c)).abs();
    let denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * numerator.atan2(denominator)
}

/// The four triangles the edge midpoints cut `t` into.
fn quarters([a, b, c]: [DVec3; 3]) -> [[DVec3; 3]; 4] {
    let (ab, bc, ca) = ((a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0);
    [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
}

/// Which of [`quarters`] the point with barycentric coordinates `(β, γ)` (of `b` and `c`) is in.
fn quarter(beta: f64, gamma: f64) -> usize {
    let alpha = 1.0 - beta - gamma;
    if alpha >= 0.5 {
        0
    } else if beta >= 0.5 {
        1
    } else if gamma >= 0.5 {
        2
    } else {
        3
    }
}

/// The barycentric coordinates `(β, γ)` of `p` in `[a, b, c]`, and its distance from the plane.
fn barycentric(p: DVec3, [a, b, c]: [DVec3; 3]) -> (f64, f64, f64) {
    let (e1, e2, d) = (b - a, c - a, p - a);
    let n = e1.cross(e2);
    let nn = n.length_squared();
    let beta = d.cross(e2).dot(n) / nn;
    let gamma = e1.cross(d).dot(n) / nn;
    (beta, gamma, d.dot(n) / nn.sqrt())
}

// ---------------------------------------------------------------------------------------------
// The exercises

/// Exercise 12.1: a grey is its own luminance; then the student's luminance equals the key's
/// on random colours where the key is present, and the golden cases' everywhere.
fn exercise_12_1(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
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
fn exercise_12_2(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
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

fn compare_bsdf(call: &str, got: BsdfValue, expected: BsdfValue) -> Result<(), String> {
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

/// Exercise 12.3: the generator advances and is the only randomness; directions above the
/// surface with positive densities; per case, the histogram of the draws against the key's
/// (two-sample χ²), the returned densities against the histogram (`E[1/pdf]` over a cell is its
/// solid angle, wherever the diffuse lobe reaches) and the reflectance `E[f cos θ / pdf]`
/// against the key's; with the key, the value and density at every direction drawn.
fn exercise_12_3(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
    let cases = sampler_cases();
    let golden: GoldenFile<SamplerCase, SamplerReference> = load(ctx, GOLDEN_SAMPLE_BSDF)?;
    if golden.cases.len() != cases.len() {
        return Err(format!(
            "{} holds {} cases, the check has {}: regenerate the golden data",
            GOLDEN_SAMPLE_BSDF,
            golden.cases.len(),
            cases.len()
        ));
    }
    let key = key(ctx);
    // The tests: a χ² and three reflectances per case, and the cells' densities of the cases
    // with a diffuse lobe.
    let upper_cells = PDF_GRID.len() / 2 - PDF_GRID.phi_cells as usize;
    let tests = cases.len() * 4 + cases.len() * upper_cells;
    let alpha = sidak(SIGNIFICANCE, tests);
    let z_limit = family_z_limit(SIGNIFICANCE, tests);
    for (k, (case, recorded)) in cases
        .iter()
        .zip(golden.cases.iter().map(|c| &c.expected))
        .enumerate()
    {
        let call = format!(
            "sample_bsdf(material = {:?}, normal = {}, wo = {})",
            case.material, case.normal, case.wo
        );
        // The generator: advanced, and the only source of randomness.
        let mut rng = Rng::new(100 + k as u64, 1);
        let mut twin = rng.clone();
        let first = s.sample_bsdf(&case.material, case.normal, case.wo, &mut rng);
        let again = s.sample_bsdf(&case.material, case.normal, case.wo, &mut twin);
        if first != again {
            return Err(format!(
                "{call} returned {first:?} and then {again:?} from generators in the same state: draw every random number from `rng`"
            ));
        }
        let next: Vec<_> = (0..4)
            .map(|_| s.sample_bsdf(&case.material, case.normal, case.wo, &mut rng))
            .collect();
        if next.iter().all(|n| *n == first) {
            return Err(format!(
                "{call} returned {first:?} five times in a row: advance `rng` (draw new numbers from it every call)"
            ));
        }
        // Seen from below, nothing.
        let below = s.sample_bsdf(&case.material, case.normal, -case.wo, &mut rng);
        if below.is_some() {
            return Err(format!(
                "sample_bsdf(material = {:?}, normal = {}, wo = {}) returned {below:?} with wo below the surface: return `None`",
                case.material, case.normal, -case.wo
            ));
        }

        let run = run_sampler(s.as_ref(), case, 1200 + k as u64, BSDF_SAMPLES)?;
        let got = &run.summary;
        let outcome = chi_square_two_sample(&got.histogram, &recorded.histogram, 10)
            .map_err(|e| format!("{call}: {e}"))?;
        if outcome.p_value < alpha {
            let none = |h: &[u64]| h[BSDF_GRID.len()] as f64 / h.iter().sum::<u64>() as f64;
            return Err(format!(
                "{call}: {BSDF_SAMPLES} directions are not distributed as the answer key's {KEY_BSDF_SAMPLES}: two-sample χ² = {:.1} with {} degrees of freedom, p = {:.2e} < {alpha:.2e}. Directions returned `None`: {:.1} % (the key's {:.1} %). Choose the lobe with P_s from the first number and draw the direction from the next two",
                outcome.statistic,
                outcome.degrees_of_freedom,
                outcome.p_value,
                100.0 * none(&got.histogram),
                100.0 * none(&recorded.histogram),
            ));
        }
        for c in 0..3 {
            let (a, b) = (got.reflectance[c], recorded.reflectance[c]);
            let error = got.reflectance_error[c].hypot(recorded.reflectance_error[c]);
            if (a - b).abs() > z_limit * error + 1e-4 * (1.0 + b.abs()) {
                let channel = ["red", "green", "blue"][c];
                return Err(format!(
                    "{call}: the mean of value·cos θ/pdf over {BSDF_SAMPLES} draws, the {channel} reflectance, is {a:.5} ± {:.5}; the key's is {b:.5} ± {:.5}. Return f of the whole BSDF (Exercise 12.2's value) and the mixture's density at the direction drawn",
                    got.reflectance_error[c], recorded.reflectance_error[c]
                ));
            }
        }
        // Where the diffuse lobe reaches every cell above the surface, the densities returned
        // must be the density of the directions: E[1_C/pdf] = |C| for every cell C (the band
        // at the horizon left out, where 1/pdf has no variance).
        if case.material.diffuse.max_element() > 0.0 {
            let onb = Onb::from_w(case.normal);
            let mut per_cell = vec![Vec::new(); PDF_GRID.len()];
            for d in &run.draws {
                let cell = PDF_GRID
                    .cell(onb.to_local(d.direction))
                    .expect("a unit vector");
                per_cell[cell].push(1.0 / f64::from(d.pdf));
            }
            let omega = 4.0 * PI / PDF_GRID.len() as f64;
            let first_upper = PDF_GRID.len() / 2 + PDF_GRID.phi_cells as usize;
            for (cell, values) in per_cell.iter().enumerate().skip(first_upper) {
                let (mean, error) = mean_and_standard_error(values, BSDF_SAMPLES);
                let z = (mean - omega) / error.max(1e-12);
                if z.abs() > z_limit {
                    let band = (cell / PDF_GRID.phi_cells as usize) as f64;
                    let cos0 = -1.0 + band * 2.0 / PDF_GRID.cos_theta_cells as f64;
                    return Err(format!(
                        "{call}: over the directions with cos θ in [{cos0:.1}, {:.1}) the mean of 1/pdf is {mean:.5} ± {error:.5}, not the cell's solid angle {omega:.5} (z = {z:.1}): the pdf returned is not the density of the directions drawn — return the mixture's (1 − P_s)·cos θ/π + P_s·(n + 1)/(2π)·cos^n α, whichever lobe drew the direction",
                        cos0 + 2.0 / PDF_GRID.cos_theta_cells as f64
                    ));
                }
            }
        }
        if let Some(key) = &key {
            for d in run.draws.iter().take(2_000) {
                let expected = key.bsdf(&case.material, case.normal, case.wo, d.direction);
                compare_bsdf(
                    &format!("{call} at the direction it drew, {}", d.direction),
                    BsdfValue {
                        value: d.value,
                        pdf: d.pdf,
                    },
                    expected,
                )?;
            }
        }
    }
    Ok(())
}

/// Draws `EMITTER_SAMPLES` points of `case` from `s`, checking each lies on the triangle with
/// the radiance given; then `E[1/pdf]` over each quarter of the triangle must be its solid
/// angle (Z-tests at `z_limit`).
fn check_emitter_case(
    s: &dyn PathTracing,
    case: &EmitterCase,
    seed: u64,
    z_limit: f64,
    key: Option<&dyn PathTracing>,
) -> Result<(), String> {
    let radiance = Vec3::new(3.0, 2.0, 0.5);
    let call = format!(
        "sample_emitter(triangle = {:?}, radiance = {radiance}, position = {})",
        case.triangle, case.position
    );
    let t = case.triangle.map(Vec3::as_dvec3);
    let p = case.position.as_dvec3();
    let size = (t[1] - t[0]).length().max((t[2] - t[0]).length());
    let mut rng = Rng::new(seed, 12);
    let mut per_quarter: [Vec<f64>; 4] = Default::default();
    let mut points = Vec::new();
    for _ in 0..EMITTER_SAMPLES {
        let Some(sample) = s.sample_emitter(case.triangle, radiance, case.position, &mut rng)
        else {
            return Err(format!(
                "{call} returned `None`, but the point sees the emitting side of the triangle"
            ));
        };
        let EmitterSample {
            direction,
            distance,
            radiance: got,
            pdf,
            delta,
        } = sample;
        if delta {
            return Err(format!(
                "{call} returned a sample with `delta: true`: a triangle is an area light, which a direction drawn from a BSDF can hit too"
            ));
        }
        let unit = (direction.length() - 1.0).abs() <= 1e-4;
        if !unit {
            return Err(format!(
                "{call} returned the direction {direction} of length {}: return a unit vector",
                direction.length()
            ));
        }
        if got != radiance {
            return Err(format!(
                "{call} returned the radiance {got}: return the emitter's radiance as it is"
            ));
        }
        if !(pdf > 0.0 && pdf.is_finite()) {
            return Err(format!(
                "{call} returned the density {pdf}: a point drawn has a positive, finite density"
            ));
        }
        let point = p + direction.as_dvec3() * f64::from(distance);
        let (beta, gamma, off) = barycentric(point, t);
        let tol = 2e-3;
        if off.abs() > 1e-3 * size || beta < -tol || gamma < -tol || beta + gamma > 1.0 + tol {
            return Err(format!(
                "{call}: position + distance·direction = {} is not on the triangle (barycentric β = {beta:.4}, γ = {gamma:.4}, {off:.3e} off its plane): return the direction to the point drawn and its distance",
                point.as_vec3()
            ));
        }
        per_quarter[quarter(beta, gamma)].push(1.0 / f64::from(pdf));
        if points.len() < 200 {
            points.push((direction, distance, pdf));
        }
    }
    for (q, sub) in quarters(t).into_iter().enumerate() {
        let omega = solid_angle(p, sub);
        let (mean, error) = mean_and_standard_error(&per_quarter[q], EMITTER_SAMPLES);
        let z = (mean - omega) / error.max(omega * 1e-9);
        if z.abs() > z_limit {
            let total = solid_angle(p, t);
            let (all, _) = mean_and_standard_error(
                &per_quarter.iter().flatten().copied().collect::<Vec<_>>(),
                EMITTER_SAMPLES,
            );
            return Err(format!(
                "{call}: the mean of 1/pdf over the points drawn in one quarter of the triangle is {mean:.4e} ± {error:.2e}, not its solid angle {omega:.4e} (z = {z:.1}); over the whole triangle {all:.4e}, its solid angle {total:.4e}. Points are uniform over the area (density 1/A) and pdf = d²/(A cos θ_l) per unit solid angle"
            ));
        }
    }
    if let Some(key) = key {
        for (direction, distance, pdf) in points {
            let expected = key.emitter_pdf(case.triangle, case.position, direction, distance);
            compare_f32(
                &format!("the density {call} returned with the direction {direction}"),
                pdf,
                expected,
                0.0,
                2e-3,
            )?;
        }
    }
    Ok(())
}

/// Exercise 12.4: on random triangles at every scale, near and far, head-on and grazing: points
/// on the triangle, the radiance as given, `E[1/pdf]` the solid angle of each quarter of the
/// triangle; `None` from behind and for a triangle without area; the generator advances.
fn exercise_12_4(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
    let cases = grading::strategies::samples(emitter_case(), 24, 41);
    let z_limit = family_z_limit(SIGNIFICANCE, cases.len() * 4);
    let key = key(ctx);
    for (k, case) in cases.iter().enumerate() {
        check_emitter_case(s.as_ref(), case, 400 + k as u64, z_limit, key.as_deref())?;
        // From behind: the point mirrored through the triangle's plane.
        let [a, b, c] = case.triangle;
        let n = (b - a).cross(c - a).normalize();
        let behind = case.position - 2.0 * n * n.dot(case.position - a);
        let mut rng = Rng::new(7, k as u64);
        for _ in 0..8 {
            if let Some(got) = s.sample_emitter(case.triangle, Vec3::ONE, behind, &mut rng) {
                return Err(format!(
                    "sample_emitter(triangle = {:?}, position = {behind}) returned {got:?}, but the point is behind the triangle, which emits on the side of (v1 − v0) × (v2 − v0): return `None`",
                    case.triangle
                ));
            }
        }
    }
    // The generator advances.
    let case = &cases[0];
    let mut rng = Rng::new(5, 5);
    let first = s.sample_emitter(case.triangle, Vec3::ONE, case.position, &mut rng);
    let second = s.sample_emitter(case.triangle, Vec3::ONE, case.position, &mut rng);
    if first == second {
        return Err(format!(
            "sample_emitter(triangle = {:?}, position = {}) returned {first:?} twice in a row: draw new numbers from `rng` every call",
            case.triangle, case.position
        ));
    }
    // A triangle without area.
    let line = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
    let mut rng = Rng::new(6, 6);
    let got = s.sample_emitter(line, Vec3::ONE, Vec3::new(0.5, 1.0, 0.0), &mut rng);
    if got.is_some() {
        return Err(format!(
            "sample_emitter(triangle = {line:?}, …) returned {got:?} for a triangle without area: return `None`"
        ));
    }
    Ok(())
}

/// Exercise 12.5: points drawn uniformly on random triangles (by the check) have
/// `E[1/emitter_pdf]` equal to the solid angle of each quarter; 0 from behind and for a
/// triangle without area; the key's values (where present) and the golden cases'.
fn exercise_12_5(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
    let cases = grading::strategies::samples(emitter_case(), 24, 51);
    let z_limit = family_z_limit(SIGNIFICANCE, cases.len() * 4);
    for (k, case) in cases.iter().enumerate() {
        let t = case.triangle.map(Vec3::as_dvec3);
        let p = case.position.as_dvec3();
        let mut rng = Rng::new(500 + k as u64, 12);
        let mut per_quarter: [Vec<f64>; 4] = Default::default();
        for _ in 0..EMITTER_SAMPLES {
            let (u, v) = (f64::from(rng.next_f32()), f64::from(rng.next_f32()));
            let r = u.sqrt();
            let (beta, gamma) = (r * (1.0 - v), r * v);
            let point = t[0] * (1.0 - beta - gamma) + t[1] * beta + t[2] * gamma;
            let to = point - p;
            let distance = to.length();
            let direction = (to / distance).as_vec3();
            let pdf = s.emitter_pdf(case.triangle, case.position, direction, distance as f32);
            if !(pdf > 0.0 && pdf.is_finite()) {
                return Err(format!(
                    "emitter_pdf(triangle = {:?}, position = {}, direction = {direction}, distance = {distance}) is {pdf}, for a point on the emitting side of the triangle",
                    case.triangle, case.position
                ));
            }
            per_quarter[quarter(beta, gamma)].push(1.0 / f64::from(pdf));
        }
        for (q, sub) in quarters(t).into_iter().enumerate() {
            let omega = solid_angle(p, sub);
            let (mean, error) = mean_and_standard_error(&per_quarter[q], EMITTER_SAMPLES);
            let z = (mean - omega) / error.max(omega * 1e-9);
            if z.abs() > z_limit {
                return Err(format!(
                    "emitter_pdf(triangle = {:?}, position = {}, …): over points drawn uniformly on one quarter of the triangle, the mean of 1/pdf is {mean:.4e} ± {error:.2e}, not the quarter's solid angle {omega:.4e} (z = {z:.1}): pdf = d²/(A cos θ_l), with A the triangle's area and θ_l at the emitter",
                    case.triangle, case.position
                ));
            }
        }
        let [a, b, c] = case.triangle;
        let n = (b - a).cross(c - a).normalize();
        let behind = case.position - 2.0 * n * n.dot(case.position - a);
        let centre = (a + b + c) / 3.0;
        let to = centre - behind;
        let pdf = s.emitter_pdf(case.triangle, behind, to.normalize(), to.length());
        if pdf != 0.0 {
            return Err(format!(
                "emitter_pdf(triangle = {:?}, position = {behind}, …) is {pdf} from behind the triangle, which emits on the side of (v1 − v0) × (v2 − v0) only: return 0",
                case.triangle
            ));
        }
    }
    let line = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
    let pdf = s.emitter_pdf(line, Vec3::new(0.5, 1.0, 0.0), -Vec3::Y, 1.0);
    if pdf != 0.0 {
        return Err(format!(
            "emitter_pdf(triangle = {line:?}, …) is {pdf} for a triangle without area: return 0"
        ));
    }
    let call = |c: &(EmitterCase, Vec3, f32)| {
        format!(
            "emitter_pdf(triangle = {:?}, position = {}, direction = {}, distance = {})",
            c.0.triangle, c.0.position, c.1, c.2
        )
    };
    if let Some(key) = key(ctx) {
        for_all(CASES, emitter_pdf_input(), |c| {
            compare_f32(
                &call(&c),
                s.emitter_pdf(c.0.triangle, c.0.position, c.1, c.2),
                key.emitter_pdf(c.0.triangle, c.0.position, c.1, c.2),
                0.0,
                2e-3,
            )
        })?;
    }
    let golden: GoldenFile<(EmitterCase, Vec3, f32), f32> = load(ctx, GOLDEN_EMITTER_PDF)?;
    for case in &golden.cases {
        let c = &case.input;
        compare_f32(
            &call(c),
            s.emitter_pdf(c.0.triangle, c.0.position, c.1, c.2),
            case.expected,
            0.0,
            2e-3,
        )?;
    }
    Ok(())
}

/// Inputs of Exercise 12.5: a case and the direction and distance to a point of its triangle.
pub fn emitter_pdf_input() -> impl Strategy<Value = (EmitterCase, Vec3, f32)> + Clone {
    (emitter_case(), 0.0f32..1.0, 0.0f32..1.0).prop_map(|(case, u, v)| {
        let [a, b, c] = case.triangle;
        let r = u.sqrt();
        let point = a * (1.0 - r) + b * (r * (1.0 - v)) + c * (r * v);
        let to = point - case.position;
        (case, to.normalize(), to.length())
    })
}

/// A density from 10⁻⁶ to 10¹⁵.
pub fn density() -> impl Strategy<Value = f32> + Clone {
    (1.0f32..10.0, -6i32..15).prop_map(|(m, e)| m * 10f32.powi(e))
}

/// Exercise 12.6: the two weights of a sample add up to one; one strategy alone has weight
/// one, a density of zero weight zero (also against zero); then the key's weights (where
/// present) and the golden cases'.
fn exercise_12_6(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
    for_all(CASES, (density(), density()), |(a, b)| {
        let (w, v) = (s.power_heuristic(a, b), s.power_heuristic(b, a));
        let sum_is_one = (w + v - 1.0).abs() <= 1e-5;
        if !sum_is_one || !(0.0..=1.0).contains(&w) {
            return Err(format!(
                "power_heuristic({a}, {b}) + power_heuristic({b}, {a}) = {w} + {v} = {}: the weights of the two strategies for one sample are in [0, 1] and add up to 1",
                w + v
            ));
        }
        Ok(())
    })?;
    for (a, b, expected) in [
        (2.0, 0.0, 1.0),
        (0.0, 3.0, 0.0),
        (0.0, 0.0, 0.0),
        (5.0, 5.0, 0.5),
    ] {
        let got = s.power_heuristic(a, b);
        if got != expected {
            return Err(format!(
                "power_heuristic({a}, {b}) is {got}, expected {expected}{}",
                if a == 0.0 && b == 0.0 {
                    ": a sample no strategy can draw has weight 0, not 0/0"
                } else {
                    ""
                }
            ));
        }
    }
    if let Some(key) = key(ctx) {
        for_all(CASES, (density(), density()), |(a, b)| {
            compare_f32(
                &format!("power_heuristic({a}, {b})"),
                s.power_heuristic(a, b),
                key.power_heuristic(a, b),
                1e-7,
                1e-4,
            )
        })?;
    }
    let golden: GoldenFile<(f32, f32), f32> = load(ctx, GOLDEN_POWER_HEURISTIC)?;
    for case in &golden.cases {
        let (a, b) = case.input;
        compare_f32(
            &format!("power_heuristic({a}, {b})"),
            s.power_heuristic(a, b),
            case.expected,
            1e-7,
            1e-4,
        )?;
    }
    Ok(())
}

/// Exercise 12.7: for throughputs below, at and above one, unequal channels among them: the
/// path survives with probability `min(1, max channel)`, its factor is `1/q`, so the expected
/// factor is one; zero and NaN end the path; the generator advances.
fn exercise_12_7(s: &Arc<dyn PathTracing>, _ctx: &LabContext) -> Result<(), String> {
    let throughputs = [
        Vec3::new(0.05, 0.01, 0.02),
        Vec3::splat(0.3),
        Vec3::new(0.9, 0.1, 0.1),
        Vec3::new(0.2, 0.6, 0.4),
        Vec3::new(1.5, 0.2, 0.1),
        Vec3::new(1e-4, 1e-4, 1e-4),
    ];
    const TRIALS: usize = 20_000;
    let z_limit = family_z_limit(SIGNIFICANCE, throughputs.len());
    for (k, &t) in throughputs.iter().enumerate() {
        let q = t.max_element().min(1.0);
        let mut rng = Rng::new(700 + k as u64, 12);
        let mut survived = 0usize;
        for _ in 0..TRIALS {
            if let Some(factor) = s.roulette(t, &mut rng) {
                survived += 1;
                compare_f32(
                    &format!("the factor roulette(throughput = {t}) returned"),
                    factor,
                    1.0 / q,
                    0.0,
                    1e-5,
                )
                .map_err(|e| format!("{e} (1/q, q = min(1, max channel) = {q}): dividing by the probability of going on keeps the estimate unbiased"))?;
            }
        }
        let rate = survived as f64 / TRIALS as f64;
        let q = f64::from(q);
        let error = (q * (1.0 - q) / TRIALS as f64).sqrt().max(1e-9);
        if ((rate - q) / error).abs() > z_limit {
            return Err(format!(
                "roulette(throughput = {t}) let {survived} of {TRIALS} paths go on ({:.2} %); the probability is q = min(1, max channel) = {:.2} %",
                100.0 * rate,
                100.0 * q
            ));
        }
    }
    for t in [Vec3::ZERO, Vec3::NAN] {
        let mut rng = Rng::new(9, 9);
        for _ in 0..16 {
            if let Some(factor) = s.roulette(t, &mut rng) {
                return Err(format!(
                    "roulette(throughput = {t}) returned Some({factor}): a path that carries nothing (or not a number) ends"
                ));
            }
        }
    }
    let mut rng = Rng::new(11, 11);
    let t = Vec3::splat(0.5);
    let outcomes: Vec<_> = (0..32).map(|_| s.roulette(t, &mut rng)).collect();
    if outcomes.iter().all(|o| *o == outcomes[0]) {
        return Err(format!(
            "roulette(throughput = {t}) returned {:?} 32 times in a row: draw a new number from `rng` every call",
            outcomes[0]
        ));
    }
    Ok(())
}

/// Exercise 12.1's golden inputs, exposed for the generator.
pub fn luminance_inputs() -> Vec<Vec3> {
    grading::strategies::samples(colour(), 64, 12)
}

// ---------------------------------------------------------------------------------------------
// Exercise 12.8: the path estimator

/// A world made of closures for the path loop: every ray meets, at distance one, a surface
/// facing it that emits `emitted` and reflects diffusely with albedo `albedo` (a furnace), or,
/// with `sky`, leaves a scene of one bounce into a uniform sky. Its BSDF sampler is the uniform
/// hemisphere and its light sampler the uniform sphere: neither is the lab's, and a correct path
/// loop is right for any.
#[derive(Clone, Copy, Debug)]
pub struct Furnace {
    /// Diffuse albedo of every surface.
    pub albedo: f32,
    /// Emitted radiance of every surface.
    pub emitted: f32,
    /// Whether the light sampler draws anything (else it returns `None`).
    pub lights: bool,
    /// `Some(L)`: the camera ray meets one surface and every later ray a sky of radiance `L`.
    pub sky: Option<f32>,
    /// `Some(E)`: the light sampler draws only a delta light along [`SUN`], at distance one,
    /// that delivers the irradiance `E`.
    pub sun: Option<f32>,
    /// The path's bounces.
    pub max_depth: u32,
}

/// The direction towards the delta light of a furnace with a sun.
pub const SUN: Vec3 = Vec3::new(0.267_261_24, 0.534_522_5, 0.801_783_7);

impl Furnace {
    /// The expected radiance along a camera ray in `direction`: `E (1 + ρ + … + ρ^D)` in the
    /// furnace, `E + ρ L` under the sky; with a sun (depth 1) `E (1 + ρ)` and the sun's
    /// `ρ/π E_s cos θ` at the first vertex, whose normal faces the ray.
    pub fn expected(&self, direction: Vec3) -> f64 {
        let (rho, e) = (f64::from(self.albedo), f64::from(self.emitted));
        let sun = self.sun.map_or(0.0, |sun| {
            let cos = f64::from((-direction).dot(SUN).max(0.0));
            rho / std::f64::consts::PI * f64::from(sun) * cos
        });
        sun + match self.sky {
            Some(_) if self.max_depth == 0 => e,
            Some(l) => e + rho * f64::from(l),
            None => {
                e * (0..=self.max_depth)
                    .map(|k| rho.powi(k as i32))
                    .sum::<f64>()
            }
        }
    }
}

/// A uniform direction of the hemisphere about `n` from `rng`.
fn uniform_hemisphere(n: Vec3, rng: &mut Rng) -> Vec3 {
    let u = rng.next_vec2();
    let cos = u.x;
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = std::f32::consts::TAU * u.y;
    Onb::from_w(n)
        .to_world(Vec3::new(sin * phi.cos(), sin * phi.sin(), cos))
        .normalize()
}

/// What the path loop asked of a [`Furnace`]: problems with the rays it traced.
#[derive(Default)]
struct Asked {
    problems: Vec<String>,
}

/// One estimate of `s.path_radiance` in `world` along a ray from the origin along `direction`.
fn furnace_estimate(
    s: &dyn PathTracing,
    world: &Furnace,
    direction: Vec3,
    rng: &mut Rng,
    asked: &std::cell::RefCell<Asked>,
) -> Vec3 {
    use contracts::lab12::{PathHit, PathVertex};
    use contracts::math::Ray;
    let camera = Ray::unbounded(Vec3::ZERO, direction, 0.0);
    let material = PathMaterial {
        diffuse: Vec3::splat(world.albedo),
        glossy: Vec3::ZERO,
        exponent: 0.0,
    };
    let traced = std::cell::Cell::new(0u32);
    let vertex_at = |r: &Ray| PathVertex {
        position: r.origin + r.direction,
        normal: -r.direction,
        material,
        emitted: Vec3::splat(world.emitted),
        light_pdf: if world.lights {
            1.0 / (4.0 * std::f32::consts::PI)
        } else {
            0.0
        },
    };
    let trace = |r: &Ray| {
        let n = traced.get();
        traced.set(n + 1);
        let offset = r.tmin > 0.0;
        if n > 0 && !offset {
            asked.borrow_mut().problems.push(format!(
                "a ray after a bounce, {r:?}, has tmin = {}: start rays off a surface at RAY_EPSILON, or they find the surface they leave",
                r.tmin
            ));
        }
        match world.sky {
            Some(l) if n > 0 => PathHit::Escaped {
                radiance: Vec3::splat(l),
                light_pdf: 0.0,
            },
            _ => PathHit::Surface(vertex_at(r)),
        }
    };
    let occluded = |r: &Ray| {
        let ok = r.tmin > 0.0 && r.tmax < 1.0 && r.tmax >= 0.99;
        if !ok {
            asked.borrow_mut().problems.push(format!(
                "the shadow ray {r:?} to a point of a light at distance 1 should have tmin > 0 and tmax a little short of 1 (not past the light, where the light itself blocks it)"
            ));
        }
        false
    };
    let sample_light = |_p: Vec3, rng: &mut Rng| -> Option<EmitterSample> {
        if let Some(sun) = world.sun {
            return Some(EmitterSample {
                direction: SUN,
                distance: 1.0,
                radiance: Vec3::splat(sun),
                pdf: 1.0,
                delta: true,
            });
        }
        if !world.lights || world.sky.is_some() {
            return None;
        }
        let u = rng.next_vec2();
        let z = 1.0 - 2.0 * u.x;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = std::f32::consts::TAU * u.y;
        Some(EmitterSample {
            direction: Vec3::new(r * phi.cos(), r * phi.sin(), z),
            distance: 1.0,
            radiance: Vec3::splat(world.emitted),
            pdf: 1.0 / (4.0 * std::f32::consts::PI),
            delta: false,
        })
    };
    let lambert = world.albedo / std::f32::consts::PI;
    let uniform = 1.0 / std::f32::consts::TAU;
    let bsdf = |v: &PathVertex, wo: Vec3, wi: Vec3| {
        if v.normal.dot(wi) > 0.0 && v.normal.dot(wo) > 0.0 {
            BsdfValue {
                value: Vec3::splat(lambert),
                pdf: uniform,
            }
        } else {
            BsdfValue {
                value: Vec3::ZERO,
                pdf: 0.0,
            }
        }
    };
    let sample_bsdf = |v: &PathVertex, _wo: Vec3, rng: &mut Rng| {
        Some(BsdfSample {
            direction: uniform_hemisphere(v.normal, rng),
            value: Vec3::splat(lambert),
            pdf: uniform,
        })
    };
    // Weights of the two strategies and a roulette that are not the lab's (its 12.6 and 12.7
    // stay unanswered here): the balance heuristic, whose weights add up to one as well, and a
    // fixed probability of going on. A correct loop is unbiased with any.
    let power_heuristic = |a: f32, b: f32| if a > 0.0 { a / (a + b) } else { 0.0 };
    let roulette = |_t: Vec3, rng: &mut Rng| (rng.next_f32() < 0.75).then_some(1.0 / 0.75);
    s.path_radiance(
        &camera,
        world.max_depth,
        &trace,
        &occluded,
        &sample_light,
        &sample_bsdf,
        &bsdf,
        &power_heuristic,
        &roulette,
        rng,
    )
}

/// The furnaces of the check: emission at the first vertex alone, direct light by both
/// strategies, deep paths with roulette, each strategy alone, a black surface, a sky.
pub const FURNACES: [Furnace; 9] = [
    Furnace {
        albedo: 0.5,
        emitted: 1.0,
        lights: true,
        sky: None,
        sun: None,
        max_depth: 0,
    },
    Furnace {
        albedo: 0.5,
        emitted: 1.0,
        lights: true,
        sky: None,
        sun: None,
        max_depth: 1,
    },
    Furnace {
        albedo: 0.8,
        emitted: 2.0,
        lights: true,
        sky: None,
        sun: None,
        max_depth: 3,
    },
    Furnace {
        albedo: 0.8,
        emitted: 1.0,
        lights: true,
        sky: None,
        sun: None,
        max_depth: 40,
    },
    Furnace {
        albedo: 0.8,
        emitted: 1.0,
        lights: false,
        sky: None,
        sun: None,
        max_depth: 6,
    },
    Furnace {
        albedo: 0.0,
        emitted: 0.7,
        lights: true,
        sky: None,
        sun: None,
        max_depth: 5,
    },
    Furnace {
        albedo: 0.6,
        emitted: 0.0,
        lights: false,
        sky: Some(1.5),
        sun: None,
        max_depth: 4,
    },
    Furnace {
        albedo: 0.6,
        emitted: 0.25,
        lights: false,
        sky: Some(2.0),
        sun: None,
        max_depth: 0,
    },
    Furnace {
        albedo: 0.7,
        emitted: 0.0,
        lights: false,
        sky: None,
        sun: Some(3.0),
        max_depth: 1,
    },
];

/// Paths per furnace.
const FURNACE_PATHS: usize = 6_000;

/// Exercise 12.8: in furnaces scripted by closures the mean of the estimates is
/// `E (1 + ρ + … + ρ^D)` (every path of length up to `D` counted once, whichever strategy found
/// it), under a sky `E + ρ L`; rays after a bounce and shadow rays are offset; the generator is
/// the only randomness; then the Cornell box by the student's loop against the reference's
/// renders, pixel by pixel.
fn exercise_12_8(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
    let z_limit = family_z_limit(SIGNIFICANCE, FURNACES.len());
    let directions = grading::strategies::samples(unit_vector(), 16, 81);
    for (k, world) in FURNACES.iter().enumerate() {
        let asked = std::cell::RefCell::new(Asked::default());
        let mut rng = Rng::new(800 + k as u64, 12);
        let mut values = Vec::with_capacity(FURNACE_PATHS);
        for i in 0..FURNACE_PATHS {
            let d = directions[i % directions.len()];
            let l = furnace_estimate(s.as_ref(), world, d, &mut rng, &asked);
            if !l.is_finite() {
                return Err(format!(
                    "path_radiance in the furnace {world:?} returned {l}: a path's radiance is finite"
                ));
            }
            // What the path brought beyond its expectation: zero on average, and exactly
            // zero where nothing is random (the delta light's direct light).
            values.push(f64::from(l.x) - world.expected(d));
            if let Some(problem) = asked.borrow().problems.first() {
                return Err(format!("path_radiance in the furnace {world:?}: {problem}"));
            }
        }
        let (residual, error) = mean_and_standard_error(&values, FURNACE_PATHS);
        let expected =
            directions.iter().map(|&d| world.expected(d)).sum::<f64>() / directions.len() as f64;
        let mean = expected + residual;
        if residual.abs() > z_limit * error + 1e-4 * expected.max(1.0) {
            let what = match world.sky {
                Some(l) => format!(
                    "a surface of albedo {} emitting {} under a sky of radiance {l}",
                    world.albedo, world.emitted
                ),
                None => format!(
                    "a furnace whose every surface has albedo {} and emits {}{}",
                    world.albedo,
                    world.emitted,
                    world.sun.map_or(String::new(), |e| format!(
                        ", lit by a delta light of irradiance {e} (weight one: no BSDF sample finds it)"
                    ))
                ),
            };
            return Err(format!(
                "path_radiance in {what}, at most {} bounces{}: the mean of {FURNACE_PATHS} paths is {mean:.4} ± {error:.4}, expected {expected:.4} (E·(1 + ρ + … + ρ^D), each light path counted once: emission found by a bounce weighted by power_heuristic(bsdf pdf, light_pdf), next-event estimation by power_heuristic(light pdf, bsdf pdf), the first vertex's emission in full)",
                world.max_depth,
                if world.lights {
                    ", lights sampled"
                } else {
                    ", no light sampling"
                },
            ));
        }
    }
    // The generator is the only randomness, and it advances.
    let world = FURNACES[3];
    let asked = std::cell::RefCell::new(Asked::default());
    let mut rng = Rng::new(5, 5);
    let mut twin = rng.clone();
    let a = furnace_estimate(s.as_ref(), &world, Vec3::Y, &mut rng, &asked);
    let b = furnace_estimate(s.as_ref(), &world, Vec3::Y, &mut twin, &asked);
    let c = furnace_estimate(s.as_ref(), &world, Vec3::Y, &mut rng, &asked);
    if a != b {
        return Err(format!(
            "path_radiance returned {a} and then {b} from generators in the same state: draw every random number from `rng`, passed on to the closures"
        ));
    }
    if a == c {
        return Err(format!(
            "path_radiance returned {a} twice in a row in a furnace of depth {}: pass `rng` to the closures that draw, so that it advances",
            world.max_depth
        ));
    }
    crate::sky::check_sky_furnace(s, ctx)?;
    check_cornell(s, ctx)
}

/// The pixels and samples of each render of the Cornell box check.
pub const CORNELL_SETTINGS: RenderSettings = RenderSettings {
    width: 32,
    height: 32,
    samples_per_pixel: 8,
    pixel_subdivisions: 1,
    seed: 0,
    progress: false,
};
/// The bounces of the Cornell box check.
pub const CORNELL_DEPTH: u32 = 4;
/// Seeds of the reference's renders, whose mean and variance `raylab golden` stores.
pub const REFERENCE_SEEDS: std::ops::Range<u64> = 1000..1064;
/// Seeds of the student's renders (disjoint from [`REFERENCE_SEEDS`]).
pub const STUDENT_SEEDS: std::ops::Range<u64> = 5000..5004;
/// The Monte Carlo snapshot of the Cornell box: the per-pixel mean and variance (one
/// render's) of the reference's renders, `cornell-mean.exr` and `cornell-variance.exr`.
pub const SNAPSHOT_CORNELL: &str = "cornell";
/// The tolerance of the Cornell box check: Šidák over the pixels, a few outliers allowed.
pub const CORNELL_TOLERANCE: NoiseTolerance = NoiseTolerance {
    family_alpha: 1e-3,
    abs: 1e-4,
    rel: 1e-3,
    max_outlier_fraction: 0.005,
};

/// The pipeline of the Cornell box check: `code` for the path loop, the base for the rest.
pub fn cornell_pipeline(code: &Arc<dyn PathTracing>, base: &Pipeline) -> Result<Pipeline, String> {
    let base_code = base
        .part::<dyn PathTracing>()
        .ok_or("the base pipeline holds no code of lab 12")?;
    let slot: Arc<dyn PathTracing> = PartSlot::shared("path_radiance", code, &base_code);
    let mut pipeline = base.clone().with_part::<dyn PathTracing>(slot);
    pipeline.view = View::Shaded;
    pipeline.max_depth = CORNELL_DEPTH;
    Ok(pipeline)
}

/// Per-pixel mean and variance of renders of the Cornell box with the given seeds.
pub fn cornell_statistics(
    pipeline: &Pipeline,
    seeds: std::ops::Range<u64>,
) -> Result<RenderStatistics, raylab_core::Error> {
    let scene = raylab_core::scene::builtin_scene("cornell-ceiling")?;
    let films = seeds
        .map(|seed| {
            render(
                &scene,
                pipeline,
                &RenderSettings {
                    seed,
                    ..CORNELL_SETTINGS
                },
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(RenderStatistics::of(&films))
}

/// Samples per pixel of the renders of the convergence-rate check: 1, 4 and 16 times the
/// reference's.
const RATE_SPP: [u32; 3] = [8, 32, 128];
/// Where a squared Z-score is clipped in the mean of [`check_convergence_rate`], so that the
/// rare bright path of a correct render (a firefly) does not dominate it.
const RATE_CLIP: f64 = 16.0;
/// The range the mean of the clipped squared Z-scores at 32 and 128 samples per pixel must
/// keep relative to its value at 8.
const RATE_RANGE: (f64, f64) = (0.6, 1.9);

/// The error of the student's loop in the Cornell box falls as `1/√N`. At 8, 32 and 128 samples
/// per pixel, the squared difference from the reference's mean is scaled by the variance the
/// reference predicts for it, `s² (8/N + 1/K)` (`s²` of an 8-sample render, `K` renders in the
/// reference's mean), clipped at [`RATE_CLIP`] and averaged over the pixels. For an unbiased
/// loop whose samples are independent this mean stays about the same as N grows (about one, or
/// the ratio of its variance to the reference's for a correct loop that is noisier or less
/// noisy): relative to 8 samples it must stay in [`RATE_RANGE`]. Samples that are not
/// independent leave the error of 8 samples at 128 (the mean grows 13-fold); a bias hidden in
/// the noise of 8 samples shows at 128.
fn check_convergence_rate(
    pipeline: &Pipeline,
    reference: &RenderStatistics,
    seed: u64,
) -> Result<(), String> {
    let scene = raylab_core::scene::builtin_scene("cornell-ceiling").map_err(|e| e.to_string())?;
    convergence_rate(reference, &|spp, k| {
        render(
            &scene,
            pipeline,
            &RenderSettings {
                samples_per_pixel: spp,
                seed: seed + k,
                ..CORNELL_SETTINGS
            },
        )
        .map_err(|e| e.to_string())
    })
}

/// [`check_convergence_rate`] of the images `render(spp, k)` makes (the `k`th render, at `spp`
/// samples per pixel).
pub fn convergence_rate(
    reference: &RenderStatistics,
    render: &dyn Fn(u32, u64) -> Result<Film, String>,
) -> Result<(), String> {
    let base_spp = f64::from(CORNELL_SETTINGS.samples_per_pixel);
    let mut means: Vec<f64> = Vec::new();
    for (k, spp) in RATE_SPP.into_iter().enumerate() {
        let film = render(spp, k as u64)?;
        let share = base_spp / f64::from(spp) + 1.0 / f64::from(reference.renders);
        let mut scores = Vec::new();
        for ((x, mu), s2) in film
            .pixels
            .iter()
            .zip(&reference.mean.pixels)
            .zip(&reference.variance.pixels)
        {
            for c in 0..3 {
                let variance = f64::from(s2[c]) * share;
                if variance > 1e-12 {
                    let d = f64::from(x[c]) - f64::from(mu[c]);
                    let score = d * d / variance;
                    scores.push(if score.is_nan() {
                        RATE_CLIP
                    } else {
                        score.min(RATE_CLIP)
                    });
                }
            }
        }
        means.push(scores.iter().sum::<f64>() / scores.len().max(1) as f64);
        let ratio = means[k] / means[0].max(1e-12);
        if !(RATE_RANGE.0..=RATE_RANGE.1).contains(&ratio) {
            let listed: Vec<String> = RATE_SPP
                .iter()
                .zip(&means)
                .map(|(n, m)| format!("{m:.2} at {n}"))
                .collect();
            return Err(format!(
                "the error of the Cornell box path traced with your loop does not fall as 1/√N: its squared difference from the reference's mean, over the variance the reference predicts for N samples per pixel, is {} (clipped at {RATE_CLIP}; it stays about the same for independent, unbiased samples): {}",
                listed.join(", "),
                if ratio > RATE_RANGE.1 {
                    "at more samples the error is larger than independent samples leave — each sample of a pixel must be an independent path (draw from `rng`, passed on to the closures), and the estimate unbiased"
                } else {
                    "at more samples the error falls faster than independent samples can make it fall"
                }
            ));
        }
    }
    Ok(())
}

/// The Cornell box lit by its ceiling, path traced by the student's loop with the reference's
/// parts, against the mean and variance of the reference's renders by a per-pixel Z-test; then
/// its error at more samples ([`check_convergence_rate`]).
fn check_cornell(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
    let pipeline = cornell_pipeline(s, &ctx.base)?;
    let reference = ctx.noisy_reference(
        SNAPSHOT_CORNELL,
        (REFERENCE_SEEDS.end - REFERENCE_SEEDS.start) as u32,
    )?;
    let student = cornell_statistics(&pipeline, STUDENT_SEEDS).map_err(|e| e.to_string())?;
    ctx.check_noisy_snapshot(
        SNAPSHOT_CORNELL,
        &student,
        (REFERENCE_SEEDS.end - REFERENCE_SEEDS.start) as u32,
        &CORNELL_TOLERANCE,
        &format!(
            "the Cornell box path traced with your loop ({}×{} pixels, {} samples, {CORNELL_DEPTH} bounces)",
            CORNELL_SETTINGS.width, CORNELL_SETTINGS.height, CORNELL_SETTINGS.samples_per_pixel
        ),
    )?;
    check_convergence_rate(&pipeline, &reference, STUDENT_SEEDS.end)
}

// ---------------------------------------------------------------------------------------------
// Exercises 12.9 and 12.10: progressive accumulation

/// Golden file of Exercise 12.10.
pub const GOLDEN_RELATIVE_ERROR: &str = "relative_error.json";

/// A stream of estimates of one pixel: `n` values about `level` (per channel, from 10⁻⁴ to
/// 10⁴) spread by `spread` of it, with one channel black.
pub fn estimates() -> impl Strategy<Value = (u32, f32, f32, u64)> + Clone {
    (
        1u32..400,
        prop::sample::select(vec![1e-4f32, 1e-2, 1.0, 1e2, 1e4]),
        prop::sample::select(vec![1e-6f32, 1e-3, 0.3, 2.0]),
        any::<u64>(),
    )
}

/// The values of an [`estimates`] stream.
fn stream((n, level, spread, seed): (u32, f32, f32, u64)) -> Vec<Vec3> {
    let mut rng = Rng::new(seed, 9);
    (0..n)
        .map(|_| {
            let x = level * (1.0 + spread * (rng.next_f32() - 0.5));
            let y = level * 0.5 * (1.0 + spread * (rng.next_f32() - 0.5));
            Vec3::new(x, y, 0.0)
        })
        .collect()
}

/// Exercise 12.9: over streams of 1 to 400 estimates at levels from 10⁻⁴ to 10⁴ (and spreads
/// down to 10⁻⁶ of the level, where a sum of squares loses every digit), the count, the mean
/// and `m2` against a two-pass computation in double precision; a black channel stays 0.
fn exercise_12_9(s: &Arc<dyn PathTracing>, _ctx: &LabContext) -> Result<(), String> {
    use contracts::lab12::PixelStatistics;
    for_all(CASES, estimates(), |input| {
        let values = stream(input);
        let mut stats = PixelStatistics::default();
        for &v in &values {
            stats = s.accumulate(&stats, v);
        }
        let n = values.len();
        let what = format!(
            "after accumulating {n} estimates around {} (spread {} of it)",
            input.1, input.2
        );
        if stats.count as usize != n {
            return Err(format!(
                "{what} the count is {}: add one per estimate",
                stats.count
            ));
        }
        for c in 0..3 {
            let xs: Vec<f64> = values.iter().map(|v| f64::from(v[c])).collect();
            let mean = xs.iter().sum::<f64>() / n as f64;
            let m2: f64 = xs.iter().map(|x| (x - mean) * (x - mean)).sum();
            let channel = ["red", "green", "blue"][c];
            let mean_ok = (f64::from(stats.mean[c]) - mean).abs() <= 1e-5 * mean.abs() + 1e-30;
            if !mean_ok {
                return Err(format!(
                    "{what} the {channel} mean is {}, expected {mean}",
                    stats.mean[c]
                ));
            }
            // m2 to 1 % of itself, or of the rounding floor of the values (ε² n mean²).
            let floor = 1e-12 * n as f64 * mean * mean;
            let m2_ok = (f64::from(stats.m2[c]) - m2).abs() <= 1e-2 * m2 + floor;
            if !m2_ok {
                return Err(format!(
                    "{what} the {channel} m2 (Σ (x − mean)²) is {}, expected {m2}: Welford's update keeps the digits that a sum of squares minus the square of the sum loses",
                    stats.m2[c]
                ));
            }
        }
        Ok(())
    })
}

/// Inputs of Exercise 12.10: statistics of streams, and the edge cases.
pub fn relative_error_inputs() -> Vec<contracts::lab12::PixelStatistics> {
    use contracts::lab12::PixelStatistics;
    let mut inputs = vec![
        PixelStatistics::default(),
        PixelStatistics {
            count: 1,
            mean: Vec3::new(0.5, 0.2, 0.1),
            m2: Vec3::ZERO,
        },
        PixelStatistics {
            count: 10,
            mean: Vec3::ZERO,
            m2: Vec3::ZERO,
        },
        PixelStatistics {
            count: 4,
            mean: Vec3::new(2.0, 1.0, 0.0),
            m2: Vec3::new(3.0, 12.0, 0.0),
        },
    ];
    let streams = grading::strategies::samples(estimates(), 60, 101);
    for input in streams {
        let mut stats = PixelStatistics::default();
        for v in stream(input) {
            let count = stats.count + 1;
            let delta = v - stats.mean;
            let mean = stats.mean + delta / count as f32;
            stats = PixelStatistics {
                count,
                mean,
                m2: stats.m2 + delta * (v - mean),
            };
        }
        inputs.push(stats);
    }
    inputs
}

/// Exercise 12.10: infinite below two estimates; 0 for a black pixel; the largest channel's
/// `√(m2/(n − 1)/n)/mean`, so that four estimates of means (2, 1, 0) and m2 (3, 12, 0) give 2;
/// the key's values (where present) and the golden cases'.
fn exercise_12_10(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
    let inputs = relative_error_inputs();
    let call = |st: &contracts::lab12::PixelStatistics| format!("relative_error({st:?})");
    for (st, expected) in [(&inputs[0], f32::INFINITY), (&inputs[1], f32::INFINITY)] {
        let got = s.relative_error(st);
        if got != expected {
            return Err(format!(
                "{} is {got}: with fewer than two estimates there is no variance, so the error is unknown: return f32::INFINITY",
                call(st)
            ));
        }
    }
    let got = s.relative_error(&inputs[2]);
    if got != 0.0 {
        return Err(format!(
            "{} is {got}: a black pixel that never varied has converged (0), not 0/0",
            call(&inputs[2])
        ));
    }
    // Red: √(3/3/4)/2 = 0.25, green: √(12/3/4)/1 = 1, blue: black.
    compare_f32(
        &call(&inputs[3]),
        s.relative_error(&inputs[3]),
        1.0,
        0.0,
        1e-5,
    )
    .map_err(|e| {
        format!(
            "{e}: the largest channel's √(s²/n)/mean with s² = m2/(n − 1) (green: √(12/3/4)/1 = 1)"
        )
    })?;
    if let Some(key) = key(ctx) {
        for st in &inputs[4..] {
            compare_f32(
                &call(st),
                s.relative_error(st),
                key.relative_error(st),
                0.0,
                1e-4,
            )?;
        }
    }
    let golden: GoldenFile<contracts::lab12::PixelStatistics, f32> =
        load(ctx, GOLDEN_RELATIVE_ERROR)?;
    for case in &golden.cases {
        compare_f32(
            &call(&case.input),
            s.relative_error(&case.input),
            case.expected,
            0.0,
            1e-4,
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A normal deviate (Box–Muller).
    fn normal(rng: &mut Rng) -> f32 {
        let u = rng.next_vec2();
        (-2.0 * (1.0 - u.x).ln()).sqrt() * (std::f32::consts::TAU * u.y).cos()
    }

    /// A 32 × 32 truth, its reference of 64 renders (the mean with its own noise, the variance
    /// of one 8-sample render), and renders of it at N samples with the noise of `noise_spp(N)`
    /// samples and a bias of `bias` standard deviations of a 128-sample render.
    fn setup(noise_spp: fn(u32) -> u32, bias: f32) -> Result<(), String> {
        let mut rng = Rng::new(4, 4);
        let n = 32 * 32;
        let truth: Vec<Vec3> = (0..n)
            .map(|i| Vec3::new(0.1 + (i % 7) as f32, 0.5, 2.0 + (i % 3) as f32))
            .collect();
        let variance: Vec<Vec3> = truth.iter().map(|t| *t * 0.3).collect();
        let noisy = |rng: &mut Rng, share: f32, shift: f32| {
            let mut film = Film::new(32, 32);
            for ((p, t), v) in film.pixels.iter_mut().zip(&truth).zip(&variance) {
                let sd = (*v * share).powf(0.5);
                let deviate = Vec3::new(normal(rng), normal(rng), normal(rng));
                *p = *t + sd * deviate + shift * (*v / 16.0).powf(0.5);
            }
            film
        };
        let mut mean = noisy(&mut rng, 1.0 / 64.0, 0.0);
        mean.pixels.iter_mut().for_each(|p| *p = p.max(Vec3::ZERO));
        let mut var = Film::new(32, 32);
        var.pixels.copy_from_slice(&variance);
        let reference = RenderStatistics {
            renders: 64,
            mean,
            variance: var,
        };
        let rng = std::cell::RefCell::new(rng);
        convergence_rate(&reference, &|spp, _| {
            let share = 8.0 / noise_spp(spp) as f32;
            Ok(noisy(&mut rng.borrow_mut(), share, bias))
        })
    }

    #[test]
    fn the_convergence_rate_check_tells_independent_samples_from_others() {
        setup(|n| n, 0.0).expect("independent, unbiased samples pass");
        // Correct alternatives with twice and half the reference's variance.
        setup(|n| n / 2, 0.0).expect("a noisier unbiased loop passes");
        setup(|n| 2 * n, 0.0).expect("a less noisy unbiased loop passes");
        let stuck = setup(|_| 8, 0.0).expect_err("an error that does not fall");
        assert!(stuck.contains("independent path"), "{stuck}");
        // A bias of 1.5 standard errors of a 128-sample render, hidden in the noise of 8.
        setup(|n| n, 1.5).expect_err("a bias that shows with more samples");
    }
}
