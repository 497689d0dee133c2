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
    let mut sum = Vec3::ZERO;
    for s in 0..spp {
        sum += render_sample(scene, pipeline, camera, settings, x, y, s);
    }
    sum / spp as f32
}

/// The radiance of sample `sample` of pixel `(x, y)`, drawn from that sample's own random
/// numbers: [`render_pixel`] averages these, and the pixel inspector traces one.
pub fn render_sample(
    scene: &Scene,
    pipeline: &Pipeline,
    camera: &PreparedCamera,
    settings: &RenderSettings,
    x: u32,
    y: u32,
    sample: u32,
) -> Vec3 {
    let mut rng = Rng::for_sample(settings.seed, x, y, sample);
    if let Some(antialiasing) = pipeline.calls.antialiasing.as_deref()
        && settings.pixel_subdivisions > 1
    {
        let jitters = antialiasing.compute_jitters(settings.pixel_subdivisions, &mut rng);
        antialiasing.compute_pixel(UVec2::new(x, y), &jitters, &mut |raster| {
            let ray = pipeline.camera_ray(camera, raster);
            pipeline.radiance(scene, &ray, &mut rng)
        })
    } else {
        let offset = if settings.samples_per_pixel == 1 {
            Vec2::splat(0.5)
        } else {
            rng.next_vec2()
        };
        let raster = Vec2::new(x as f32, y as f32) + offset;
        let ray = pipeline.camera_ray(camera, raster);
        pipeline.radiance(scene, &ray, &mut rng)
    }
}

/// Samples per pixel of each pass of a [`render_progressive`] (jittered within the pixel).
pub const PASS_SAMPLES: u32 = 4;

/// The settings of pass `pass` (from 0) of a [`render_progressive`] of `settings`:
/// [`PASS_SAMPLES`] samples per pixel, seeded by `settings.seed + pass`. The pixel inspector
/// takes them to trace a sample of that pass.
pub fn pass_settings(settings: &RenderSettings, pass: u32) -> RenderSettings {
    RenderSettings {
        samples_per_pixel: PASS_SAMPLES,
        seed: settings.seed.wrapping_add(u64::from(pass)),
        ..*settings
    }
}

/// The outcome of a progressive render.
pub struct ProgressiveRender {
    /// The last pass's partial render, its film replaced by the mean of every pass.
    pub rendered: PartialRender,
    /// Per pixel, the variance of that mean (`m2 / (n (n − 1))` per channel).
    pub variance: Film,
    /// The passes rendered.
    pub passes: u32,
    /// The largest relative error of a pixel's mean when it stopped.
    pub worst_error: f32,
}

/// Renders `scene` through `pipeline` in passes of [`PASS_SAMPLES`] samples per pixel, up to
/// `settings.samples_per_pixel` in all, each pixel's pass means accumulated through lab 12's
/// `accumulate` (Exercise 12.9); stops early when every pixel's `relative_error` (Exercise
/// 12.10) is below `target`. `after_pass(passes, mean)` is called after each pass. Pass `p`
/// draws its numbers from the seed `settings.seed + p`, so the image does not depend on the
/// number of threads. A panic of the lab's two functions is an error naming the exercise.
pub fn render_progressive(
    scene: &Scene,
    pipeline: &Pipeline,
    settings: &RenderSettings,
    target: Option<f32>,
    mut after_pass: impl FnMut(u32, &Film) -> Result<(), Error>,
) -> Result<ProgressiveRender, Error> {
    use contracts::lab12::PixelStatistics;
    let code = crate::required(&pipeline.calls.path_tracing);
    let passes = settings.samples_per_pixel.div_ceil(PASS_SAMPLES).max(1);
    let mut stats = vec![PixelStatistics::default(); (settings.width * settings.height) as usize];
    let mut last = None;
    let mut worst_error = f32::INFINITY;
    let mut done = 0;
    for pass in 0..passes {
        let pass_settings = pass_settings(settings, pass);
        let rendered = render_partial(scene, pipeline, &pass_settings)?;
        let film = &rendered.film;
        stats = raylab_core::catch_quietly("Exercise 12.9", || {
            stats
                .iter()
                .zip(&film.pixels)
                .map(|(s, &x)| code.accumulate(s, x))
                .collect()
        })
        .map_err(Error::Panic)?;
        done = pass + 1;
        let mean = Film {
            pixels: stats.iter().map(|s| s.mean).collect(),
            ..film.clone()
        };
        after_pass(done, &mean)?;
        last = Some(rendered);
        if let Some(target) = target {
            worst_error = raylab_core::catch_quietly("Exercise 12.10", || {
                stats
                    .iter()
                    .map(|s| code.relative_error(s))
                    .fold(0.0, f32::max)
            })
            .map_err(Error::Panic)?;
            if worst_error < target {
                break;
            }
        }
    }
    let mut rendered = last.expect("at least one pass");
    rendered.film.pixels = stats.iter().map(|s| s.mean).collect();
    let variance = Film {
        pixels: stats
            .iter()
            .map(|s| {
                let n = s.count as f32;
                if s.count > 1 {
                    s.m2 / (n * (n - 1.0))
                } else {
                    Vec3::splat(f32::INFINITY)
                }
            })
            .collect(),
        ..rendered.film.clone()
    };
    Ok(ProgressiveRender {
        rendered,
        variance,
        passes: done,
        worst_error,
    })
}
