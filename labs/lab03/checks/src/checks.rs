//! Lab 03's exercises and their checks.
//!
//! Every exercise is checked in four ways, in this order (the first failure is reported):
//!
//! 1. properties of the function alone, on inputs drawn by proptest from a fixed seed;
//! 2. for 3.1, tiny scenes where the right answer is known (a point in the open is lit exactly
//!    as without shadows, a point under an occluder is black); for 3.2 and 3.3, chi-square
//!    tests of the distribution of the samples; for 3.4, golden cases;
//! 3. for 3.2–3.4, the irradiance from a quad light estimated through the integrator's own
//!    area-light code, compared with the analytic irradiance as the samples grow;
//! 4. renders of the Cornell box: the hard shadows of the point light compared pixel by pixel
//!    (3.1, deterministic), and the soft shadows of the area light compared with the
//!    reference's per-pixel mean and variance by a Z-test (all exercises; see
//!    [`NoiseTolerance`]).
//!
//! Each check puts the student's function for its exercise, and only that one, into the
//! pipeline; everything else is the reference (`ctx.base`).

use std::sync::Arc;

use glam::{Vec2, Vec3};
use proptest::prelude::*;

use contracts::lab02::LightSample;
use contracts::lab03::Shadows;
use grading::radiometry::irradiance_polygon;
use grading::stats::{
    NoiseTolerance, RenderStatistics, chi_square_p_value, chi_square_uniform,
    mean_and_standard_error, normal_two_sided_quantile, sidak,
};
use grading::strategies::triangle_strategy;
use grading::strategies::{point, scale, unit_vector};
use grading::{
    Exercise, GoldenFile, LabContext, PixelTolerance, StrataNames, cell_of, check_one_per_cell,
    compare_f32, compare_vec3, for_all,
};
use pipeline::render::render;
use pipeline::{Pipeline, View};
use raylab_core::film::Film;
use raylab_core::math::Ray;
use raylab_core::render::RenderSettings;
use raylab_core::sampling::Rng;
use raylab_core::scene::{
    CameraSetup, DirectionalLight, Light, Material, MaterialId, Mesh, Plane, PointLight, Scene,
    SceneDescription, builtin_scene,
};
use raylab_core::scene::{Hit, HitSurface};

/// Golden file of Exercise 3.4.
pub const GOLDEN_AREA_SAMPLE: &str = "area_light_sample.json";
/// Snapshot of the Cornell box lit by its point light only: hard shadows (deterministic).
pub const SNAPSHOT_POINT: &str = "cornell-point";
/// The Monte Carlo snapshot of the Cornell box lit by its area light only: the per-pixel mean
/// and variance (one render's) of the reference's renders, `cornell-area-mean.exr` and
/// `cornell-area-variance.exr` (`LabContext::check_noisy_snapshot`).
pub const SNAPSHOT_AREA: &str = "cornell-area";
/// Size and sampling of lab 03's snapshots (the seed is that of the hard-shadow snapshot; the
/// soft-shadow renders use [`REFERENCE_SEEDS`] and [`STUDENT_SEEDS`]).
pub const SNAPSHOT_SETTINGS: RenderSettings = RenderSettings::snapshot(3);
/// `n` of the `n × n` area-light samples of the soft-shadow renders.
pub const SNAPSHOT_LIGHT_SAMPLES: u32 = 4;
/// Seeds of the reference renders whose mean and variance the soft-shadow snapshot holds.
pub const REFERENCE_SEEDS: std::ops::Range<u64> = 1000..1064;
/// Seeds of the student's soft-shadow renders (disjoint from [`REFERENCE_SEEDS`]).
pub const STUDENT_SEEDS: std::ops::Range<u64> = 5000..5004;

/// Accepted range of a shadow ray's `tmin`: above the rounding error of hit positions in a
/// scene of metre size (about 1e-7), at most 1 mm (`RAY_EPSILON` is 0.1 mm).
pub const TMIN_RANGE: (f32, f32) = (1e-5, 1e-3);
/// A shadow ray towards a light at distance `d` must stop between `d − 1e-3·max(1, d)` and
/// `d − 1e-6·max(1, d)`: short of the light's own surface, and not much shorter.
pub const TMAX_SHORT_BY: (f32, f32) = (1e-6, 1e-3);

/// Which student function a render or an estimate exercises; the rest is the base.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// Exercise 3.1, `shadow_ray`.
    ShadowRay,
    /// Exercise 3.2, `stratified_samples`.
    Stratified,
    /// Exercise 3.3, `sample_triangle`.
    Triangle,
    /// Exercise 3.4, `area_light_sample`.
    AreaSample,
}

impl Part {
    /// The contract method whose code this part is (the student's in a [`PartSlot`](pipeline::PartSlot)).
    pub fn function(self) -> &'static str {
        match self {
            Part::ShadowRay => "shadow_ray",
            Part::Stratified => "stratified_samples",
            Part::Triangle => "sample_triangle",
            Part::AreaSample => "area_light_sample",
        }
    }
}

/// Input of Exercise 3.4: surface point, light point, light normal, emission, pdf.
pub type AreaSampleInput = (Vec3, Vec3, Vec3, Vec3, f32);

/// This lab.
pub const LAB: course::LabId = course::LabId::of(3);

/// The exercises of lab 03 (`labs/lab03/exercises.toml`), each with its check.
pub fn exercises() -> Vec<Exercise<dyn Shadows>> {
    grading::exercises(
        LAB,
        grading::checks![exercise_3_1, exercise_3_2, exercise_3_3, exercise_3_4],
    )
}

// ---------------------------------------------------------------------------------------------
// The pipeline of one part

/// The lab-3 pipeline with `student` in `part`'s slot and `base` everywhere else, shading
/// with `n × n` area-light samples.
pub fn part_pipeline(part: Part, student: &Arc<dyn Shadows>, base: &Pipeline, n: u32) -> Pipeline {
    let mut pipeline = base.with_student_function(part.function(), student);
    pipeline.view = View::Shaded;
    pipeline.area_light_samples = n;
    pipeline
}

// ---------------------------------------------------------------------------------------------
// Exercise 3.1

/// Checks one shadow ray against the contract; `Err` says what is wrong.
fn check_shadow_ray(position: Vec3, light: &LightSample, ray: &Ray) -> Result<(), String> {
    let call = format!(
        "shadow_ray(position = {position}, light = {{ direction: {}, distance: {} }})",
        light.direction, light.distance
    );
    let got = format!(
        "a ray from {} along {} over [{}, {}]",
        ray.origin, ray.direction, ray.tmin, ray.tmax
    );
    if !(ray.origin - position)
        .abs()
        .cmple(Vec3::splat(1e-6) + 1e-6 * position.abs())
        .all()
    {
        return Err(format!(
            "{call} returned {got}: the shadow ray must start at the surface point {position} (the offset goes into tmin)"
        ));
    }
    if !(ray.direction - light.direction)
        .abs()
        .cmple(Vec3::splat(1e-5))
        .all()
    {
        let hint = if (ray.direction + light.direction).length() < 1e-3 {
            " — it points away from the light"
        } else {
            ""
        };
        return Err(format!(
            "{call} returned {got}: its direction must be the unit direction towards the light, {}{hint}",
            light.direction
        ));
    }
    let (lo, hi) = TMIN_RANGE;
    if ray.tmin.is_nan() || ray.tmin < lo {
        return Err(format!(
            "{call} returned {got}: tmin = {} is too small — the ray starts on the surface it leaves and, by rounding, hits that surface again (shadow acne); use a small positive offset such as RAY_EPSILON = 1e-4 (accepted: [{lo}, {hi}])",
            ray.tmin
        ));
    }
    if ray.tmin > hi {
        return Err(format!(
            "{call} returned {got}: tmin = {} is too large — an occluder closer than that to the point is skipped and light leaks through where objects touch; use RAY_EPSILON = 1e-4 (accepted: [{lo}, {hi}])",
            ray.tmin
        ));
    }
    let d = light.distance;
    if d.is_infinite() {
        if ray.tmax.is_nan() || ray.tmax < f32::MAX {
            return Err(format!(
                "{call} returned {got}: a directional light is infinitely far away, so anything along the ray shadows the point: tmax must stay ∞"
            ));
        }
        return Ok(());
    }
    let scale = d.max(1.0);
    let short_by = d - ray.tmax;
    if ray.tmax.is_infinite() || ray.tmax > d {
        return Err(format!(
            "{call} returned {got}: tmax = {} is beyond the light (distance {d}) — a surface behind the light, like the ceiling above a lamp, would shadow the point; stop just short of the light, at light.distance − RAY_EPSILON",
            ray.tmax
        ));
    }
    if short_by.is_nan() || short_by < TMAX_SHORT_BY.0 * scale {
        return Err(format!(
            "{call} returned {got}: tmax = {} reaches the light itself (distance {d}) — the shadow ray of an area light then hits the light's own surface and the light shadows itself; stop at light.distance − RAY_EPSILON",
            ray.tmax
        ));
    }
    if short_by > TMAX_SHORT_BY.1 * scale {
        return Err(format!(
            "{call} returned {got}: tmax = {} stops {short_by} short of the light (distance {d}); occluders in between are missed — use light.distance − RAY_EPSILON",
            ray.tmax
        ));
    }
    Ok(())
}

/// A light sample towards a point light (finite distance) or a directional light (infinite).
fn light_sample_strategy() -> impl Strategy<Value = LightSample> {
    (unit_vector(), 0.05f32..20.0, any::<bool>()).prop_map(|(direction, distance, directional)| {
        LightSample {
            direction,
            distance: if directional { f32::INFINITY } else { distance },
            radiance: Vec3::ONE,
        }
    })
}

/// Material ids of the test scenes.
const WHITE: MaterialId = MaterialId(0);
const LAMP: MaterialId = MaterialId(1);

/// A scene for the checks: planes `(point, normal)`, quads (four corners in order; the normal
/// of the triangles is `(c1 − c0) × (c2 − c0)`) that are lamps or white, and lights.
fn test_scene(planes: &[(Vec3, Vec3)], quads: &[([Vec3; 4], bool)], lights: Vec<Light>) -> Scene {
    let mut lamp = Material::lambertian("lamp", Vec3::ZERO);
    lamp.emission = Vec3::new(4.0, 3.0, 2.0);
    let mut mesh = Mesh::default();
    for (corners, emissive) in quads {
        let base = mesh.positions.len() as u32;
        mesh.positions.extend_from_slice(corners);
        let m = if *emissive { LAMP } else { WHITE };
        mesh.faces.push([base, base + 1, base + 2]);
        mesh.faces.push([base, base + 2, base + 3]);
        mesh.face_materials.extend([m, m]);
    }
    Scene::new(SceneDescription {
        name: "lab 03 check scene".into(),
        camera: Some(CameraSetup {
            eye: Vec3::new(0.0, 1.0, 3.0),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            focal_distance: 1.0,
        }),
        background: Vec3::ZERO,
        environment: None,
        materials: vec![Material::lambertian("white", Vec3::splat(0.8)), lamp],
        lights,
        planes: planes
            .iter()
            .map(|&(p, n)| Plane::new(p, n, WHITE))
            .collect(),
        spheres: Vec::new(),
        mesh,
    })
    .expect("the check scenes are valid")
}

/// A horizontal square of half-size `h` centred at `c`, normal up (`down = false`) or down.
fn square(c: Vec3, h: f32, down: bool) -> [Vec3; 4] {
    let (a, b) = (Vec3::new(h, 0.0, 0.0), Vec3::new(0.0, 0.0, h));
    if down {
        [c - a - b, c + a - b, c + a + b, c - a + b]
    } else {
        [c - a - b, c - a + b, c + a + b, c + a - b]
    }
}

/// The occluder of the small scenes: a square at height 0.5 with half-size 0.25.
const OCCLUDER_Y: f32 = 0.5;
const OCCLUDER_HALF: f32 = 0.25;

/// Where the segment from `p` towards `light` (a position, or a direction for `far`) crosses
/// the occluder's height, relative to its centre; `None` if it does not get there.
fn crossing(p: Vec3, towards: Vec3, far: bool) -> Option<Vec2> {
    let d = if far { towards } else { towards - p };
    if p.y >= OCCLUDER_Y || d.y <= 0.0 {
        return None;
    }
    let s = (OCCLUDER_Y - p.y) / d.y;
    if !far && s > 1.0 {
        return None;
    }
    let q = p + s * d;
    Some(Vec2::new(q.x, q.z))
}

/// What the closest surface along a shadow ray is, for a failure message.
fn what_blocks(scene: &Scene, ray: &Ray, light_distance: f32) -> String {
    match scene.trace_to_closest(ray) {
        None => "it hits nothing".into(),
        Some(h) if h.distance < 1e-3 => format!(
            "it hits a surface at t = {:.2e}: the surface it starts on (shadow acne)",
            h.distance
        ),
        Some(h) if h.distance >= light_distance * 0.999 => format!(
            "it hits a surface at t = {} (at {}), at or beyond the light (distance {light_distance})",
            h.distance, h.position
        ),
        Some(h) => format!(
            "it hits a surface at t = {} (at {})",
            h.distance, h.position
        ),
    }
}

/// A camera ray from `eye` to `target` and what it hits.
fn hit_towards(scene: &Scene, eye: Vec3, target: Vec3) -> Hit {
    let ray = Ray::unbounded(eye, (target - eye).normalize(), 0.0);
    scene
        .trace_to_closest(&ray)
        .expect("the check scenes are closed below")
}

/// Exercise 3.1 in small scenes: floor points in the open (and on top of the occluder) are lit
/// exactly as in lab 02, floor points under the occluder are black; with an area light, every
/// one of its `n²` samples reaches an unoccluded point.
fn check_small_scenes(s: &Arc<dyn Shadows>, base: &Pipeline) -> Result<(), String> {
    let pipeline = part_pipeline(Part::ShadowRay, s, base, 3);
    let no_shadows = pipeline.clone().without::<dyn Shadows>();
    let floor = (Vec3::ZERO, Vec3::Y);
    let ceiling = (Vec3::new(0.0, 2.0, 0.0), -Vec3::Y);
    let occluder = (
        square(Vec3::new(0.0, OCCLUDER_Y, 0.0), OCCLUDER_HALF, false),
        false,
    );
    let light_pos = Vec3::new(0.1, 1.0, 0.05);
    let dir_light = Vec3::new(0.3, -1.0, 0.2).normalize();
    let cases: [(&str, Scene, Vec3, bool); 2] = [
        (
            "a point light at (0.1, 1, 0.05) above a square occluder at y = 0.5 over a floor, under a ceiling at y = 2",
            test_scene(
                &[floor, ceiling],
                &[occluder],
                vec![Light::Point(PointLight {
                    position: light_pos,
                    intensity: Vec3::ONE,
                })],
            ),
            light_pos,
            false,
        ),
        (
            "a directional light along (0.3, −1, 0.2) above a square occluder at y = 0.5 over a floor",
            test_scene(
                &[floor],
                &[occluder],
                vec![Light::Directional(DirectionalLight {
                    direction: dir_light,
                    emission: Vec3::ONE,
                })],
            ),
            -dir_light,
            true,
        ),
    ];
    let eye = Vec3::new(2.3, 1.3, 2.9);
    let mut targets: Vec<Vec3> = Vec::new();
    for i in 0..24 {
        for j in 0..24 {
            targets.push(Vec3::new(
                -1.5 + 3.0 * (i as f32 + 0.37) / 24.0,
                0.0,
                -1.5 + 3.0 * (j as f32 + 0.61) / 24.0,
            ));
        }
    }
    // Points on top of the occluder (lit: both lights are above it).
    for i in 0..5 {
        for j in 0..5 {
            targets.push(Vec3::new(
                -0.2 + 0.4 * (i as f32 + 0.3) / 5.0,
                OCCLUDER_Y,
                -0.2 + 0.4 * (j as f32 + 0.7) / 5.0,
            ));
        }
    }
    for (what, scene, towards, far) in &cases {
        for &target in &targets {
            let hit = hit_towards(scene, eye, target);
            if (hit.position - target).length() > 1e-3 {
                continue; // the camera ray hit the occluder first
            }
            let on_top = target.y > 0.0;
            let in_shadow = match crossing(hit.position, *towards, *far) {
                _ if on_top => Some(false),
                None => Some(false),
                Some(q) => {
                    let m = q.abs().max_element() - OCCLUDER_HALF;
                    // Points whose shadow edge is within 1 cm are ambiguous: skip them.
                    (m.abs() > 0.01).then_some(m < 0.0)
                }
            };
            let Some(in_shadow) = in_shadow else {
                continue;
            };
            let mut rng = Rng::new(1, 1);
            let got = pipeline.radiance(
                scene,
                &Ray::unbounded(eye, (target - eye).normalize(), 0.0),
                &mut rng,
            );
            let unshadowed = no_shadows.radiance(
                scene,
                &Ray::unbounded(eye, (target - eye).normalize(), 0.0),
                &mut rng,
            );
            let expected = if in_shadow { Vec3::ZERO } else { unshadowed };
            let close = (got - expected)
                .abs()
                .cmple(Vec3::splat(1e-6) + 1e-5 * expected.abs())
                .all();
            if close {
                continue;
            }
            let shading = base.code::<dyn contracts::lab02::Shading>();
            let light = match scene.lights[0] {
                Light::Point(p) => shading.sample_point_light(&p, hit.position),
                Light::Directional(d) => shading.sample_directional_light(&d, hit.position),
                Light::Area(_) => unreachable!("the cases have no area light"),
            };
            let ray = s.shadow_ray(hit.position, &light);
            let place = if on_top {
                "on top of the occluder"
            } else if in_shadow {
                "on the floor, in the occluder's shadow"
            } else {
                "on the floor, in the open"
            };
            return Err(format!(
                "in a scene with {what}, the point {} ({place}) has radiance {got}, expected {expected}{}. Its shadow ray is shadow_ray(position = {}, light = {{ direction: {}, distance: {} }}) = a ray from {} along {} over [{}, {}]; {}",
                hit.position,
                if in_shadow {
                    " (black: the occluder blocks the light)"
                } else {
                    " (lit exactly as without shadows)"
                },
                hit.position,
                light.direction,
                light.distance,
                ray.origin,
                ray.direction,
                ray.tmin,
                ray.tmax,
                what_blocks(scene, &ray, light.distance)
            ));
        }
    }

    // An area light (a lamp square at y = 1 facing down, a ceiling above it): nothing is in the
    // way, so every sample must reach the floor.
    let scene = test_scene(
        &[floor, (Vec3::new(0.0, 1.5, 0.0), -Vec3::Y)],
        &[(square(Vec3::new(0.0, 1.0, 0.0), 0.2, true), true)],
        Vec::new(),
    );
    let Some(Light::Area(area)) = scene.lights.first().cloned() else {
        unreachable!("the lamp makes an area light")
    };
    let n = pipeline.area_light_samples;
    for (k, &target) in targets.iter().enumerate().step_by(7) {
        let hit = hit_towards(&scene, eye, target);
        let mut rng = Rng::new(2, k as u64);
        let kept = pipeline.light_samples(&scene, &hit, &mut rng).len();
        if kept == (n * n) as usize {
            continue;
        }
        let mut rng = Rng::new(2, k as u64);
        let samples = base.light_samples(&scene, &hit, &mut rng);
        let blocked = samples
            .iter()
            .map(|l| (l, s.shadow_ray(hit.position, l)))
            .find(|(_, r)| scene.trace_to_any(r));
        let detail = blocked.map_or_else(String::new, |(l, r)| {
            format!(
                " For the sample at distance {} along {}, shadow_ray returned a ray from {} along {} over [{}, {}]; {}",
                l.distance,
                l.direction,
                r.origin,
                r.direction,
                r.tmin,
                r.tmax,
                what_blocks(&scene, &r, l.distance)
            )
        });
        return Err(format!(
            "under an area light (a square lamp of area {} at y = 1 facing down, nothing in the way, a ceiling above it), only {kept} of the {} light samples reach the floor point {}; all should.{detail}",
            area.area,
            n * n,
            hit.position
        ));
    }
    Ok(())
}

/// The Cornell box with only its point light (`point = true`) or only its area light.
pub fn snapshot_scene(point: bool) -> Result<Scene, raylab_core::Error> {
    let mut scene = builtin_scene("cornell")?;
    scene.lights.retain(|l| match l {
        Light::Point(_) => point,
        Light::Area(_) => !point,
        Light::Directional(_) => false,
    });
    scene.name = if point {
        "cornell, point light only".into()
    } else {
        "cornell, area light only".into()
    };
    Ok(scene)
}

/// The hard-shadow snapshot of a part: the Cornell box lit by its point light.
pub fn render_point_snapshot(pipeline: &Pipeline) -> Result<Film, raylab_core::Error> {
    render(&snapshot_scene(true)?, pipeline, &SNAPSHOT_SETTINGS)
}

fn exercise_3_1(s: &Arc<dyn Shadows>, ctx: &LabContext) -> Result<(), String> {
    for_all(
        300,
        (point(5.0), light_sample_strategy()),
        |(position, light)| check_shadow_ray(position, &light, &s.shadow_ray(position, &light)),
    )?;
    check_small_scenes(s, &ctx.base)?;
    let pipeline = part_pipeline(Part::ShadowRay, s, &ctx.base, SNAPSHOT_LIGHT_SAMPLES);
    let film = render_point_snapshot(&pipeline).map_err(|e| e.to_string())?;
    let tol = PixelTolerance {
        abs: 2e-3,
        rel: 2e-3,
        max_outlier_fraction: 0.005,
    };
    ctx.check_snapshot(SNAPSHOT_POINT, &film, &tol)?;
    check_area_snapshot(Part::ShadowRay, s, ctx)
}

// ---------------------------------------------------------------------------------------------
// Statistics

/// Rejection level of the chi-square tests of 3.2 and 3.3 (each test; there are about ten).
pub const CHI_SQUARE_P: f64 = 1e-6;

/// Formats counts as a small table for messages.
fn format_counts(counts: &[u32]) -> String {
    counts
        .iter()
        .map(|c| c.to_string())
        .collect::<Vec<_>>()
        .join(" ")
}

// ---------------------------------------------------------------------------------------------
// Exercise 3.2

fn check_strata(n: u32, samples: &[Vec2]) -> Result<(), String> {
    let call = format!("stratified_samples(n = {n}, rng)");
    let names = StrataNames {
        call: &call,
        point: "sample",
        cell: "cell",
        outside_hint: "",
    };
    check_one_per_cell(&names, n, samples)
}

/// Where a sample lies within its cell, in `[0, 1)²`.
fn offset_in_cell(p: Vec2, n: u32) -> Vec2 {
    let (i, j) = cell_of(p, n);
    let o = Vec2::new(
        (p.x as f64 * n as f64 - i as f64) as f32,
        (p.y as f64 * n as f64 - j as f64) as f32,
    );
    o.clamp(Vec2::ZERO, Vec2::splat(0.999_999))
}

/// The positions of samples within their cells, binned into `k × k` bins.
fn offset_counts(samples: &[Vec2], n: u32, k: u32) -> Vec<u32> {
    let mut counts = vec![0u32; (k * k) as usize];
    for p in samples {
        let o = offset_in_cell(*p, n);
        let (bx, by) = ((o.x * k as f32) as u32, (o.y * k as f32) as u32);
        counts[(by.min(k - 1) * k + bx.min(k - 1)) as usize] += 1;
    }
    counts
}

/// The jitter: within its cell, each sample must be uniformly distributed and independent of
/// the others (χ² tests of the in-cell positions), and it must come from `rng`.
fn check_jitter(s: &Arc<dyn Shadows>) -> Result<(), String> {
    const K: u32 = 4;
    // One call with many cells: the in-cell positions of its 256 samples.
    for seed in 0..6u64 {
        let samples = s.stratified_samples(16, &mut Rng::new(seed, 31));
        let counts = offset_counts(&samples, 16, K);
        let stat = chi_square_uniform(&counts);
        let p = chi_square_p_value(stat, K * K - 1);
        if p < CHI_SQUARE_P {
            return Err(format!(
                "the samples of one call stratified_samples(n = 16, rng) are not jittered uniformly within their cells: binning each sample's position within its cell into {K}×{K} bins gives the counts [{}] (expected about {} each; χ² = {stat:.1}, {} degrees of freedom, p = {p:.1e}). Each cell needs its own uniform random point (i + ξ₁, j + ξ₂)/n with fresh ξ₁, ξ₂ from rng.next_vec2() — not the cell centre, and not one offset shared by all cells or by x and y",
                format_counts(&counts),
                256 / (K * K),
                K * K - 1
            ));
        }
    }
    // The samples come from rng: two generators give two different sets.
    for n in [1u32, 4] {
        let a = s.stratified_samples(n, &mut Rng::new(1, 2));
        let b = s.stratified_samples(n, &mut Rng::new(3, 4));
        if a == b {
            return Err(format!(
                "stratified_samples(n = {n}, rng) returned the same samples {a:?} for two different generators: the jitter must come from rng (rng.next_vec2() once per cell)"
            ));
        }
    }
    // Many calls with few cells, pooled.
    for n in 1..=3u32 {
        let calls = 1024 / (n * n);
        let mut rng = Rng::new(17, n as u64);
        let samples: Vec<Vec2> = (0..calls)
            .flat_map(|_| s.stratified_samples(n, &mut rng))
            .collect();
        let counts = offset_counts(&samples, n, K);
        let stat = chi_square_uniform(&counts);
        let p = chi_square_p_value(stat, K * K - 1);
        if p < CHI_SQUARE_P {
            return Err(format!(
                "over {calls} calls of stratified_samples(n = {n}, rng) on one generator, the positions of the samples within their cells are not uniform: {K}×{K} bins hold [{}] (expected about {} each; χ² = {stat:.1}, {} degrees of freedom, p = {p:.1e}). Each call must draw new random offsets from rng",
                format_counts(&counts),
                samples.len() as u32 / (K * K),
                K * K - 1
            ));
        }
    }
    Ok(())
}

fn exercise_3_2(s: &Arc<dyn Shadows>, ctx: &LabContext) -> Result<(), String> {
    for_all(300, (1u32..=16, any::<u64>()), |(n, seed)| {
        check_strata(n, &s.stratified_samples(n, &mut Rng::new(seed, 5)))
    })?;
    check_jitter(s)?;
    check_irradiance(Part::Stratified, s, &ctx.base)?;
    check_area_snapshot(Part::Stratified, s, ctx)
}

// ---------------------------------------------------------------------------------------------
// Exercise 3.3

/// Barycentric coordinates `(β, γ)` of `p` in the triangle (least squares, f64) and the
/// distance of `p` from the triangle's plane.
fn barycentrics(t: &[Vec3; 3], p: Vec3) -> (f64, f64, f64) {
    let [a, b, c] = t.map(|v| v.as_dvec3());
    let (e1, e2, d) = (b - a, c - a, p.as_dvec3() - a);
    let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (d1, d2) = (d.dot(e1), d.dot(e2));
    let det = d11 * d22 - d12 * d12;
    let beta = (d22 * d1 - d12 * d2) / det;
    let gamma = (d11 * d2 - d12 * d1) / det;
    let off_plane = (d - beta * e1 - gamma * e2).length();
    (beta, gamma, off_plane)
}

fn check_in_triangle(t: &[Vec3; 3], u: Vec2, p: Vec3) -> Result<(), String> {
    let call = format!(
        "sample_triangle(v0 = {}, v1 = {}, v2 = {}, u = {u})",
        t[0], t[1], t[2]
    );
    if !p.is_finite() {
        return Err(format!("{call} returned {p}"));
    }
    let scale = (t[1] - t[0]).length().max((t[2] - t[0]).length()) as f64;
    let (beta, gamma, off) = barycentrics(t, p);
    let tol = 1e-4;
    if off > tol * scale {
        return Err(format!(
            "{call} returned {p}, {off:.3e} off the triangle's plane"
        ));
    }
    if beta < -tol || gamma < -tol || beta + gamma > 1.0 + tol {
        return Err(format!(
            "{call} returned {p}, outside the triangle: its barycentric coordinates are (1 − β − γ, β, γ) = ({:.4}, {beta:.4}, {gamma:.4}); all three must be in [0, 1]",
            1.0 - beta - gamma
        ));
    }
    Ok(())
}

/// Uniform numbers in `[0, 1)²`, with the corners and edges of the square now and then.
fn unit_square() -> impl Strategy<Value = Vec2> + Clone {
    let coord = prop_oneof![
        6 => 0.0f32..1.0,
        1 => Just(0.0f32),
        1 => Just(1.0 - f32::EPSILON / 2.0),
    ];
    (coord.clone(), coord).prop_map(|(x, y)| Vec2::new(x, y))
}

/// Index of the sub-triangle of a `k × k` subdivision (`k²` triangles of equal area) that the
/// point with barycentrics `(β, γ)` lies in.
fn sub_triangle(beta: f64, gamma: f64, k: u32) -> usize {
    let (x, y) = (
        beta.clamp(0.0, 1.0) * k as f64,
        gamma.clamp(0.0, 1.0) * k as f64,
    );
    let (i, j) = (x.floor().min(k as f64 - 1.0), y.floor().min(k as f64 - 1.0));
    let (mut i, mut j) = (i as u32, j as u32);
    if i + j > k - 1 {
        // Rounding at the outer edge: move into the nearest upright cell.
        let excess = i + j - (k - 1);
        if i >= excess {
            i -= excess;
        } else {
            j -= excess - i;
            i = 0;
        }
    }
    let inverted = i + j < k - 1 && (x - i as f64) + (y - j as f64) > 1.0;
    (2 * (j * k + i) + inverted as u32) as usize
}

/// Uniformity by area: samples from uniform `u` are counted in the `k²` congruent sub-triangles
/// of each test triangle, and Pearson's χ² test compares the counts with equal ones.
fn check_uniform_by_area(s: &Arc<dyn Shadows>) -> Result<(), String> {
    const K: u32 = 4;
    const N: usize = 12_800;
    let triangles = [
        [Vec3::ZERO, Vec3::X, Vec3::Y],
        [
            Vec3::new(1.0, 2.0, -1.0),
            Vec3::new(-2.0, 0.5, 0.3),
            Vec3::new(0.4, -1.0, 2.0),
        ],
        [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(3.0, 0.1, 0.0),
            Vec3::new(2.6, 0.3, 0.4),
        ],
    ];
    for (k, t) in triangles.iter().enumerate() {
        let mut rng = Rng::new(23, k as u64);
        let mut counts = vec![0u32; 2 * (K * K) as usize];
        for _ in 0..N {
            let u = rng.next_vec2();
            let p = s.sample_triangle(*t, u);
            check_in_triangle(t, u, p)?;
            let (beta, gamma, _) = barycentrics(t, p);
            counts[sub_triangle(beta, gamma, K)] += 1;
        }
        // Only the k² real sub-triangles (upright cells and the inverted ones inside).
        let cells: Vec<u32> = (0..K * K)
            .flat_map(|c| {
                let (i, j) = (c % K, c / K);
                let mut v = Vec::new();
                if i + j < K {
                    v.push(counts[2 * c as usize]);
                }
                if i + j + 1 < K {
                    v.push(counts[2 * c as usize + 1]);
                }
                v
            })
            .collect();
        let stat = chi_square_uniform(&cells);
        let p = chi_square_p_value(stat, K * K - 1);
        if p < CHI_SQUARE_P {
            return Err(format!(
                "sample_triangle is not uniform by area on the triangle v0 = {}, v1 = {}, v2 = {}: of {N} samples from uniform u, the {} congruent sub-triangles of a {K}×{K} subdivision hold [{}] (expected {} each; χ² = {stat:.1}, {} degrees of freedom, p = {p:.1e}); the sub-triangles are listed row by row from the edge v0–v1 (β along the row, γ across rows). A uniform point has barycentrics (1 − √u₁, √u₁(1 − u₂), √u₁·u₂)",
                t[0],
                t[1],
                t[2],
                K * K,
                format_counts(&cells),
                N as u32 / (K * K),
                K * K - 1,
            ));
        }
    }
    Ok(())
}

fn exercise_3_3(s: &Arc<dyn Shadows>, ctx: &LabContext) -> Result<(), String> {
    for_all(300, (triangle_strategy(), unit_square()), |(t, u)| {
        check_in_triangle(&t, u, s.sample_triangle(t, u))
    })?;
    check_uniform_by_area(s)?;
    check_irradiance(Part::Triangle, s, &ctx.base)?;
    check_area_snapshot(Part::Triangle, s, ctx)
}

// ---------------------------------------------------------------------------------------------
// Exercise 3.4

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

fn exercise_3_4(s: &Arc<dyn Shadows>, ctx: &LabContext) -> Result<(), String> {
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

// ---------------------------------------------------------------------------------------------
// Irradiance from a quad light: the estimate against the analytic value

/// Form factor from a point to a parallel rectangle `[0, a] × [0, b]` whose corner lies at
/// height `h` straight above it, facing it (Howell's catalogue of configuration factors,
/// "differential planar element to parallel rectangle"):
/// `F = 1/(2π) [X/√(1+X²)·atan(Y/√(1+X²)) + Y/√(1+Y²)·atan(X/√(1+Y²))]`, `X = a/h`, `Y = b/h`.
pub fn form_factor_parallel_corner(a: f64, b: f64, h: f64) -> f64 {
    let (x, y) = (a / h, b / h);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    ((x / sx) * (y / sx).atan() + (y / sy) * (x / sy).atan()) / (2.0 * std::f64::consts::PI)
}

/// Irradiance at a point facing up from a Lambertian rectangle of radiance `le` at height `h`
/// above it, spanning `[x0, x1] × [z0, z1]` relative to the point: `E = π·L_e·F`, with `F`
/// summed from four corner rectangles with signs.
pub fn irradiance_parallel_rectangle(le: f64, h: f64, x: [f64; 2], z: [f64; 2]) -> f64 {
    let g =
        |x: f64, z: f64| x.signum() * z.signum() * form_factor_parallel_corner(x.abs(), z.abs(), h);
    let f = g(x[1], z[1]) - g(x[0], z[1]) - g(x[1], z[0]) + g(x[0], z[0]);
    std::f64::consts::PI * le * f
}

/// One quad-light configuration of the irradiance check.
struct QuadCase {
    what: &'static str,
    corners: [Vec3; 4],
    receiver: Vec3,
    normal: Vec3,
    exact: f64,
}

fn quad_cases() -> Vec<QuadCase> {
    // A 0.3 × 0.2 rectangle 0.5 above the floor, the receiver off its axis.
    let rect = [
        Vec3::new(-0.15, 0.5, -0.1),
        Vec3::new(0.15, 0.5, -0.1),
        Vec3::new(0.15, 0.5, 0.1),
        Vec3::new(-0.15, 0.5, 0.1),
    ];
    let receiver = Vec3::new(0.1, 0.0, -0.05);
    let exact_rect = irradiance_parallel_rectangle(
        1.0,
        0.5,
        [-0.15 - 0.1, 0.15 - 0.1],
        [-0.1 + 0.05, 0.1 + 0.05],
    );
    // A tilted trapezoid (two triangles of unequal area) and a tilted receiver.
    let trapezoid = [
        Vec3::new(-0.3, 0.6, -0.1),
        Vec3::new(0.2, 0.45, -0.15),
        Vec3::new(0.1, 0.5, 0.2),
        Vec3::new(-0.2, 0.62, 0.15),
    ];
    let normal = Vec3::new(0.3, 1.0, -0.2).normalize();
    let receiver2 = Vec3::new(0.05, 0.0, 0.3);
    let exact_trap = irradiance_polygon(
        1.0,
        receiver2.as_dvec3(),
        normal.as_dvec3(),
        &trapezoid.map(|v| v.as_dvec3()),
    );
    vec![
        QuadCase {
            what: "a 0.3 × 0.2 rectangular light 0.5 above a point off its axis, facing it",
            corners: rect,
            receiver,
            normal: Vec3::Y,
            exact: exact_rect,
        },
        QuadCase {
            what: "a tilted trapezoidal light (two triangles of unequal area) above a tilted point",
            corners: trapezoid,
            receiver: receiver2,
            normal,
            exact: exact_trap,
        },
    ]
}

/// The scene of one quad case: the quad as a lamp of radiance 1 (facing down), nothing else.
fn quad_scene(case: &QuadCase) -> Scene {
    let mut corners = case.corners;
    if (corners[1] - corners[0]).cross(corners[2] - corners[0]).y > 0.0 {
        corners.reverse();
    }
    let mut scene = test_scene(&[], &[(corners, true)], Vec::new());
    scene.materials[LAMP.0 as usize].emission = Vec3::ONE;
    scene
}

/// `M` estimates of the irradiance at the receiver, through the integrator's own light
/// sampling (`Pipeline::light_samples`: `pick_face`, 3.2–3.4, weight `1/n²`, shadow rays).
fn irradiance_estimates(pipeline: &Pipeline, scene: &Scene, case: &QuadCase, m: u32) -> Vec<f64> {
    let hit = Hit {
        distance: 1.0,
        position: case.receiver,
        geometric_normal: case.normal,
        shading_normal: case.normal,
        texcoord: Vec2::ZERO,
        surface: HitSurface::Unknown,
        material: WHITE,
        trace_depth: 0,
        ior: 1.0,
    };
    (0..m)
        .map(|k| {
            let mut rng = Rng::new(pipeline.area_light_samples as u64, k as u64);
            pipeline
                .light_samples(scene, &hit, &mut rng)
                .iter()
                .map(|l| l.radiance.x as f64 * case.normal.dot(l.direction).max(0.0) as f64)
                .sum()
        })
        .collect()
}

/// Estimates per level of the irradiance check.
pub const IRRADIANCE_ESTIMATES: u32 = 1024;
/// The `n` of the levels of the irradiance check.
pub const IRRADIANCE_LEVELS: [u32; 4] = [1, 2, 4, 8];
/// Least ratio of the standard errors with one and with 8×8 samples in the irradiance check:
/// `8√2`, the variance of 64 jittered samples at most half that of 64 independent ones (the
/// reference reaches 15–30, independent samples 8).
pub const MIN_STRATIFICATION_GAIN: f64 = 11.3;
/// Family-wise false-alarm rate of the irradiance check's Z-tests (Šidák-corrected).
pub const IRRADIANCE_ALPHA: f64 = 1e-4;

/// The area-light estimator converges to the analytic irradiance: at every level the mean of
/// [`IRRADIANCE_ESTIMATES`] estimates is within the Šidák-corrected `z·SE` of the exact value
/// (plus 1e-5 relative for rounding), and stratification pays: the standard error with 8×8
/// samples is at most `1/MIN_STRATIFICATION_GAIN` of that with one sample.
pub fn check_irradiance(part: Part, s: &Arc<dyn Shadows>, base: &Pipeline) -> Result<(), String> {
    let cases = quad_cases();
    let z = normal_two_sided_quantile(sidak(
        IRRADIANCE_ALPHA,
        cases.len() * IRRADIANCE_LEVELS.len(),
    ));
    for case in &cases {
        let scene = quad_scene(case);
        let mut errors = Vec::new();
        for n in IRRADIANCE_LEVELS {
            let pipeline = part_pipeline(part, s, base, n);
            let x = irradiance_estimates(&pipeline, &scene, case, IRRADIANCE_ESTIMATES);
            let (mean, se) = mean_and_standard_error(&x, x.len());
            errors.push((n, mean, se));
            let within = (mean - case.exact).abs() <= z * se + 1e-5 * case.exact;
            if !within {
                let history = errors
                    .iter()
                    .map(|(n, m, se)| format!("{}: {m:.5} ± {se:.5}", n * n))
                    .collect::<Vec<_>>()
                    .join(", ");
                return Err(format!(
                    "the irradiance from {} (radiance 1; exact value E = {:.5} by the analytic formula) estimated through the renderer's area-light sampling with {n}×{n} samples is {mean:.5} ± {se:.5} (mean ± standard error of {IRRADIANCE_ESTIMATES} estimates), {:.2}× the exact value and {:.1} standard errors off (at most {z:.1} allowed). Estimates so far (samples: mean ± SE): {history}",
                    case.what,
                    case.exact,
                    mean / case.exact,
                    (mean - case.exact).abs() / se.max(1e-300)
                ));
            }
        }
        let (se1, se8) = (errors[0].2, errors[errors.len() - 1].2);
        // 64 independent samples would divide the standard error by √64 = 8.
        let gain = se1 / se8;
        if gain.is_nan() || gain < MIN_STRATIFICATION_GAIN {
            return Err(format!(
                "the irradiance from {} estimated with 8×8 stratified samples has standard error {se8:.2e}, and with one sample {se1:.2e}: only {gain:.1}× smaller. 64 independent samples would give 8× (√64); jittered samples, one per cell, must do better than {MIN_STRATIFICATION_GAIN:.1}× (half the variance of independent samples)",
                case.what,
            ));
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Soft-shadow renders: a Z-test against the reference statistics

/// The tolerance of the soft-shadow snapshot.
pub const AREA_TOLERANCE: NoiseTolerance = NoiseTolerance {
    family_alpha: 1e-3,
    abs: 1e-4,
    rel: 1e-3,
    max_outlier_fraction: 0.003,
};

/// One soft-shadow render: the Cornell box lit by its area light, `seed`.
pub fn render_area(pipeline: &Pipeline, seed: u64) -> Result<Film, raylab_core::Error> {
    render(
        &snapshot_scene(false)?,
        pipeline,
        &RenderSettings {
            seed,
            ..SNAPSHOT_SETTINGS
        },
    )
}

/// Per-pixel mean and (unbiased) variance of renders with the given seeds.
pub fn area_statistics(
    pipeline: &Pipeline,
    seeds: std::ops::Range<u64>,
) -> Result<RenderStatistics, raylab_core::Error> {
    let films = seeds
        .map(|seed| render_area(pipeline, seed))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(RenderStatistics::of(&films))
}

/// The soft-shadow check of a part: the student's renders ([`STUDENT_SEEDS`]) against the
/// reference's ([`REFERENCE_SEEDS`]) under [`AREA_TOLERANCE`].
pub fn check_area_snapshot(
    part: Part,
    s: &Arc<dyn Shadows>,
    ctx: &LabContext,
) -> Result<(), String> {
    let pipeline = part_pipeline(part, s, &ctx.base, SNAPSHOT_LIGHT_SAMPLES);
    let student = area_statistics(&pipeline, STUDENT_SEEDS).map_err(|e| e.to_string())?;
    ctx.check_noisy_snapshot(
        SNAPSHOT_AREA,
        &student,
        (REFERENCE_SEEDS.end - REFERENCE_SEEDS.start) as u32,
        &AREA_TOLERANCE,
        &format!(
            "the soft shadows of the Cornell box (lit by its area light only, {n}×{n} light samples)",
            n = SNAPSHOT_LIGHT_SAMPLES
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn lamberts_formula_matches_the_rectangle_form_factor() {
        // A rectangle [x0, x1] × [z0, z1] at height h above a point facing up, both ways.
        for (x, z, h) in [
            ([-0.25, 0.05], [0.05, 0.25], 0.5),
            ([0.1, 0.7], [-0.3, 0.2], 0.3),
            ([-1.0, 1.0], [-1.0, 1.0], 1.0),
        ] {
            let polygon = [
                DVec3::new(x[0], h, z[0]),
                DVec3::new(x[1], h, z[0]),
                DVec3::new(x[1], h, z[1]),
                DVec3::new(x[0], h, z[1]),
            ];
            let a = irradiance_parallel_rectangle(2.0, h, x, z);
            let b = irradiance_polygon(2.0, DVec3::ZERO, DVec3::Y, &polygon);
            assert!((a - b).abs() < 1e-12 * a.max(1.0), "{a} {b}");
        }
        // A huge square close above: almost the whole hemisphere, E → π·L.
        let e = irradiance_parallel_rectangle(1.0, 1e-3, [-1.0, 1.0], [-1.0, 1.0]);
        assert!((e - std::f64::consts::PI).abs() < 1e-2, "{e}");
    }

    #[test]
    fn sub_triangles_split_the_triangle_into_equal_parts() {
        // Uniform barycentrics on a fine grid: every one of the k² cells gets its share.
        let k = 4;
        let mut counts = vec![0u32; 2 * (k * k) as usize];
        let m = 400;
        for i in 0..m {
            for j in 0..m - i {
                let (b, g) = ((i as f64 + 0.3) / m as f64, (j as f64 + 0.3) / m as f64);
                if b + g < 1.0 {
                    counts[sub_triangle(b, g, k)] += 1;
                }
            }
        }
        let used: Vec<u32> = counts.iter().copied().filter(|&c| c > 0).collect();
        assert_eq!(used.len(), (k * k) as usize);
        let (lo, hi) = (used.iter().min().unwrap(), used.iter().max().unwrap());
        assert!((*hi as f64) < 1.1 * *lo as f64, "{used:?}");
    }
}
