//! The same seed gives the same image on any number of threads, also when some pixels panic.

use std::sync::Arc;

use contracts::lab01::{CameraBasis, CameraRays};
use contracts::lab02::Lab02;
use pipeline::Pipeline;
use pipeline::render::{render, render_partial};
use raylab_core::film::{Film, ToneMap};
use raylab_core::glam::{UVec2, Vec2, Vec3};
use raylab_core::math::Ray;
use raylab_core::render::{NON_FINITE_COLOUR, PANICKED_COLOUR, PartialRender, RenderSettings};
use raylab_core::scene::{Scene, builtin_scene, load_scene_file};

/// A built-in scene, or lab 12's sky scene (`"sky"`), with the pipeline of the last lab
/// prepared for it (the sky's distribution built).
fn scene_and_pipeline(name: &str) -> (Scene, Pipeline) {
    let pipeline = reference::pipeline(course::last().number());
    if name == "sky" {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../labs/lab12/scenes/sky-spheres.toml");
        let scene = load_scene_file(&path).unwrap();
        let pipeline = pipeline::path::with_sky(&pipeline, &scene).unwrap();
        assert!(pipeline.sky.is_some(), "the sky scene's sky is a light");
        (scene, pipeline)
    } else {
        (builtin_scene(name).unwrap(), pipeline)
    }
}

fn render_on(threads: usize, scene: &str) -> raylab_core::film::Film {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let (scene, pipeline) = scene_and_pipeline(scene);
    let settings = RenderSettings {
        width: 96,
        height: 72,
        samples_per_pixel: 4,
        pixel_subdivisions: 2,
        seed: 42,
        progress: false,
    };
    pool.install(|| render(&scene, &pipeline, &settings))
        .unwrap()
}

#[test]
fn one_and_two_threads_give_identical_images() {
    for scene in ["default", "cornell", "sky"] {
        let one = render_on(1, scene);
        let two = render_on(2, scene);
        assert_eq!(one.pixels.len(), 96 * 72);
        assert!(one == two, "scene {scene}: 1 and 2 threads differ");
        // And the image is not trivially constant.
        assert!(one.pixels.iter().any(|p| *p != one.pixels[0]));
    }
}

#[test]
fn another_seed_gives_another_image() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let scene = builtin_scene("default").unwrap();
    let mut settings = RenderSettings {
        width: 48,
        height: 36,
        samples_per_pixel: 4,
        pixel_subdivisions: 1,
        seed: 1,
        progress: false,
    };
    let a = pool
        .install(|| render(&scene, &reference::pipeline(2), &settings))
        .unwrap();
    settings.seed = 2;
    let b = pool
        .install(|| render(&scene, &reference::pipeline(2), &settings))
        .unwrap();
    assert!(a != b, "the seed has no effect on a 4-spp render");
}

/// Reference camera, except that the right third of the image is "unfinished" (Exercise 1.4)
/// and a band of rows gets a NaN direction, as a student's camera half done might.
struct HalfDoneCamera;

impl contracts::lab01::CameraRays for HalfDoneCamera {
    fn image_plane_coords(&self, raster: Vec2, resolution: UVec2) -> Vec2 {
        reference::lab01::Lab01.image_plane_coords(raster, resolution)
    }
    fn camera_basis(&self, eye: Vec3, look_at: Vec3, up: Vec3) -> CameraBasis {
        reference::lab01::Lab01.camera_basis(eye, look_at, up)
    }
    fn field_of_view(&self, focal_distance: f32) -> f32 {
        reference::lab01::Lab01.field_of_view(focal_distance)
    }
    fn ray_direction(&self, basis: &CameraBasis, focal_distance: f32, ip: Vec2) -> Vec3 {
        if ip.x > 0.2 {
            todo!("Exercise 1.4: ray_direction (docs/lab01.md, Exercise 1.4)")
        }
        if (0.1..0.2).contains(&ip.y) {
            return Vec3::NAN;
        }
        reference::lab01::Lab01.ray_direction(basis, focal_distance, ip)
    }
    fn camera_ray(&self, eye: Vec3, direction: Vec3) -> Ray {
        if direction.x < -0.4 {
            panic!("an index out of bounds, say");
        }
        reference::lab01::Lab01.camera_ray(eye, direction)
    }
}

fn partial_on(threads: usize, pipeline: &Pipeline) -> PartialRender {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let scene = builtin_scene("default").unwrap();
    let settings = RenderSettings {
        width: 96,
        height: 72,
        samples_per_pixel: 2,
        pixel_subdivisions: 1,
        seed: 42,
        progress: false,
    };
    pool.install(|| render_partial(&scene, pipeline, &settings))
        .unwrap()
}

fn bits(film: &Film) -> Vec<[u32; 3]> {
    film.pixels
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect()
}

#[test]
fn a_partial_render_marks_and_counts_what_panicked_the_same_on_one_and_two_threads() {
    let pipeline = { reference::pipeline(2).with_part::<dyn CameraRays>(Arc::new(HalfDoneCamera)) };
    let one = partial_on(1, &pipeline);
    let two = partial_on(2, &pipeline);
    assert!(bits(&one.film) == bits(&two.film), "1 and 2 threads differ");
    assert_eq!(one.panicked, two.panicked);
    assert_eq!(one.failures, two.failures);

    // The reference where the camera works, NaN and magenta where it does not.
    let full = partial_on(2, &reference::pipeline(2));
    assert!(full.failures.is_empty() && !full.panicked.contains(&true));
    assert_eq!(full.non_finite_pixels(), 0);
    let marked = one.marked();
    let (mut finished, mut nan) = (0, 0);
    for (i, &p) in one.film.pixels.iter().enumerate() {
        if one.panicked[i] {
            assert!(p.is_nan());
            assert_eq!(marked.pixels[i], PANICKED_COLOUR);
        } else if !p.is_finite() {
            nan += 1;
            assert_eq!(marked.pixels[i], NON_FINITE_COLOUR);
        } else {
            finished += 1;
            assert_eq!(p, full.film.pixels[i]);
        }
    }
    assert!(finished > 1000, "only {finished} pixels finished");
    assert_eq!(nan, one.non_finite_pixels());
    assert!(nan > 0);

    // Counted by cause: the exercise named by the stub, and the other panic by its place.
    let sorted = one.failures.sorted();
    assert_eq!(sorted.len(), 2, "{sorted:?}");
    assert_eq!(sorted[0].exercise(), Some("1.4"));
    assert_eq!(sorted[1].exercise(), None);
    let at = sorted[1].panic.location.as_deref().unwrap();
    assert!(at.starts_with(file!()), "{at}");
    assert!(sorted[1].panic.message.contains("out of bounds"));
    let panicked = one.panicked.iter().filter(|&&p| p).count();
    assert_eq!(one.failures.pixels(), panicked);
    assert!(sorted.iter().all(|f| f.pixels > 0));

    // A tone map does not change the marks.
    let shown = one.display(ToneMap::Reinhard {
        key: 0.5,
        white: f32::INFINITY,
    });
    for (i, &p) in shown.pixels.iter().enumerate() {
        if one.panicked[i] {
            assert_eq!(p, PANICKED_COLOUR);
        }
    }
}

#[test]
fn a_partial_render_of_the_stubs_names_their_exercises_and_the_strict_render_stops() {
    let scene = builtin_scene("default").unwrap();
    let settings = RenderSettings {
        width: 32,
        height: 24,
        ..RenderSettings::default()
    };
    // Exercise 1.2 prepares the camera: every pixel fails.
    let lab1 = reference::pipeline(1).with_part::<dyn CameraRays>(Arc::new(lab01::Student));
    let rendered = render_partial(&scene, &lab1, &settings).unwrap();
    let sorted = rendered.failures.sorted();
    assert_eq!(sorted.len(), 1);
    assert_eq!(sorted[0].exercise(), Some("1.2"));
    assert_eq!(sorted[0].pixels, 32 * 24);
    // Lab 02's stubs: the first intersection test every ray meets.
    let lab2 = reference::pipeline(2).with_part::<dyn Lab02>(Arc::new(lab02::Student));
    let rendered = render_partial(&scene, &lab2, &settings).unwrap();
    assert_eq!(rendered.failures.pixels(), 32 * 24);
    assert!(rendered.failures.0.iter().all(|f| f.exercise().is_some()));
    // `render` itself still stops at the first panic, as the checks need.
    let err = render(&scene, &lab1, &settings).unwrap_err().to_string();
    assert!(err.contains("Exercise 1.2"), "{err}");
}
