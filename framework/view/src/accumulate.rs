//! The render behind the page: passes through each pipeline, accumulated per pixel, restarted
//! when the camera moves; paused while the image has converged (its estimated error at most the
//! target) or while no page asks for it, and resumed when one does or the camera moves.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, RwLock};
use std::time::{Duration, Instant};

use glam::Vec3;
use pipeline::job::failure_lines;
use pipeline::render::render_pixel;
use raylab_core::Error;
use raylab_core::render::{
    PartialRender, PixelFailures, RenderSettings, render_partial_with, resolution,
};
use raylab_core::scene::{CameraSetup, Scene};

use crate::{Shown, ViewSettings};

pub use pipeline::render::PASS_SAMPLES;

/// Samples per pixel of the first pass after a start or a camera move: one, so that the first
/// image comes as soon as it can.
pub const FIRST_PASS_SAMPLES: u32 = 1;

/// Passes after which the render stops until the camera moves.
pub const MAX_PASSES: u32 = 1024;

/// The error at which an image has converged and the render stops until the camera moves: the
/// root mean square over the pixels of the standard error of each pixel's mean relative to
/// that mean, estimated from the passes ([`Accumulated::error`]).
pub const TARGET_ERROR: f32 = 0.01;

/// How long after the last request for an update (a page's `/wait`) the render goes on: a page
/// closed, or hidden (it stops asking), stops costing the machine its cores.
pub const IDLE_AFTER: Duration = Duration::from_secs(15);

/// Why the render is not running.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Paused {
    /// Every image has converged to the target error.
    Converged,
    /// No page has asked for an update for a while.
    Idle,
    /// Every image has its [`MAX_PASSES`] passes.
    Done,
    /// Every pixel panicked: another pass would compute nothing.
    AllMarked,
}

impl Paused {
    /// The word the status gives.
    pub fn word(self) -> &'static str {
        match self {
            Self::Converged => "converged",
            Self::Idle => "idle",
            Self::Done => "done",
            Self::AllMarked => "all marked",
        }
    }
}

/// One pipeline's accumulated image.
pub(crate) struct Accumulated {
    /// What the page calls the pipeline.
    pub name: String,
    /// Per pixel, the sum of the samples' radiance.
    pub sum: Vec<Vec3>,
    /// Per pixel, the sum over the passes of the samples times the square of the pass's mean
    /// luminance: with [`Self::sum`], the estimate of the pixel's variance.
    pub sum_squares: Vec<f64>,
    /// Whether a sample of the pixel panicked (the pixel shows magenta).
    pub panicked: Vec<bool>,
    /// Samples per pixel so far.
    pub samples: u32,
    /// Passes so far.
    pub passes: u32,
    /// What the panicked pixels failed on, over every pass for this camera: a pixel is
    /// computed until it panics once, so each is counted once.
    pub failed: PixelFailures,
    /// The lines naming what panicked (`pipeline::job::failure_lines` of [`Self::failed`]).
    pub failures: Vec<String>,
}

impl Accumulated {
    /// Adds a pass of `samples` samples per pixel, rendered around the pixels marked before.
    pub fn add_pass(&mut self, partial: &PartialRender, samples: u32) {
        for (i, &radiance) in partial.film.pixels.iter().enumerate() {
            self.sum[i] += radiance * samples as f32;
            let luminance = f64::from(luminance_of(radiance));
            self.sum_squares[i] += f64::from(samples) * luminance * luminance;
            self.panicked[i] |= partial.panicked[i];
        }
        self.failed.merge(&partial.failures);
        self.failures = failure_lines(&self.failed, self.sum.len());
        self.samples += samples;
        self.passes += 1;
    }

    /// The mean radiance of pixel `index`, `None` where a sample panicked.
    pub fn mean(&self, index: usize) -> Option<Vec3> {
        (!self.panicked[index] && self.samples > 0).then(|| self.sum[index] / self.samples as f32)
    }

    /// The image's estimated error: the root mean square over its pixels (those that did not
    /// panic and are finite) of the standard error of each pixel's mean luminance relative to
    /// that mean, or to [`DARK`] times the image's mean luminance where the pixel is darker (the
    /// root of the relative mean squared error, relMSE, by which renderers measure noise);
    /// `None` before two passes. With `n` samples in passes of `n_p` samples whose mean
    /// luminances are `L_p`, `Σ n_p L_p² − (Σ n_p L_p)² / n` estimates `(passes − 1) σ²`, and
    /// the mean's variance is `σ² / n`. Each pixel relative to itself: a rare bright path (a
    /// firefly) counts about 1, however bright. An image black everywhere has no error.
    pub fn error(&self) -> Option<f64> {
        if self.passes < 2 {
            return None;
        }
        let n = f64::from(self.samples);
        // Each pixel counted: its mean luminance and the standard error of that mean.
        let pixels = || {
            (0..self.sum.len())
                .filter(|&i| !self.panicked[i])
                .map(move |i| {
                    let total = f64::from(luminance_of(self.sum[i]));
                    let spread = (self.sum_squares[i] - total * total / n).max(0.0);
                    (total / n, (spread / f64::from(self.passes - 1) / n).sqrt())
                })
                .filter(|(mean, error)| mean.is_finite() && error.is_finite())
        };
        let (count, luminance) =
            pixels().fold((0usize, 0.0), |(c, l), (mean, _)| (c + 1, l + mean));
        if count == 0 || luminance <= 0.0 {
            return Some(0.0);
        }
        let dark = DARK * luminance / count as f64;
        let squares: f64 = pixels()
            .map(|(mean, error)| (error / mean.max(dark)).powi(2))
            .sum();
        Some((squares / count as f64).sqrt())
    }
}

/// The fraction of the image's mean luminance below which a pixel's error counts against that
/// instead of its own mean: noise in the near-black is not what one sees.
const DARK: f64 = 0.05;

/// The luminance of a radiance (Rec. 709 weights).
fn luminance_of(radiance: Vec3) -> f32 {
    radiance.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// What the page sees: the camera and the images so far.
pub(crate) struct State {
    /// Counts the camera's moves: the images belong to this camera.
    pub generation: u64,
    /// The camera now.
    pub camera: CameraSetup,
    /// The scene's own camera.
    pub initial_camera: CameraSetup,
    /// Counts the images' changes for this camera (one per pipeline's pass), and the render's
    /// pauses that a page is told of.
    pub updates: u64,
    /// Each pipeline's image.
    pub images: Vec<Accumulated>,
    /// When this camera was set.
    pub camera_set: Instant,
    /// Seconds from the camera's setting to its first pass's image.
    pub first_pass_seconds: Option<f64>,
    /// When a page last asked for an update (a `/wait` began or ended) or moved the camera.
    pub asked: Instant,
    /// The requests for an update under way (long polls held).
    pub asking: usize,
    /// Why the worker is waiting instead of rendering, while it is.
    pub paused: Option<Paused>,
}

impl State {
    /// Passes done by every pipeline for this camera.
    pub fn passes(&self) -> u32 {
        self.images.iter().map(|i| i.passes).min().unwrap_or(0)
    }

    /// Whether every pixel of every pipeline panicked in a pass of this camera: a later pass
    /// would compute nothing (marked pixels are not computed again).
    pub fn all_marked(&self) -> bool {
        self.passes() > 0 && self.images.iter().all(|i| i.panicked.iter().all(|&p| p))
    }

    /// Passes done by the furthest pipeline for this camera: what the page has to show.
    pub fn shown_passes(&self) -> u32 {
        self.images.iter().map(|i| i.passes).max().unwrap_or(0)
    }

    /// The largest estimated error of the images (see [`Accumulated::error`]), `None` until
    /// every image has two passes.
    pub fn error(&self) -> Option<f64> {
        self.images
            .iter()
            .map(Accumulated::error)
            .try_fold(0.0f64, |worst, e| Some(worst.max(e?)))
    }

    /// Why the render should not go on now, if it should not: the images are done (their
    /// passes, all pixels marked, converged to `target`), or no page has asked for an update
    /// within `idle_after` and none is asking.
    pub fn pause_reason(&self, target: f32, idle_after: Duration) -> Option<Paused> {
        if self.passes() >= MAX_PASSES {
            Some(Paused::Done)
        } else if self.all_marked() {
            Some(Paused::AllMarked)
        } else if self.error().is_some_and(|e| e <= f64::from(target)) {
            Some(Paused::Converged)
        } else if self.asking == 0 && self.asked.elapsed() >= idle_after {
            Some(Paused::Idle)
        } else {
            None
        }
    }
}

/// The state shared by the worker and the requests.
pub(crate) struct Accumulator {
    state: Mutex<State>,
    changed: Condvar,
    /// The camera's generation, read by every pixel of a pass: a pass of an older camera
    /// stops at once.
    current_generation: AtomicU64,
    /// The image size.
    pub width: u32,
    /// The image size.
    pub height: u32,
    /// The scene's name.
    pub scene_name: String,
    /// The scene, its camera the one of the pass under way (the worker sets it at the start
    /// of each pass).
    scene: RwLock<Scene>,
    /// The pipelines, in the page's order.
    shown: Vec<Shown>,
    /// The settings of a camera's first pass, whose samples the pixel inspector traces again.
    pub first_pass: RenderSettings,
    /// A pixel the page inspects as it opens.
    pub inspect: Option<[u32; 2]>,
    /// The error at which the images have converged.
    pub target_error: f32,
    /// How long the render goes on after the last request for an update.
    pub idle_after: Duration,
}

impl Accumulator {
    /// Starts the worker rendering `scene` through each of `shown`.
    pub fn start(
        scene: Scene,
        shown: Vec<Shown>,
        settings: &ViewSettings,
    ) -> Result<Arc<Self>, Error> {
        let render_settings = RenderSettings {
            width: settings.width,
            height: settings.height,
            samples_per_pixel: PASS_SAMPLES,
            pixel_subdivisions: 1,
            seed: settings.seed,
            progress: false,
        };
        render_settings.validate()?;
        let pixels = (settings.width * settings.height) as usize;
        let accumulator = Arc::new(Self {
            state: Mutex::new(State {
                generation: 0,
                camera: scene.camera,
                initial_camera: scene.camera,
                updates: 0,
                images: shown
                    .iter()
                    .map(|s| Accumulated {
                        name: s.name.clone(),
                        sum: vec![Vec3::ZERO; pixels],
                        sum_squares: vec![0.0; pixels],
                        panicked: vec![false; pixels],
                        samples: 0,
                        passes: 0,
                        failed: PixelFailures::default(),
                        failures: Vec::new(),
                    })
                    .collect(),
                camera_set: Instant::now(),
                first_pass_seconds: None,
                asked: Instant::now(),
                asking: 0,
                paused: None,
            }),
            changed: Condvar::new(),
            current_generation: AtomicU64::new(0),
            width: settings.width,
            height: settings.height,
            scene_name: scene.name.clone(),
            scene: RwLock::new(scene),
            shown,
            first_pass: RenderSettings {
                samples_per_pixel: FIRST_PASS_SAMPLES,
                ..render_settings
            },
            inspect: settings
                .inspect
                .filter(|[x, y]| *x < settings.width && *y < settings.height),
            target_error: settings.target_error,
            idle_after: settings.idle_after,
        });
        let worker = accumulator.clone();
        std::thread::spawn(move || worker.render_forever(render_settings));
        Ok(accumulator)
    }

    /// The state, whoever panicked while holding it (nothing does: a pixel's panic is caught
    /// inside the render).
    pub fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Calls `f` with the scene (its camera the one of the pass under way, which may still be
    /// the one before the last [`Self::set_camera`]) and the pipelines in the page's order:
    /// for a route that traces a pixel itself, such as a pixel inspector.
    pub fn with_scene<T>(&self, f: impl FnOnce(&Scene, &[Shown]) -> T) -> T {
        f(
            &self.scene.read().unwrap_or_else(|e| e.into_inner()),
            &self.shown,
        )
    }

    /// Moves the camera: the accumulation starts again; returns the new generation.
    pub fn set_camera(&self, camera: CameraSetup) -> u64 {
        let mut state = self.lock();
        state.generation += 1;
        self.current_generation
            .store(state.generation, Ordering::SeqCst);
        state.camera = camera;
        state.updates = 0;
        state.camera_set = Instant::now();
        state.first_pass_seconds = None;
        // A camera move is a page asking, and the new images have converged nowhere yet.
        state.asked = Instant::now();
        state.paused = None;
        for image in &mut state.images {
            image.sum.fill(Vec3::ZERO);
            image.sum_squares.fill(0.0);
            image.panicked.fill(false);
            image.failed = PixelFailures::default();
            image.samples = 0;
            image.passes = 0;
        }
        self.changed.notify_all();
        state.generation
    }

    /// Waits (at most `timeout`) until the state is no longer at `generation` and `updates`,
    /// and returns it locked. A page asking for an update: the render runs while it waits (a
    /// paused one resumes) and for [`Self::idle_after`] after.
    pub fn wait_for_change(
        &self,
        generation: u64,
        updates: u64,
        timeout: Duration,
    ) -> MutexGuard<'_, State> {
        let mut state = self.lock();
        state.asking += 1;
        state.asked = Instant::now();
        self.changed.notify_all();
        let mut state = self
            .changed
            .wait_timeout_while(state, timeout, |s| {
                s.generation == generation && s.updates == updates
            })
            .map_or_else(|e| e.into_inner().0, |(state, _)| state);
        state.asking -= 1;
        state.asked = Instant::now();
        state
    }

    /// The worker: renders pass after pass for the current camera, through every pipeline
    /// (the last, the reference beside the student's code, first: it is the quicker to show),
    /// publishes each pipeline's pass as it is done, and starts again whenever the camera
    /// moves.
    fn render_forever(&self, settings: RenderSettings) {
        let shown = &self.shown;
        'camera: loop {
            let (generation, pass, marked, camera) = {
                let mut state = self.lock();
                // Paused until a page asks or the camera moves: each notifies. A new reason
                // is an update, so that a page watching learns it at once; an idle pause has
                // no page to tell.
                while let Some(reason) = state.pause_reason(self.target_error, self.idle_after) {
                    if state.paused != Some(reason) {
                        state.paused = Some(reason);
                        if reason != Paused::Idle {
                            state.updates += 1;
                            self.changed.notify_all();
                        }
                    }
                    state = self.changed.wait(state).unwrap_or_else(|e| e.into_inner());
                }
                state.paused = None;
                let marked: Vec<Vec<bool>> =
                    state.images.iter().map(|i| i.panicked.clone()).collect();
                (state.generation, state.passes(), marked, state.camera)
            };
            // Set with the state unlocked: a request holding the scene may wait for the state.
            self.scene.write().unwrap_or_else(|e| e.into_inner()).camera = camera;
            let samples = if pass == 0 {
                FIRST_PASS_SAMPLES
            } else {
                PASS_SAMPLES
            };
            let pass_settings = RenderSettings {
                samples_per_pixel: samples,
                seed: settings.seed.wrapping_add(u64::from(pass)),
                ..settings
            };
            let scene = self.scene.read().unwrap_or_else(|e| e.into_inner());
            for (index, s) in shown.iter().enumerate().rev() {
                let marked = &marked[index];
                // `pipeline::render::render_partial`, but each pixel skipped once the camera
                // has moved (the pass is then thrown away), and a pixel already marked as
                // panicked not computed again: it stays magenta, and a panic costs time.
                let outcome = render_partial_with(
                    &pass_settings,
                    || {
                        s.pipeline
                            .prepare_camera(&scene, resolution(&pass_settings))
                    },
                    |camera, x, y| {
                        let pixel = (y * pass_settings.width + x) as usize;
                        if marked[pixel]
                            || self.current_generation.load(Ordering::Relaxed) != generation
                        {
                            return Vec3::ZERO;
                        }
                        render_pixel(&scene, &s.pipeline, camera, &pass_settings, x, y)
                    },
                );
                let mut state = self.lock();
                if state.generation != generation {
                    continue 'camera;
                }
                let image = &mut state.images[index];
                match outcome {
                    Ok(partial) => image.add_pass(&partial, samples),
                    Err(e) => {
                        image.panicked.fill(true);
                        image.failures = vec![format!("error: {e}")];
                        image.samples += samples;
                        image.passes += 1;
                    }
                }
                state.updates += 1;
                if state.first_pass_seconds.is_none() {
                    state.first_pass_seconds = Some(state.camera_set.elapsed().as_secs_f64());
                }
                self.changed.notify_all();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One pixel's image after `passes` passes of `PASS_SAMPLES` samples whose mean luminances
    /// are `values`, in turn.
    fn image(values: &[f32], passes: u32) -> Accumulated {
        let mut image = Accumulated {
            name: "test".into(),
            sum: vec![Vec3::ZERO],
            sum_squares: vec![0.0],
            panicked: vec![false],
            samples: 0,
            passes: 0,
            failed: PixelFailures::default(),
            failures: Vec::new(),
        };
        for p in 0..passes {
            let value = values[p as usize % values.len()];
            let n = PASS_SAMPLES as f32;
            image.sum[0] += Vec3::splat(value) * n;
            image.sum_squares[0] += f64::from(n) * f64::from(value) * f64::from(value);
            image.samples += PASS_SAMPLES;
            image.passes += 1;
        }
        image
    }

    /// A pass of a 4×1 image in which the pixels `failing` panicked on Exercise 2.2's stub.
    fn pass(failing: &[usize]) -> PartialRender {
        let mut film = raylab_core::film::Film::new(4, 1);
        let mut panicked = vec![false; 4];
        let mut failures = PixelFailures::default();
        for &i in failing {
            film.pixels[i] = Vec3::NAN;
            panicked[i] = true;
            let panic = raylab_core::CaughtPanic {
                message: "not yet implemented: Exercise 2.2: intersect_triangle".into(),
                location: None,
            };
            failures.add(&panic, 1);
        }
        PartialRender {
            film,
            panicked,
            failures,
        }
    }

    #[test]
    fn the_failure_lines_count_the_pixels_of_every_pass() {
        let mut image = image(&[0.5], 0);
        image.sum = vec![Vec3::ZERO; 4];
        image.sum_squares = vec![0.0; 4];
        image.panicked = vec![false; 4];
        // Pixels 0 and 1 fail on the first pass; pixel 3 only on the third (a sample that
        // reached the stub late); later passes skip the marked pixels.
        for failing in [&[0, 1][..], &[], &[3], &[]] {
            image.add_pass(&pass(failing), PASS_SAMPLES);
        }
        assert_eq!(
            image.failures,
            [
                "warning: 3 of 4 pixels are magenta: their computation panicked",
                "  Exercise 2.2 is unfinished: 3 pixels (75.0%)"
            ],
            "not the last pass's alone"
        );
        assert_eq!(image.panicked, [true, true, false, true]);
        assert_eq!((image.passes, image.samples), (4, 4 * PASS_SAMPLES));
    }

    #[test]
    fn the_error_is_the_pixels_standard_error_relative_to_the_mean() {
        assert_eq!(image(&[0.5], 1).error(), None, "one pass tells no spread");
        assert!(image(&[0.5], 2).error().unwrap() < 1e-6, "no noise");
        assert_eq!(image(&[0.0], 8).error(), Some(0.0), "black");
        // Passes of mean 1 ± 0.5: σ² of a pass is 1/4 (with n/(n − 1)), so of a sample 1, and
        // the mean's error is 1/√samples.
        let noisy = image(&[0.5, 1.5], 64);
        let expected = (1.0 / f64::from(noisy.samples)).sqrt() * (64.0 / 63.0f64).sqrt();
        assert!((noisy.error().unwrap() - expected).abs() < 1e-3 * expected);
        let more = image(&[0.5, 1.5], 256).error().unwrap();
        assert!(
            (noisy.error().unwrap() / more - 2.0).abs() < 0.02,
            "falls as 1/√n"
        );
        let mut marked = image(&[0.5, 1.5], 64);
        marked.panicked[0] = true;
        assert_eq!(marked.error(), Some(0.0), "marked pixels are not counted");
        let mut nan = image(&[0.5, 1.5], 64);
        nan.sum[0] = Vec3::NAN;
        assert_eq!(nan.error(), Some(0.0), "nor pixels that are not finite");

        // Three pixels, one of them of a rare bright path: it counts about 1, not its brightness.
        let mut three = image(&[0.5, 1.5], 64);
        three.sum = vec![three.sum[0]; 3];
        three.sum_squares = vec![three.sum_squares[0]; 3];
        three.panicked = vec![false; 3];
        // One sample of 1000 in one of the passes.
        three.sum[2] += Vec3::splat(1000.0);
        three.sum_squares[2] += 1000.0 * 1000.0 / f64::from(PASS_SAMPLES);
        let quiet = noisy.error().unwrap();
        let error = three.error().unwrap();
        assert!(
            error > ((2.0 * quiet * quiet + 0.25) / 3.0).sqrt()
                && error < ((2.0 * quiet * quiet + 1.21) / 3.0).sqrt(),
            "{error}"
        );
        // A pixel in the dark counts its error against the image's brightness.
        let mut dark = image(&[0.5, 1.5], 64);
        dark.sum = vec![dark.sum[0], dark.sum[0] * 1e-4];
        dark.sum_squares = vec![dark.sum_squares[0], dark.sum_squares[0] * 1e-8];
        dark.panicked = vec![false; 2];
        let mean = (1.0 + 1e-4) / 2.0;
        let expected = ((quiet.powi(2) + (quiet * 1e-4 / (DARK * mean)).powi(2)) / 2.0).sqrt();
        assert!(
            (dark.error().unwrap() - expected).abs() < 1e-3 * expected,
            "{:?}",
            dark.error()
        );
    }
}
