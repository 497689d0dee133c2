//! Rendering a scene through a [`Pipeline`]: the core's parallel tile loop
//! ([`raylab_core::render`]) with each pixel's samples traced by the pipeline — the camera ray
//! of lab 01, lab 07's subdivided pixels, the radiance of the integrator.

use glam::{UVec2, Vec2, Vec3};
use raylab_core::Error;
use raylab_core::film::Film;
use raylab_core::render::{
    PartialRender, RenderSettings, render_partial_with, render_with, resolution,
};
use raylab_core::sampling::Rng;
use raylab_core::scene::Scene;

use crate::{Pipeline, PreparedCamera};

/// Renders `scene` through `pipeline`. A panic in a pipeline component (an unfinished
/// exercise, say) stops the render and is returned as [`Error::Panic`]; [`render_partial`]
/// carries on instead and marks the pixels it cost.
pub fn render(
    scene: &Scene,
    pipeline: &Pipeline,
    settings: &RenderSettings,
) -> Result<Film, Error> {
    render_with(
        settings,
        &format!("rendering '{}'", scene.name),
        || pipeline.prepare_camera(scene, resolution(settings)),
        |camera, x, y| render_pixel(scene, pipeline, camera, settings, x, y),
    )
}

/// Renders `scene` through `pipeline` like [`render`], but a pixel whose computation panics
/// (an unfinished `todo!()` in a student's stub, or any other panic) does not stop the image:
/// it gets NaN radiance and is marked and counted (see [`render_partial_with`]). A panic while
/// preparing the camera (Exercise 1.2) fails every pixel. Deterministic like [`render`].
pub fn render_partial(
    scene: &Scene,
    pipeline: &Pipeline,
    settings: &RenderSettings,
) -> Result<PartialRender, Error> {
    render_partial_with(
        settings,
        || pipeline.prepare_camera(scene, resolution(settings)),
        |camera, x, y| render_pixel(scene, pipeline, camera, settings, x, y),
    )
}

/// The average radiance of the samples of pixel `(x, y)`.
pub fn render_pixel(
    scene: &Scene,
    pipeline: &Pipeline,
    camera: &PreparedCamera,
    settings: &RenderSettings,
    x: u32,
    y: u32,
) -> Vec3 {
    let spp = settings.samples_per_pixel;
    let subdivided = pipeline.lab >= 7 && settings.pixel_subdivisions > 1;
    let mut sum = Vec3::ZERO;
    for s in 0..spp {
        let mut rng = Rng::for_sample(settings.seed, x, y, s);
        sum += if subdivided {
            let jitters = pipeline
                .antialiasing
                .compute_jitters(settings.pixel_subdivisions, &mut rng);
            pipeline
                .antialiasing
                .compute_pixel(UVec2::new(x, y), &jitters, &mut |raster| {
                    let ray = pipeline.camera_ray(camera, raster);
                    pipeline.radiance(scene, &ray, &mut rng)
                })
        } else {
            let offset = if spp == 1 {
                Vec2::splat(0.5)
            } else {
                rng.next_vec2()
            };
            let raster = Vec2::new(x as f32, y as f32) + offset;
            let ray = pipeline.camera_ray(camera, raster);
            pipeline.radiance(scene, &ray, &mut rng)
        };
    }
    sum / spp as f32
}
