//! The pixel inspector on the default scene through the answer key's pipeline: what it
//! holds, that its radiance is the render's, and the exercise it names when a pixel fails.

use std::sync::Arc;

use contracts::lab02::{LightSample, Shading};
use contracts::scene::{DirectionalLight, PointLight};
use contracts::trace::{NonFinite, RayAnswer, RayKind};
use glam::Vec3;
use pipeline::Pipeline;
use pipeline::inspect::{Inspection, Problem, Step, inspect_pixel};
use pipeline::render::{render, render_partial};
use raylab_core::render::RenderSettings;
use raylab_core::scene::{Scene, builtin_scene};

/// A small 1-sample image of the default scene.
fn settings(spp: u32, subdivisions: u32) -> RenderSettings {
    RenderSettings {
        width: 32,
        height: 24,
        samples_per_pixel: spp,
        pixel_subdivisions: subdivisions,
        seed: 5,
        progress: false,
    }
}

fn default_scene() -> Scene {
    builtin_scene("default").unwrap()
}

/// A pixel of the ground plane, lit by both lights, near the bottom-left corner.
const GROUND: (u32, u32) = (3, 21);

fn inspect(scene: &Scene, pipeline: &Pipeline, settings: &RenderSettings) -> Inspection {
    inspect_pixel(scene, pipeline, settings, GROUND.0, GROUND.1, 0).unwrap()
}

/// The calls of an inspection as (method, exercise id).
fn calls(inspection: &Inspection) -> Vec<(&str, Option<&str>)> {
    inspection
        .steps
        .iter()
        .filter_map(|s| match s {
            Step::Call(c) => Some((c.call.method, c.exercise.as_ref().map(|e| e.id.as_str()))),
            Step::Ray(_) => None,
        })
        .collect()
}

#[test]
fn a_pixel_s_inspection_holds_its_camera_ray_its_hit_and_its_shading() {
    let scene = default_scene();
    let inspection = inspect(&scene, &reference::pipeline(4), &settings(1, 1));
    let calls = calls(&inspection);
    for expected in [
        ("camera_basis", Some("1.2")),
        ("camera_ray", Some("1.5")),
        ("sample_point_light", Some("2.4")),
        ("sample_directional_light", Some("2.5")),
        ("shade_lambertian", Some("2.6")),
    ] {
        assert!(calls.contains(&expected), "{expected:?} not in {calls:?}");
    }
    let rays: Vec<_> = inspection
        .steps
        .iter()
        .filter_map(|s| match s {
            Step::Ray(r) => Some(r),
            Step::Call(_) => None,
        })
        .collect();
    let camera = rays.iter().find(|r| r.kind == RayKind::Camera).unwrap();
    let RayAnswer::Closest(Some(hit)) = &camera.answer else {
        panic!("the camera ray hits the ground: {camera:?}");
    };
    assert_eq!(hit.material, "ground");
    // The radiance along the camera ray is the sample's (lab 4: the Whitted integrator).
    assert_eq!(camera.radiance, Some(inspection.radiance));
    assert!(hit.position.y.abs() < 1e-3, "{hit:?}");
    assert_eq!(hit.shading_normal, Vec3::Y);
    assert!((hit.distance - camera.ray.origin.distance(hit.position)).abs() < 1e-3);
    // Two shadow rays (point and directional light), nothing blocking them here.
    let shadows: Vec<_> = rays.iter().filter(|r| r.kind == RayKind::Shadow).collect();
    assert_eq!(shadows.len(), 2, "{shadows:?}");
    assert!(shadows.iter().all(|r| r.answer == RayAnswer::Any(false)));
    // The camera ray comes after the call that made it, and the shading after the hit.
    let at = |method: &str| {
        inspection
            .steps
            .iter()
            .position(|s| matches!(s, Step::Call(c) if c.call.method == method))
            .unwrap()
    };
    let camera_at = inspection
        .steps
        .iter()
        .position(|s| matches!(s, Step::Ray(r) if r.kind == RayKind::Camera))
        .unwrap();
    assert!(at("camera_ray") < camera_at && camera_at < at("shade_lambertian"));
    assert!(inspection.culprit.is_none() && inspection.panic.is_none());
    assert!(inspection.radiance.is_finite() && inspection.radiance.x > 0.0);
    // It serializes (for the page that shows it).
    let json = serde_json::to_value(&inspection).unwrap();
    assert_eq!(json["steps"][0]["type"], "call");
    assert_eq!(json["steps"][0]["method"], "camera_basis");
    assert_eq!(json["steps"][0]["exercise"]["id"], "1.2");
}

#[test]
fn the_inspected_radiance_is_the_sample_s_in_the_render() {
    let scene = default_scene();
    // The Whitted integrator, Fresnel-weighted glass, and the path tracer.
    for lab in [4, 10, 12] {
        let pipeline = reference::pipeline(lab);
        let settings = settings(1, 1);
        let film = render(&scene, &pipeline, &settings).unwrap();
        for (x, y) in [GROUND, (16, 12), (27, 14), (10, 2)] {
            let inspection = inspect_pixel(&scene, &pipeline, &settings, x, y, 0).unwrap();
            assert_eq!(
                inspection.radiance.to_array(),
                film.get(x, y).to_array(),
                "lab {lab}, pixel ({x}, {y})"
            );
        }
    }
    // Three jittered samples of 2 × 2 subpixels each (lab 07): their mean is the pixel.
    let pipeline = reference::pipeline(7);
    let settings = settings(3, 2);
    let film = render(&scene, &pipeline, &settings).unwrap();
    let mut sum = Vec3::ZERO;
    for sample in 0..3 {
        let inspection = inspect_pixel(&scene, &pipeline, &settings, 16, 12, sample).unwrap();
        let jitters = calls(&inspection)
            .iter()
            .filter(|(m, _)| *m == "compute_jitters")
            .count();
        assert_eq!(jitters, 1);
        sum += inspection.radiance;
    }
    assert_eq!((sum / 3.0).to_array(), film.get(16, 12).to_array());
}

/// The answer key's shading, but for one function that panics or returns a NaN.
struct BrokenShading {
    nan: bool,
}

impl Shading for BrokenShading {
    fn sample_point_light(&self, light: &PointLight, position: Vec3) -> LightSample {
        let sample = reference::lab02::Lab02.sample_point_light(light, position);
        if self.nan {
            LightSample {
                radiance: Vec3::NAN,
                ..sample
            }
        } else {
            sample
        }
    }

    fn sample_directional_light(&self, light: &DirectionalLight, position: Vec3) -> LightSample {
        reference::lab02::Lab02.sample_directional_light(light, position)
    }

    fn shade_lambertian(&self, rho_d: Vec3, normal: Vec3, lights: &[LightSample]) -> Vec3 {
        if !self.nan {
            #[allow(clippy::useless_vec)]
            let index = vec![0usize; 3][lights.len() + 3];
            return Vec3::splat(index as f32);
        }
        reference::lab02::Lab02.shade_lambertian(rho_d, normal, lights)
    }
}

#[test]
fn a_failing_function_is_named_by_its_exercise() {
    let scene = default_scene();
    let broken =
        |nan| reference::pipeline(4).with_part::<dyn Shading>(Arc::new(BrokenShading { nan }));
    // A panic (no exercise in its message): the pixel is magenta, and Exercise 2.6 is named.
    let pipeline = broken(false);
    let rendered = render_partial(&scene, &pipeline, &settings(1, 1)).unwrap();
    assert!(rendered.panicked[(GROUND.1 * 32 + GROUND.0) as usize]);
    let inspection = inspect(&scene, &pipeline, &settings(1, 1));
    let panic = inspection.panic.as_ref().expect("the sample panicked");
    assert!(panic.message.contains("index out of bounds"), "{panic:?}");
    let culprit = inspection.culprit.as_ref().unwrap();
    assert_eq!(culprit.problem, Problem::Panicked);
    assert_eq!(culprit.method, "shade_lambertian");
    assert_eq!(culprit.exercise.as_ref().unwrap().id, "2.6");
    assert!(
        culprit
            .message
            .starts_with("Exercise 2.6 (shade_lambertian, lab 2) panicked"),
        "{}",
        culprit.message
    );
    assert!(
        matches!(&inspection.steps[culprit.step], Step::Call(c) if c.call.method == "shade_lambertian")
    );

    // A NaN: the pixel is cyan, and the NaN's origin is Exercise 2.4, not the shading that
    // carried it on.
    let pipeline = broken(true);
    let film = render(&scene, &pipeline, &settings(1, 1)).unwrap();
    assert!(film.get(GROUND.0, GROUND.1).is_nan());
    let inspection = inspect(&scene, &pipeline, &settings(1, 1));
    assert_eq!(inspection.non_finite, Some(NonFinite::Nan));
    assert!(inspection.panic.is_none());
    let culprit = inspection.culprit.as_ref().unwrap();
    assert_eq!(culprit.problem, Problem::Nan);
    assert_eq!(culprit.exercise.as_ref().unwrap().id, "2.4");
    assert!(
        culprit.message.contains("returned a NaN"),
        "{}",
        culprit.message
    );
}

#[test]
fn inspecting_twice_gives_the_same_answer_and_recording_stops() {
    let scene = default_scene();
    let pipeline = reference::pipeline(12);
    let settings = settings(4, 1);
    let json = |i: &Inspection| serde_json::to_string(i).unwrap();
    let first = inspect_pixel(&scene, &pipeline, &settings, 16, 12, 2).unwrap();
    assert!(!contracts::trace::is_recording());
    // A render with the traced pipeline, on this thread and others, notes nothing: the next
    // inspection holds its own calls only.
    let traced = pipeline.traced();
    let camera = traced.prepare_camera(&scene, glam::UVec2::new(32, 24));
    pipeline::render::render_pixel(&scene, &traced, &camera, &settings, 16, 12);
    render(&scene, &traced, &settings).unwrap();
    let second = inspect_pixel(&scene, &pipeline, &settings, 16, 12, 2).unwrap();
    assert_eq!(json(&first), json(&second));
    assert!(!contracts::trace::is_recording());
    // The path tracer's calls, nested in its path loop.
    let nested = first
        .steps
        .iter()
        .any(|s| matches!(s, Step::Call(c) if c.call.method == "bsdf" && c.call.depth == 1));
    assert!(nested, "{:?}", calls(&first));
    // A pixel or sample the image does not have is an error.
    assert!(inspect_pixel(&scene, &pipeline, &settings, 32, 0, 0).is_err());
    assert!(inspect_pixel(&scene, &pipeline, &settings, 0, 0, 4).is_err());
}

#[test]
fn a_mirror_s_reflected_ray_carries_its_radiance() {
    let scene = default_scene();
    let pipeline = reference::pipeline(4);
    let settings = settings(1, 1);
    let on_mirror = (0..24)
        .map(|y| inspect_pixel(&scene, &pipeline, &settings, 16, y, 0).unwrap())
        .find(|i| {
            i.steps.iter().any(|s| {
                matches!(s, Step::Ray(r) if r.kind == RayKind::Camera
                    && matches!(&r.answer, RayAnswer::Closest(Some(h)) if h.material == "mirror"))
            })
        })
        .expect("a pixel of the middle column sees the mirror sphere");
    let reflected = on_mirror
        .steps
        .iter()
        .find_map(|s| match s {
            Step::Ray(r) if r.kind == RayKind::Reflected => Some(r),
            _ => None,
        })
        .expect("the mirror reflects a ray");
    assert_eq!(reflected.depth, 0);
    assert_eq!(reflected.radiance, Some(on_mirror.radiance));
    let calls = calls(&on_mirror);
    assert!(calls.contains(&("reflected_ray", Some("4.2"))), "{calls:?}");
}
