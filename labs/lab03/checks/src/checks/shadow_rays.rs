//! Exercise 3.1: shadow rays towards point lights, in small scenes and the point-light snapshot.

use std::sync::Arc;

use glam::{Vec2, Vec3};
use proptest::prelude::*;

use contracts::lab02::LightSample;
use contracts::lab03::Shadows;
use grading::strategies::{point, unit_vector};
use grading::{LabContext, PixelTolerance, for_all};
use pipeline::Pipeline;
use pipeline::render::render;
use raylab_core::film::Film;
use raylab_core::math::Ray;
use raylab_core::sampling::Rng;
use raylab_core::scene::Hit;
use raylab_core::scene::{
    CameraSetup, DirectionalLight, Light, Material, MaterialId, Mesh, Plane, PointLight, Scene,
    SceneDescription,
};

use super::cornell::snapshot_scene;
use super::soft_shadows::check_area_snapshot;
use super::{Part, SNAPSHOT_LIGHT_SAMPLES, SNAPSHOT_POINT, SNAPSHOT_SETTINGS, part_pipeline};

/// Accepted range of a shadow ray's `tmin`: above the rounding error of hit positions in a
/// scene of metre size (about 1e-7), at most 1 mm (`RAY_EPSILON` is 0.1 mm).
pub const TMIN_RANGE: (f32, f32) = (1e-5, 1e-3);
/// A shadow ray towards a light at distance `d` must stop between `d − 1e-3·max(1, d)` and
/// `d − 1e-6·max(1, d)`: short of the light's own surface, and not much shorter.
pub const TMAX_SHORT_BY: (f32, f32) = (1e-6, 1e-3);

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
pub(super) const WHITE: MaterialId = MaterialId(0);
pub(super) const LAMP: MaterialId = MaterialId(1);

/// A scene for the checks: planes `(point, normal)`, quads (four corners in order; the normal
/// of the triangles is `(c1 − c0) × (c2 − c0)`) that are lamps or white, and lights.
pub(super) fn test_scene(
    planes: &[(Vec3, Vec3)],
    quads: &[([Vec3; 4], bool)],
    lights: Vec<Light>,
) -> Scene {
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

/// The hard-shadow snapshot of a part: the Cornell box lit by its point light.
pub fn render_point_snapshot(pipeline: &Pipeline) -> Result<Film, raylab_core::Error> {
    render(&snapshot_scene(true)?, pipeline, &SNAPSHOT_SETTINGS)
}

pub(super) fn exercise_3_1(s: &Arc<dyn Shadows>, ctx: &LabContext) -> Result<(), String> {
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
