//! The same seed gives the same image on any number of threads.

use framework::render::{RenderSettings, render};
use framework::scene::builtin_scene;

fn render_on(threads: usize, scene: &str) -> framework::film::Film {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let scene = builtin_scene(scene).unwrap();
    let settings = RenderSettings {
        width: 96,
        height: 72,
        samples_per_pixel: 4,
        pixel_subdivisions: 2,
        seed: 42,
        progress: false,
    };
    pool.install(|| render(&scene, &reference::pipeline(reference::LAST_LAB), &settings))
        .unwrap()
}

#[test]
fn one_and_two_threads_give_identical_images() {
    for scene in ["default", "cornell"] {
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
