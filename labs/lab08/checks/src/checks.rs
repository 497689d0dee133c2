//! Lab 08's exercises and their checks.
//!
//! The emission exercises (8.1, 8.2) return a random direction and a power that does not
//! depend on it, so the power is compared exactly (up to rounding) and the direction by its
//! distribution only:
//!
//! - per call (300 property cases, positions up to 10³ units from the origin, lights from
//!   10⁻⁴ to 10³ units): the photon starts where it should, travels along a finite unit
//!   direction (8.2: into the hemisphere of the normal) on a ray valid from no more than
//!   [`RAY_EPSILON`] (8.2: from more than 0, so that it does not hit the light), and the
//!   generator has moved on; its power is finite, shared equally among the photons emitted
//!   (`N·Φ_p` does not depend on `N`), linear in the light's intensity (8.2: radiance and area)
//!   and, when the key is present, the key's; the golden cases (`golden/emit_*.json`) fix its
//!   scale without the key;
//! - over [`DIRECTIONS`] directions drawn one after another from one generator: 8.1's are
//!   uniform on the sphere (Pearson's χ² on 128 cells of equal solid angle, 8 bands of `z` by
//!   16 sectors of azimuth, and the mean direction 0); 8.2's are cosine-weighted about the
//!   normal (χ² on 16 bands of `cos²θ`, which is uniform for a cosine-weighted direction, on
//!   16 sectors of azimuth about the normal, and on the [`JOINT_BANDS`] × 16 cells of both
//!   together, the joint distribution), about five normals including the axes.
//!
//! Exercise 8.3 (`russian_roulette`): the power goes on unchanged; `R = 0` always refracts and
//! `R = 1` always reflects; for seven reflectances from 0.02 to 0.96 the share of reflections in
//! [`DECISIONS`] draws from one generator is `R` (a binomial z-score). Then whole photon traces
//! with the student's roulette and the base's emission: in a closed box of mirrors around a
//! glass sphere holding the light (every photon is stored after a specular bounce) the stored
//! power is the emitted power; and the caustic under the glass sphere of the Cornell box
//! (`cornell-spheres`) matches the reference's recorded one (`golden/glass_caustic.json`):
//! the photons stored in a disc under the sphere, in a ring around it and in all, each a
//! two-sample Poisson z-score.
//!
//! Exercise 8.4 (`caustic_radiance`): on random photon sets (500 cases, radii from 10⁻⁴ to 10³
//! units), the estimate is finite, zero without photons, linear in the reflectance, additive
//! over the photons, blind to photons arriving from behind the surface and falling as
//! `1/r²` with the maximum radius while fewer than `k` were found, and with `k` found the same
//! as for those photons found with the farthest one's distance as maximum radius; the key's
//! where present; zero where the disc has no area (the zero-radius rule: `k` photons at the
//! shading point, or a maximum radius of 0); and the golden cases
//! (`golden/caustic_radiance.json`). Then the density
//! estimate itself: a plane lit by a point light, every photon stored where it first lands
//! (not only after a specular bounce), gives at 25 points the radiance the base's lab 02 code
//! shades there from the light (its irradiance), and with the radius shrinking as the photons grow the error
//! falls (the estimate is consistent).
//!
//! Each statistic is a z-score (the χ² through the Wilson–Hilferty transform) compared with
//! the two-sided normal quantile at the Šidák-corrected level [`FAMILY_ALPHA`] over the tests
//! of its exercise; the generators are fixed, so the outcome is deterministic on any number of
//! threads.

use std::f32::consts::PI;
use std::sync::Arc;

use glam::{DVec3, Vec3};
use proptest::prelude::*;

use contracts::lab08::{EmittedPhoton, NearbyPhoton, PhotonMapping, Scatter};
use grading::stats::{chi_square_uniform_z, family_z_limit};
use grading::strategies::{point, scale, unit_vector};
use grading::{Exercise, GoldenFile, LabContext, compare_vec3, for_all};
use pipeline::photon::{PhotonSettings, PhotonTrace, StoreRule, trace_photons};
use pipeline::{Pipeline, View};
use raylab_core::math::{Onb, RAY_EPSILON};
use raylab_core::sampling::Rng;
use raylab_core::scene::{Light, PointLight, Scene, builtin_scene, parse_scene_str};

/// Golden file of Exercise 8.1: position, intensity, photons emitted → power.
pub const GOLDEN_POINT: &str = "emit_point_light.json";
/// Golden file of Exercise 8.2: position, normal, radiance, area, photons emitted → power.
pub const GOLDEN_AREA: &str = "emit_area_light.json";
/// Golden file of Exercise 8.4: the estimate's inputs → the radiance.
pub const GOLDEN_RADIANCE: &str = "caustic_radiance.json";
/// Golden file of Exercise 8.3: the reference's photon counts of the glass sphere's caustic.
pub const GOLDEN_CAUSTIC: &str = "glass_caustic.json";

/// Chance that a correct implementation fails any statistical test of one exercise, had the
/// generators been random.
pub const FAMILY_ALPHA: f64 = 1e-4;
/// Directions drawn for the distribution checks of Exercises 8.1 and 8.2.
pub const DIRECTIONS: usize = 32_768;
/// Bands of `cos²θ` of Exercise 8.2's joint test, by 16 sectors of azimuth.
pub const JOINT_BANDS: usize = 8;
/// Roulette decisions drawn per reflectance in Exercise 8.3.
pub const DECISIONS: usize = 20_000;
/// The reflectances whose roulette frequencies Exercise 8.3 checks.
pub const REFLECTANCES: [f32; 7] = [0.02, 0.04, 0.1, 0.3, 0.5, 0.7, 0.96];
/// Relative tolerance of powers and radiances against the key, golden cases and exact
/// relations: rounding of another order of the same operations.
pub const REL_TOL: f32 = 2e-5;

/// Photons traced for the glass sphere's caustic (Exercise 8.3).
pub const CAUSTIC_PHOTONS: u32 = 100_000;
/// Seed of the student's caustic trace (the golden data's is [`CAUSTIC_GOLDEN_SEED`]).
pub const CAUSTIC_SEED: u64 = 8;
/// Seed of the reference's recorded caustic.
pub const CAUSTIC_GOLDEN_SEED: u64 = 80;
/// Centre of the caustic under the glass sphere of `cornell-spheres`, on the floor: where
/// the line from the point light through the sphere's centre meets it.
pub const CAUSTIC_CENTRE: Vec3 = Vec3::new(0.146, 0.0, 0.170);
/// Radius of the disc of the caustic, and the outer radius of the ring around it.
pub const CAUSTIC_RADII: [f32; 2] = [0.03, 0.08];

/// Photons traced on the lit plane of Exercise 8.4's density check.
pub const PLANE_PHOTONS: u32 = 400_000;
/// The density check's `k` and maximum radius.
pub const PLANE_K: usize = 400;
/// The density check's maximum radius.
pub const PLANE_MAX_RADIUS: f32 = 0.5;
/// The consistency check: photons emitted and the (fixed) radius, from coarse to fine.
pub const CONSISTENCY_STEPS: [(u32, f32); 3] = [(25_000, 0.4), (100_000, 0.2), (400_000, 0.1)];

/// This lab.
pub const LAB: course::LabId = course::LabId::of(8);

/// The exercises of lab 08 (`labs/lab08/exercises.toml`), each with its check.
pub fn exercises() -> Vec<Exercise<dyn PhotonMapping>> {
    grading::exercises(
        LAB,
        grading::checks![exercise_8_1, exercise_8_2, exercise_8_3, exercise_8_4],
    )
}

// ---------------------------------------------------------------------------------------------
// Pipelines

/// Which student function a trace or render exercises; the others come from the base.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// Exercise 8.1.
    PointLight,
    /// Exercise 8.2.
    AreaLight,
    /// Exercise 8.3.
    Roulette,
    /// Exercise 8.4.
    Radiance,
}

impl Part {
    /// The contract method whose code this part is (the student's in a [`PartSlot`](pipeline::PartSlot)).
    pub fn function(self) -> &'static str {
        match self {
            Part::PointLight => "emit_point_light",
            Part::AreaLight => "emit_area_light",
            Part::Roulette => "russian_roulette",
            Part::Radiance => "caustic_radiance",
        }
    }
}

/// The pipeline of one part's traces: `student` for that part only, `base` for the rest, at
/// lab 8.
pub fn part_pipeline(part: Part, student: &Arc<dyn PhotonMapping>, base: &Pipeline) -> Pipeline {
    let mut pipeline = base.with_student_function(part.function(), student);
    pipeline.view = View::Shaded;
    pipeline
}

/// The largest |z| of a statistic when an exercise makes `tests` statistical tests.
pub fn z_limit(tests: usize) -> f64 {
    family_z_limit(FAMILY_ALPHA, tests)
}

/// Whether the next number of `rng` differs from that of `before` (a copy taken before a
/// call): the call drew from `rng`.
fn advanced(rng: &Rng, before: &Rng) -> bool {
    rng.clone().next_u32() != before.clone().next_u32()
}

fn close(a: Vec3, b: Vec3) -> bool {
    let scale = a.abs().max(b.abs()).max_element();
    (a - b).abs().max_element() <= REL_TOL * scale + f32::MIN_POSITIVE
}

/// The checks of an emitted photon's ray common to both lights.
fn check_ray(
    call: &str,
    photon: &EmittedPhoton,
    origin: Vec3,
    min_tmin: bool,
) -> Result<(), String> {
    let ray = &photon.ray;
    if !(ray.origin.is_finite() && ray.direction.is_finite() && photon.power.is_finite()) {
        return Err(format!("{call} = {photon:?} is not finite"));
    }
    let tol = 1e-6 * origin.abs().max_element().max(1.0);
    if (ray.origin - origin).abs().max_element() > tol {
        return Err(format!(
            "{call}: the photon starts at {}, expected the point of emission {origin}",
            ray.origin
        ));
    }
    if (ray.direction.length() - 1.0).abs() > 1e-4 {
        return Err(format!(
            "{call}: the direction {} has length {}, expected a unit vector (normalise it)",
            ray.direction,
            ray.direction.length()
        ));
    }
    if !(ray.tmin >= 0.0 && ray.tmin <= RAY_EPSILON) || (min_tmin && ray.tmin <= 0.0) {
        let expected = if min_tmin {
            "in (0, RAY_EPSILON]: it starts on the light's surface"
        } else {
            "in [0, RAY_EPSILON]"
        };
        return Err(format!("{call}: tmin = {}, expected {expected}", ray.tmin));
    }
    if ray.tmax < 1e30 {
        return Err(format!(
            "{call}: tmax = {}, expected an unbounded ray",
            ray.tmax
        ));
    }
    if photon.power.min_element() < 0.0 {
        return Err(format!("{call}: negative power {}", photon.power));
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Exercise 8.1

/// Input of Exercise 8.1: light position, intensity, photons emitted.
pub type PointInput = (Vec3, Vec3, u32);

/// Inputs of Exercise 8.1 over every scale.
pub fn point_input() -> impl Strategy<Value = PointInput> + Clone {
    (
        point(1.0),
        scale(),
        (0.0f32..100.0, 0.0f32..100.0, 0.0f32..100.0),
        1u32..1_000_000,
    )
        .prop_map(|(p, s, (r, g, b), n)| (p * s, Vec3::new(r, g, b), n))
}

fn point_light(position: Vec3, intensity: Vec3) -> PointLight {
    PointLight {
        position,
        intensity,
    }
}

fn exercise_8_1(s: &Arc<dyn PhotonMapping>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab08::PhotonMapping>());
    for_all(
        300,
        (point_input(), any::<u64>()),
        |((position, intensity, n), seed)| {
            let light = point_light(position, intensity);
            let call = format!("emit_point_light({light:?}, emitted = {n}, rng)");
            let mut rng = Rng::new(seed, 1);
            let before = rng.clone();
            let photon = s.emit_point_light(&light, n, &mut rng);
            check_ray(&call, &photon, position, false)?;
            if !advanced(&rng, &before) {
                return Err(format!(
                    "{call}: the generator passed in did not move on; draw the direction's numbers from it"
                ));
            }
            let again = s.emit_point_light(&light, n, &mut Rng::new(seed ^ 0x5555, 2));
            if !close(again.power, photon.power) {
                return Err(format!(
                    "{call}: the power {} changes with the direction drawn (another gives {}); every photon carries the same share",
                    photon.power, again.power
                ));
            }
            let n2 = if n > 1 { n / 2 } else { 7 };
            let other = s.emit_point_light(&light, n2, &mut Rng::new(seed, 3));
            if !close(photon.power * n as f32, other.power * n2 as f32) {
                return Err(format!(
                    "{call}: power {} but {} with emitted = {n2}: the light's power must be shared equally among the photons emitted (N·Φ_p the same for every N)",
                    photon.power, other.power
                ));
            }
            let doubled = s.emit_point_light(
                &point_light(position, 2.0 * intensity),
                n,
                &mut Rng::new(seed, 4),
            );
            if !close(doubled.power, 2.0 * photon.power) {
                return Err(format!(
                    "{call}: power {} but {} for twice the intensity: the power is proportional to the intensity",
                    photon.power, doubled.power
                ));
            }
            if let Some(key) = &key {
                let expected = key
                    .emit_point_light(&light, n, &mut Rng::new(seed, 1))
                    .power;
                compare_vec3(
                    &format!("{call}: the photon's power"),
                    photon.power,
                    expected,
                    1e-30,
                    REL_TOL,
                )?;
            }
            Ok(())
        },
    )?;
    let golden: GoldenFile<PointInput, Vec3> = ctx.golden(GOLDEN_POINT)?;
    for case in &golden.cases {
        let (position, intensity, n) = case.input;
        let photon = s.emit_point_light(&point_light(position, intensity), n, &mut Rng::new(11, 0));
        compare_vec3(
            &format!(
                "emit_point_light(position {position}, intensity {intensity}, emitted = {n}): the power (recorded case)"
            ),
            photon.power,
            case.expected,
            1e-30,
            REL_TOL,
        )?;
    }
    // The distribution of the directions.
    let mut rng = Rng::new(81, 0);
    let light = point_light(Vec3::new(3.0, -2.0, 1.0), Vec3::ONE);
    let mut cells = vec![0u32; 8 * 16];
    let mut sum = DVec3::ZERO;
    for _ in 0..DIRECTIONS {
        let d = s
            .emit_point_light(&light, 1000, &mut rng)
            .ray
            .direction
            .normalize();
        let band = (((d.z + 1.0) * 4.0) as usize).min(7);
        let sector = ((((d.y.atan2(d.x) / (2.0 * PI)) + 0.5) * 16.0) as usize).min(15);
        cells[band * 16 + sector] += 1;
        sum += d.as_dvec3();
    }
    let z_max = z_limit(4);
    let (_, z) = chi_square_uniform_z(&cells);
    if z.abs() > z_max {
        return Err(format!(
            "the directions of {DIRECTIONS} photons drawn one after another are not uniform on the sphere: χ² on 128 cells of equal solid angle (8 bands of z, 16 sectors of azimuth) has z = {z:.1} (limit {z_max:.2}); cell counts from z = −1 up: {cells:?}"
        ));
    }
    let mean = sum / DIRECTIONS as f64;
    let sigma = (1.0 / (3.0 * DIRECTIONS as f64)).sqrt();
    for (axis, m) in ["x", "y", "z"].iter().zip(mean.to_array()) {
        if (m / sigma).abs() > z_max {
            return Err(format!(
                "the mean direction of {DIRECTIONS} photons has {axis} = {m:.4}, expected 0 (z = {:.1}, limit {z_max:.2}): the directions favour one side",
                m / sigma
            ));
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Exercise 8.2

/// Input of Exercise 8.2: position, normal, radiance, area, photons emitted.
pub type AreaInput = (Vec3, Vec3, Vec3, f32, u32);

/// Inputs of Exercise 8.2 over every scale.
pub fn area_input() -> impl Strategy<Value = AreaInput> + Clone {
    (
        point(1.0),
        scale(),
        prop_oneof![
            unit_vector(),
            prop::sample::select(vec![
                Vec3::X,
                Vec3::NEG_X,
                Vec3::Y,
                Vec3::NEG_Y,
                Vec3::Z,
                Vec3::NEG_Z
            ]),
        ],
        (0.0f32..50.0, 0.0f32..50.0, 0.0f32..50.0),
        0.01f32..1.0,
        1u32..1_000_000,
    )
        .prop_map(|(p, s, n, (r, g, b), a, count)| (p * s, n, Vec3::new(r, g, b), a * s * s, count))
}

fn exercise_8_2(s: &Arc<dyn PhotonMapping>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab08::PhotonMapping>());
    for_all(
        300,
        (area_input(), any::<u64>()),
        |((position, normal, radiance, area, n), seed)| {
            let call = format!(
                "emit_area_light(position {position}, normal {normal}, radiance {radiance}, area {area}, emitted = {n}, rng)"
            );
            let mut rng = Rng::new(seed, 1);
            let before = rng.clone();
            let photon = s.emit_area_light(position, normal, radiance, area, n, &mut rng);
            check_ray(&call, &photon, position, true)?;
            if photon.ray.direction.dot(normal) < -1e-6 {
                return Err(format!(
                    "{call}: the direction {} leaves the light's back (cos θ = {}); the light emits about its normal",
                    photon.ray.direction,
                    photon.ray.direction.dot(normal)
                ));
            }
            if !advanced(&rng, &before) {
                return Err(format!(
                    "{call}: the generator passed in did not move on; draw the direction's numbers from it"
                ));
            }
            let emit = |radiance: Vec3, area: f32, n: u32, stream: u64| {
                s.emit_area_light(
                    position,
                    normal,
                    radiance,
                    area,
                    n,
                    &mut Rng::new(seed, stream),
                )
                .power
            };
            let again = s
                .emit_area_light(
                    position,
                    normal,
                    radiance,
                    area,
                    n,
                    &mut Rng::new(seed ^ 0x5555, 2),
                )
                .power;
            if !close(again, photon.power) {
                return Err(format!(
                    "{call}: the power {} changes with the direction drawn (another gives {again}); every photon carries the same share",
                    photon.power
                ));
            }
            let n2 = if n > 1 { n / 2 } else { 7 };
            let other = emit(radiance, area, n2, 3);
            if !close(photon.power * n as f32, other * n2 as f32) {
                return Err(format!(
                    "{call}: power {} but {other} with emitted = {n2}: the light's power must be shared equally among the photons emitted",
                    photon.power
                ));
            }
            let doubled = emit(2.0 * radiance, area, n, 4);
            if !close(doubled, 2.0 * photon.power) {
                return Err(format!(
                    "{call}: power {} but {doubled} for twice the radiance: the power is proportional to the radiance",
                    photon.power
                ));
            }
            let larger = emit(radiance, 3.0 * area, n, 5);
            if !close(larger, 3.0 * photon.power) {
                return Err(format!(
                    "{call}: power {} but {larger} for three times the area: the power is proportional to the light's area",
                    photon.power
                ));
            }
            if let Some(key) = &key {
                let expected = key
                    .emit_area_light(position, normal, radiance, area, n, &mut Rng::new(seed, 1))
                    .power;
                compare_vec3(
                    &format!("{call}: the photon's power"),
                    photon.power,
                    expected,
                    1e-30,
                    REL_TOL,
                )?;
            }
            Ok(())
        },
    )?;
    let golden: GoldenFile<AreaInput, Vec3> = ctx.golden(GOLDEN_AREA)?;
    for case in &golden.cases {
        let (position, normal, radiance, area, n) = case.input;
        let photon = s.emit_area_light(position, normal, radiance, area, n, &mut Rng::new(11, 0));
        compare_vec3(
            &format!(
                "emit_area_light(position {position}, normal {normal}, radiance {radiance}, area {area}, emitted = {n}): the power (recorded case)"
            ),
            photon.power,
            case.expected,
            1e-30,
            REL_TOL,
        )?;
    }
    let normals = [
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
        Vec3::new(0.48, -0.6, 0.64),
    ];
    let z_max = z_limit(3 * normals.len());
    for (i, normal) in normals.into_iter().enumerate() {
        let mut rng = Rng::new(82, i as u64);
        let basis = Onb::from_w(normal);
        let (mut bands, mut sectors) = (vec![0u32; 16], vec![0u32; 16]);
        let mut cells = vec![0u32; JOINT_BANDS * 16];
        for _ in 0..DIRECTIONS {
            let d = s
                .emit_area_light(Vec3::ZERO, normal, Vec3::ONE, 1.0, 1000, &mut rng)
                .ray
                .direction
                .normalize();
            let local = basis.to_local(d);
            let cos2 = (local.z * local.z).clamp(0.0, 1.0);
            bands[((cos2 * 16.0) as usize).min(15)] += 1;
            let sector = ((((local.y.atan2(local.x) / (2.0 * PI)) + 0.5) * 16.0) as usize).min(15);
            sectors[sector] += 1;
            let band = ((cos2 * JOINT_BANDS as f32) as usize).min(JOINT_BANDS - 1);
            cells[band * 16 + sector] += 1;
        }
        let (_, z) = chi_square_uniform_z(&bands);
        if z.abs() > z_max {
            return Err(format!(
                "the directions of {DIRECTIONS} photons about the normal {normal} are not cosine-weighted: cos²θ of a cosine-weighted direction is uniform in [0, 1], but χ² on 16 bands of it has z = {z:.1} (limit {z_max:.2}); counts from cos²θ = 0 up: {bands:?}"
            ));
        }
        let (_, z) = chi_square_uniform_z(&sectors);
        if z.abs() > z_max {
            return Err(format!(
                "the directions of {DIRECTIONS} photons about the normal {normal} do not spread evenly around it: χ² on 16 sectors of azimuth has z = {z:.1} (limit {z_max:.2}); counts: {sectors:?}"
            ));
        }
        // Each alone can be right while the two go together (one number driving both).
        let (_, z) = chi_square_uniform_z(&cells);
        if z.abs() > z_max {
            let empty = cells.iter().filter(|&&c| c == 0).count();
            return Err(format!(
                "the directions of {DIRECTIONS} photons about the normal {normal} have cos²θ uniform and the azimuth even, each on its own, but not together: χ² on the {} cells of {JOINT_BANDS} bands of cos²θ by 16 sectors of azimuth, each of which a cosine-weighted direction falls in equally often, has z = {z:.1} (limit {z_max:.2}; {empty} cells empty). The polar angle and the azimuth must be independent: draw two numbers, ξ₁ for the disc's radius √ξ₁ and ξ₂ for the angle 2πξ₂, not one for both",
                cells.len()
            ));
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Exercise 8.3

/// A closed box of mirrors (six planes at ±1) around a glass sphere holding a point light,
/// with a diffuse sphere: every photon goes through the glass, and none leaves the box.
pub const MIRROR_BOX: &str = r#"
name = "mirror-box"
[camera]
eye = [0.0, 0.0, 0.9]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
focal_distance = 1.0
[materials.mirror]
illum = 3
specular = [1.0, 1.0, 1.0]
[materials.glass]
illum = 4
ior = 1.5
[materials.white]
diffuse = [0.8, 0.8, 0.8]
[[lights]]
type = "point"
position = [0.05, -0.03, 0.02]
intensity = [1.0, 2.0, 3.0]
[[planes]]
point = [1.0, 0.0, 0.0]
normal = [-1.0, 0.0, 0.0]
material = "mirror"
[[planes]]
point = [-1.0, 0.0, 0.0]
normal = [1.0, 0.0, 0.0]
material = "mirror"
[[planes]]
point = [0.0, 1.0, 0.0]
normal = [0.0, -1.0, 0.0]
material = "mirror"
[[planes]]
point = [0.0, -1.0, 0.0]
normal = [0.0, 1.0, 0.0]
material = "mirror"
[[planes]]
point = [0.0, 0.0, 1.0]
normal = [0.0, 0.0, -1.0]
material = "mirror"
[[planes]]
point = [0.0, 0.0, -1.0]
normal = [0.0, 0.0, 1.0]
material = "mirror"
[[spheres]]
center = [0.0, 0.0, 0.0]
radius = 0.3
material = "glass"
[[spheres]]
center = [0.5, 0.5, 0.5]
radius = 0.3
material = "white"
"#;

/// A scene of the checks from its text.
pub fn check_scene(name: &str, text: &str) -> Result<Scene, String> {
    parse_scene_str(name, text, std::path::Path::new(".")).map_err(|e| e.to_string())
}

/// The photon counts of a caustic trace: in the disc under the glass sphere, in the ring
/// around it, and in all.
pub fn caustic_counts(trace: &PhotonTrace) -> [u32; 3] {
    let mut counts = [0u32; 3];
    for p in trace.map.photons() {
        let d = (p.position - CAUSTIC_CENTRE).length();
        if p.position.y < 1e-3 && d < CAUSTIC_RADII[0] {
            counts[0] += 1;
        } else if p.position.y < 1e-3 && d < CAUSTIC_RADII[1] {
            counts[1] += 1;
        }
        counts[2] += 1;
    }
    counts
}

/// The caustic trace of `cornell-spheres` through `pipeline`.
pub fn glass_caustic(pipeline: &Pipeline, seed: u64) -> Result<PhotonTrace, String> {
    let scene = builtin_scene("cornell-spheres").map_err(|e| e.to_string())?;
    let settings = PhotonSettings {
        emitted: CAUSTIC_PHOTONS,
        seed,
        ..PhotonSettings::DEFAULT
    };
    Ok(trace_photons(
        pipeline,
        &scene,
        &settings,
        StoreRule::Caustic,
    ))
}

fn exercise_8_3(s: &Arc<dyn PhotonMapping>, ctx: &LabContext) -> Result<(), String> {
    for_all(
        300,
        (
            0.0f32..=1.0,
            (0.0f32..10.0, 0.0f32..10.0, 0.0f32..10.0),
            scale(),
            any::<u64>(),
        ),
        |(r, (a, b, c), sc, seed)| {
            let power = Vec3::new(a, b, c) * sc;
            let call = format!("russian_roulette(reflectance = {r}, power = {power}, rng)");
            let mut rng = Rng::new(seed, 1);
            let before = rng.clone();
            let (_, carried) = s.russian_roulette(r, power, &mut rng);
            if !close(carried, power) {
                return Err(format!(
                    "{call}: the photon carries {carried} on; Russian roulette keeps its power (the choice itself does the weighting by R)"
                ));
            }
            if !advanced(&rng, &before) {
                return Err(format!(
                    "{call}: the generator passed in did not move on; draw the roulette's number from it"
                ));
            }
            Ok(())
        },
    )?;
    let mut rng = Rng::new(83, 0);
    for (r, expected) in [(0.0, Scatter::Refract), (1.0, Scatter::Reflect)] {
        for _ in 0..200 {
            let (got, _) = s.russian_roulette(r, Vec3::ONE, &mut rng);
            if got != expected {
                return Err(format!(
                    "russian_roulette(reflectance = {r}) chose {got:?}; with R = {r} the photon is always {}",
                    if r == 0.0 { "refracted" } else { "reflected" }
                ));
            }
        }
    }
    let z_max = z_limit(REFLECTANCES.len() + 3);
    for (i, r) in REFLECTANCES.into_iter().enumerate() {
        let mut rng = Rng::new(84, i as u64);
        let reflected = (0..DECISIONS)
            .filter(|_| s.russian_roulette(r, Vec3::ONE, &mut rng).0 == Scatter::Reflect)
            .count();
        let p = r as f64;
        let z =
            (reflected as f64 - p * DECISIONS as f64) / (DECISIONS as f64 * p * (1.0 - p)).sqrt();
        if z.abs() > z_max {
            return Err(format!(
                "russian_roulette(reflectance = {r}) reflected {reflected} of {DECISIONS} photons drawn one after another ({:.4}), expected a share of R = {r} (z = {z:.1}, limit {z_max:.2})",
                reflected as f64 / DECISIONS as f64
            ));
        }
    }
    // Whole traces with the student's roulette.
    let pipeline = part_pipeline(Part::Roulette, s, &ctx.base);
    let scene = check_scene("mirror-box", MIRROR_BOX)?;
    let settings = PhotonSettings {
        emitted: 20_000,
        seed: 3,
        ..PhotonSettings::DEFAULT
    };
    let trace = trace_photons(&pipeline, &scene, &settings, StoreRule::Caustic);
    let lost = trace.emitted_power - trace.stored_power - trace.truncated_power;
    if lost.abs().max_element() > 1e-4 * trace.emitted_power.max_element()
        || trace.truncated_power.max_element() > 1e-2 * trace.emitted_power.max_element()
    {
        return Err(format!(
            "in a closed box of mirrors around a glass sphere holding the light, every photon ends on the diffuse sphere inside: stored power {} (+ {} dropped after the bounce limit), expected the emitted {}",
            trace.stored_power, trace.truncated_power, trace.emitted_power
        ));
    }
    let golden: GoldenFile<u64, [u32; 3]> = ctx.golden(GOLDEN_CAUSTIC)?;
    let expected = golden
        .cases
        .first()
        .ok_or("golden/glass_caustic.json holds no case")?
        .expected;
    let got = caustic_counts(&glass_caustic(&pipeline, CAUSTIC_SEED)?);
    let names = [
        "in the disc of the caustic under the glass sphere",
        "in the ring around it",
        "in all",
    ];
    for ((name, g), e) in names.iter().zip(got).zip(expected) {
        let z = (g as f64 - e as f64) / ((g + e) as f64).max(1.0).sqrt();
        if z.abs() > z_max {
            return Err(format!(
                "the caustic map of cornell-spheres ({CAUSTIC_PHOTONS} photons) holds {g} photons {name}, the reference's {e} (z = {z:.1}, limit {z_max:.2})"
            ));
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Exercise 8.4

/// Input of Exercise 8.4: diffuse reflectance, normal, photons, k, maximum radius.
pub type RadianceInput = (Vec3, Vec3, Vec<NearbyPhoton>, usize, f32);

/// Inputs of Exercise 8.4 over every scale: up to `k` photons sorted by distance (from a
/// hundredth of the maximum radius up), about half of the sets with exactly `k`, a few photons
/// from behind the surface.
pub fn radiance_input() -> impl Strategy<Value = RadianceInput> + Clone {
    (
        1usize..40,
        any::<bool>(),
        scale(),
        0.05f32..1.0,
        unit_vector(),
    )
        .prop_flat_map(|(k, full, sc, r, normal)| {
            let n = if full { k..k + 1 } else { 0..k };
            // Distances from a hundredth of the maximum radius up: the disc always has an
            // area here (the zero-radius rule has a check of its own).
            let photon = (
                0.01f32..1.0,
                0.0f32..1e-2,
                0.0f32..1e-2,
                0.0f32..1e-2,
                unit_vector(),
                0u8..10,
            );
            (
                (0.0f32..1.0, 0.0f32..1.0, 0.0f32..1.0),
                Just(normal),
                prop::collection::vec(photon, n),
                Just(k),
                Just(r * sc),
            )
        })
        .prop_map(|((dr, dg, db), normal, raw, k, max_radius)| {
            let mut photons: Vec<NearbyPhoton> = raw
                .into_iter()
                .map(|(u, a, b, c, d, behind)| {
                    // Most photons arrive from the front (against the normal).
                    let front = -(normal + 0.9 * d).normalize_or(normal);
                    let direction = if behind == 0 { -front } else { front };
                    let distance = u * max_radius;
                    NearbyPhoton {
                        power: Vec3::new(a, b, c),
                        direction,
                        distance_squared: distance * distance,
                    }
                })
                .collect();
            photons.sort_by(|a, b| a.distance_squared.total_cmp(&b.distance_squared));
            (Vec3::new(dr, dg, db), normal, photons, k, max_radius)
        })
}

/// The estimate where the disc has no area: `k` photons found all at the shading point, or a
/// maximum radius of 0 with fewer found. There is no density to estimate, and the rule
/// (docs/lab08.md, Exercise 8.4) is an estimate of zero.
fn check_zero_radius(s: &dyn PhotonMapping) -> Result<(), String> {
    let at_point = |n: usize| {
        (0..n)
            .map(|i| NearbyPhoton {
                power: Vec3::new(0.5, 1.0, 0.25) * (i + 1) as f32,
                direction: Vec3::new(0.3, -1.0, 0.1).normalize(),
                distance_squared: 0.0,
            })
            .collect::<Vec<_>>()
    };
    let cases = [
        (at_point(1), 1, 0.025, "the k = 1 photon found lies"),
        (at_point(3), 3, 0.025, "all k = 3 photons found lie"),
        (at_point(2), 5, 0.0, "2 photons lie"),
    ];
    for (photons, k, max_radius, which) in cases {
        let l = s.caustic_radiance(Vec3::splat(0.7), Vec3::Y, &photons, k, max_radius);
        if l != Vec3::ZERO {
            let disc = if photons.len() >= k {
                "the disc is the one that just holds the k photons, of radius 0"
            } else {
                "fewer than k were found, so the disc is the maximum radius's, 0"
            };
            return Err(format!(
                "caustic_radiance(diffuse [0.7, 0.7, 0.7], normal +y, {} photons, k = {k}, max_radius = {max_radius}) = {l}, where {which} exactly at the shading point (distance_squared 0): {disc}, and Σ Φ_p / (π r²) has no value. The rule for a disc of no area (r² = 0) is an estimate of zero: return zero rather than divide by r² = 0",
                photons.len()
            ));
        }
    }
    Ok(())
}

fn exercise_8_4(s: &Arc<dyn PhotonMapping>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab08::PhotonMapping>());
    let radiance = |(diffuse, normal, photons, k, r): &RadianceInput| {
        s.caustic_radiance(*diffuse, *normal, photons, *k, *r)
    };
    for_all(500, radiance_input(), |input| {
        let (diffuse, normal, photons, k, r) = &input;
        let (k, r) = (*k, *r);
        let call = format!(
            "caustic_radiance(diffuse {diffuse}, normal {normal}, {} photons, k = {k}, max_radius = {r})",
            photons.len()
        );
        let l = radiance(&input);
        if !l.is_finite() || l.min_element() < 0.0 {
            return Err(format!(
                "{call} = {l}: expected a finite, non-negative radiance"
            ));
        }
        if photons.is_empty() && l != Vec3::ZERO {
            return Err(format!("{call} = {l} without any photon"));
        }
        let doubled = s.caustic_radiance(2.0 * *diffuse, *normal, photons, k, r);
        if !close(doubled, 2.0 * l) {
            return Err(format!(
                "{call} = {l}, but {doubled} for twice the reflectance: the reflected radiance is proportional to it"
            ));
        }
        let front: Vec<NearbyPhoton> = photons
            .iter()
            .copied()
            .filter(|p| p.direction.dot(*normal) < 0.0)
            .collect();
        if photons.len() < k {
            let sum: Vec3 = photons
                .iter()
                .map(|p| s.caustic_radiance(*diffuse, *normal, std::slice::from_ref(p), k, r))
                .sum();
            if !close(sum, l) {
                return Err(format!(
                    "{call} = {l}, but the estimates of its photons one by one add up to {sum}: with fewer than k photons found, each adds its own power over the same disc (the estimate is the sum of the photons' power, not their mean)"
                ));
            }
            let only_front = s.caustic_radiance(*diffuse, *normal, &front, k, r);
            if !close(only_front, l) {
                return Err(format!(
                    "{call} = {l}, but {only_front} without the photons that arrived from behind the surface (travelling along the normal): those do not light this side"
                ));
            }
            let wider = s.caustic_radiance(*diffuse, *normal, photons, k, 2.0 * r);
            if !close(4.0 * wider, l) {
                return Err(format!(
                    "{call} = {l}, but {wider} with twice the maximum radius (the same photons, fewer than k): the photons' power is spread over the disc's area, so doubling its radius quarters the estimate"
                ));
            }
        } else if let Some(farthest) = photons.last() {
            let r_k = farthest.distance_squared.sqrt();
            if r_k > 0.0 {
                let wider = s.caustic_radiance(*diffuse, *normal, photons, k, 3.0 * r);
                if !close(wider, l) {
                    return Err(format!(
                        "{call} = {l}, but {wider} with three times the maximum radius: with k photons found the disc is the one that just holds them, whatever the maximum radius"
                    ));
                }
                let as_max = s.caustic_radiance(*diffuse, *normal, photons, k + 1, r_k);
                if !close(as_max, l) {
                    return Err(format!(
                        "{call} = {l}, but {as_max} for the same photons found with the farthest one's distance {r_k} as maximum radius (and k + 1): with k found the disc's radius is the farthest photon's distance"
                    ));
                }
            }
        }
        if let Some(key) = &key {
            let expected = key.caustic_radiance(*diffuse, *normal, photons, k, r);
            compare_vec3(&call, l, expected, 1e-30, REL_TOL)?;
        }
        Ok(())
    })?;
    check_zero_radius(s.as_ref())?;
    let golden: GoldenFile<RadianceInput, Vec3> = ctx.golden(GOLDEN_RADIANCE)?;
    for case in &golden.cases {
        let (diffuse, normal, photons, k, r) = &case.input;
        compare_vec3(
            &format!(
                "caustic_radiance(diffuse {diffuse}, normal {normal}, {} photons, k = {k}, max_radius = {r}) (recorded case)",
                photons.len()
            ),
            radiance(&case.input),
            case.expected,
            1e-30,
            REL_TOL,
        )?;
    }
    check_density(s, ctx)
}

/// A plane lit by a point light a unit above it.
pub const LIT_PLANE: &str = r#"
name = "lit-plane"
[camera]
eye = [0.0, 3.0, 3.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
focal_distance = 1.0
[materials.white]
diffuse = [0.5, 0.6, 0.7]
[[lights]]
type = "point"
position = [0.1, 1.0, -0.2]
intensity = [2.0, 1.0, 0.5]
[[planes]]
point = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
material = "white"
"#;

/// The 25 points of the lit plane where the density estimate is checked.
pub fn plane_points() -> Vec<Vec3> {
    let mut points = Vec::new();
    for i in 0..5 {
        for j in 0..5 {
            points.push(Vec3::new(-1.0 + 0.5 * i as f32, 0.0, -1.0 + 0.5 * j as f32));
        }
    }
    points
}

/// The ratios of the student's estimates at [`plane_points`] from a map of the lit plane
/// (every photon stored where it lands) to the radiance the base's lab 02 code shades there
/// from the light (red and blue channels).
fn plane_errors(
    s: &Arc<dyn PhotonMapping>,
    base: &Pipeline,
    scene: &Scene,
    photons: u32,
    k: usize,
    max_radius: f32,
) -> Result<Vec<(Vec3, f32, f32)>, String> {
    let settings = PhotonSettings {
        emitted: photons,
        seed: 4,
        ..PhotonSettings::DEFAULT
    };
    let trace = trace_photons(base, scene, &settings, StoreRule::FirstDiffuse);
    let Some(Light::Point(light)) = scene.lights.first() else {
        return Err("the lit plane has no point light".into());
    };
    let diffuse = scene
        .materials
        .iter()
        .find(|m| m.name == "white")
        .map(|m| m.diffuse)
        .unwrap_or(Vec3::ONE);
    let mut out = Vec::new();
    let shading = base.code::<dyn contracts::lab02::Shading>();
    for p in plane_points() {
        // What a diffuse surface reflects of the light it receives directly: lab 02's shader.
        let sample = shading.sample_point_light(light, p);
        let expected = shading.shade_lambertian(diffuse, Vec3::Y, &[sample]);
        let nearby = trace.map.nearest(p, k, max_radius);
        let got = s.caustic_radiance(diffuse, Vec3::Y, &nearby, k, max_radius);
        out.push((p, (got / expected).x, (got / expected).z));
    }
    Ok(out)
}

/// The density estimate against the exact irradiance, and its consistency.
fn check_density(s: &Arc<dyn PhotonMapping>, ctx: &LabContext) -> Result<(), String> {
    let scene = check_scene("lit-plane", LIT_PLANE)?;
    let base = ctx.base.clone();
    let ratios = plane_errors(s, &base, &scene, PLANE_PHOTONS, PLANE_K, PLANE_MAX_RADIUS)?;
    // k photons give a relative standard deviation of 1/√k = 5 %.
    let sigma = 1.0 / (PLANE_K as f32).sqrt();
    let mut mean = 0.0;
    for (p, red, blue) in &ratios {
        mean += red / ratios.len() as f32;
        if (red - 1.0).abs() > 6.0 * sigma || (red - blue).abs() > 1e-3 {
            return Err(format!(
                "a plane lit by a point light, every photon stored where it lands ({PLANE_PHOTONS} photons, k = {PLANE_K}, max_radius = {PLANE_MAX_RADIUS}): the estimate at {p} is {red:.3} (red) and {blue:.3} (blue) times the radiance ρ·E/π of the exact irradiance, expected 1 ± {:.2} (the same for every channel)",
                6.0 * sigma
            ));
        }
    }
    if (mean - 1.0).abs() > 0.03 {
        return Err(format!(
            "a plane lit by a point light, every photon stored where it lands: over 25 points the estimate is on average {mean:.3} times the radiance ρ·E/π of the exact irradiance, expected 1 ± 0.03"
        ));
    }
    let mut errors = Vec::new();
    for (photons, radius) in CONSISTENCY_STEPS {
        let ratios = plane_errors(s, &base, &scene, photons, 100_000, radius)?;
        let rms = (ratios
            .iter()
            .map(|(_, r, _)| (r - 1.0).powi(2))
            .sum::<f32>()
            / ratios.len() as f32)
            .sqrt();
        errors.push((photons, radius, rms));
    }
    let (first, last) = (errors[0].2, errors[errors.len() - 1].2);
    if !(last < first && last < 0.08) {
        return Err(format!(
            "the estimate with all photons within a fixed radius should converge as the photons grow and the radius shrinks; RMS relative errors over 25 points of the lit plane (photons, radius, error): {errors:?}"
        ));
    }
    Ok(())
}
