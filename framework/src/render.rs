//! Deterministic parallel rendering: the image is cut into tiles that rayon renders in
//! parallel; every (pixel, sample) draws from its own seeded generator, so the same seed gives
//! the same image on any number of threads.

use glam::{UVec2, Vec2, Vec3};
use rayon::prelude::*;

use crate::Error;
use crate::film::Film;
use crate::pipeline::{Pipeline, PreparedCamera};
use crate::sampling::Rng;
use crate::scene::Scene;

/// Side length of a render tile in pixels.
pub const TILE_SIZE: u32 = 16;

/// Size, sampling and seed of a render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel: 1 traces through the pixel centre, more trace through uniformly
    /// random points in the pixel and average.
    pub samples_per_pixel: u32,
    /// Pixel subdivision `s` of lab 07: with a pipeline at lab 7 or later and `s > 1`, every
    /// sample of a pixel averages `s × s` jittered subpixel rays (`compute_jitters`,
    /// `compute_pixel`).
    pub pixel_subdivisions: u32,
    /// Seed of every random number of the render.
    pub seed: u64,
    /// Show a progress bar on standard error (when it is a terminal).
    pub progress: bool,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 512,
            height: 384,
            samples_per_pixel: 1,
            pixel_subdivisions: 1,
            seed: 0,
            progress: false,
        }
    }
}

impl RenderSettings {
    /// The settings of every lab's snapshot images: 160×120 pixels, one ray through each pixel
    /// centre, no subdivision, the given seed. Small, so a lab's checks take about a second.
    pub const fn snapshot(seed: u64) -> Self {
        Self {
            width: 160,
            height: 120,
            samples_per_pixel: 1,
            pixel_subdivisions: 1,
            seed,
            progress: false,
        }
    }

    /// Checks the settings, naming the offending value.
    pub fn validate(&self) -> Result<(), Error> {
        let invalid = |what: &str, value: u32| Error::Invalid {
            what: format!("{what} {value}"),
            reason: "expected a whole number of at least 1".into(),
        };
        if self.width == 0 {
            return Err(invalid("image width", self.width));
        }
        if self.height == 0 {
            return Err(invalid("image height", self.height));
        }
        if self.samples_per_pixel == 0 {
            return Err(invalid("samples per pixel", self.samples_per_pixel));
        }
        if self.pixel_subdivisions == 0 || self.pixel_subdivisions > 64 {
            return Err(Error::Invalid {
                what: format!("pixel subdivisions {}", self.pixel_subdivisions),
                reason: "expected a whole number from 1 to 64".into(),
            });
        }
        if self.width as u64 * self.height as u64 > 1 << 28 {
            return Err(Error::Invalid {
                what: format!("image size {}×{}", self.width, self.height),
                reason: "expected at most 2^28 pixels".into(),
            });
        }
        Ok(())
    }
}

/// Renders `scene` through `pipeline`. A panic in a pipeline component (an unfinished
/// exercise, say) is returned as [`Error::Panic`].
pub fn render(
    scene: &Scene,
    pipeline: &Pipeline,
    settings: &RenderSettings,
) -> Result<Film, Error> {
    settings.validate()?;
    let resolution = UVec2::new(settings.width, settings.height);
    let tiles: Vec<(u32, u32)> = (0..settings.height.div_ceil(TILE_SIZE))
        .flat_map(|ty| (0..settings.width.div_ceil(TILE_SIZE)).map(move |tx| (tx, ty)))
        .collect();
    let bar = if settings.progress {
        indicatif::ProgressBar::new(tiles.len() as u64).with_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {pos}/{len} tiles, {elapsed} (eta {eta})",
            )
            .expect("the template is valid"),
        )
    } else {
        indicatif::ProgressBar::hidden()
    };
    let rendered = crate::catch_quietly(&format!("rendering '{}'", scene.name), || {
        let camera = pipeline.prepare_camera(scene, resolution);
        tiles
            .par_iter()
            .map(|&(tx, ty)| {
                let tile = render_tile(scene, pipeline, &camera, settings, tx, ty);
                bar.inc(1);
                tile
            })
            .collect::<Vec<_>>()
    })?;
    bar.finish_and_clear();
    let mut film = Film::new(settings.width, settings.height);
    for (x, y, value) in rendered.into_iter().flatten() {
        film.set(x, y, value);
    }
    Ok(film)
}

fn render_tile(
    scene: &Scene,
    pipeline: &Pipeline,
    camera: &PreparedCamera,
    settings: &RenderSettings,
    tx: u32,
    ty: u32,
) -> Vec<(u32, u32, Vec3)> {
    let x_end = ((tx + 1) * TILE_SIZE).min(settings.width);
    let y_end = ((ty + 1) * TILE_SIZE).min(settings.height);
    let mut out = Vec::with_capacity((TILE_SIZE * TILE_SIZE) as usize);
    for y in ty * TILE_SIZE..y_end {
        for x in tx * TILE_SIZE..x_end {
            out.push((x, y, render_pixel(scene, pipeline, camera, settings, x, y)));
        }
    }
    out
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
