//! The render behind the page: passes through each pipeline, accumulated per pixel, restarted
//! when the camera moves.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, RwLock};
use std::time::{Duration, Instant};

use glam::Vec3;
use pipeline::job::failure_lines;
use pipeline::render::render_pixel;
use raylab_core::Error;
use raylab_core::render::{RenderSettings, render_partial_with, resolution};
use raylab_core::scene::{CameraSetup, Scene};

use crate::{Shown, ViewSettings};

pub use pipeline::render::PASS_SAMPLES;

/// Samples per pixel of the first pass after a start or a camera move: one, so that the first
/// image comes as soon as it can.
pub const FIRST_PASS_SAMPLES: u32 = 1;

/// Passes after which the render stops until the camera moves.
pub const MAX_PASSES: u32 = 1024;

/// One pipeline's accumulated image.
pub(crate) struct Accumulated {
    /// What the page calls the pipeline.
    pub name: String,
    /// Per pixel, the sum of the samples' radiance.
    pub sum: Vec<Vec3>,
    /// Whether a sample of the pixel panicked (the pixel shows magenta).
    pub panicked: Vec<bool>,
    /// Samples per pixel so far.
    pub samples: u32,
    /// Passes so far.
    pub passes: u32,
    /// The lines naming what panicked in the last pass (`pipeline::job::failure_lines`).
    pub failures: Vec<String>,
}

impl Accumulated {
    /// The mean radiance of pixel `index`, `None` where a sample panicked.
    pub fn mean(&self, index: usize) -> Option<Vec3> {
        (!self.panicked[index] && self.samples > 0).then(|| self.sum[index] / self.samples as f32)
    }
}

/// What the page sees: the camera and the images so far.
pub(crate) struct State {
    /// Counts the camera's moves: the images belong to this camera.
    pub generation: u64,
    /// The camera now.
    pub camera: CameraSetup,
    /// The scene's own camera.
    pub initial_camera: CameraSetup,
    /// Counts the images' changes for this camera (one per pipeline's pass).
    pub updates: u64,
    /// Each pipeline's image.
    pub images: Vec<Accumulated>,
    /// When this camera was set.
    pub camera_set: Instant,
    /// Seconds from the camera's setting to its first pass's image.
    pub first_pass_seconds: Option<f64>,
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
                        panicked: vec![false; pixels],
                        samples: 0,
                        passes: 0,
                        failures: Vec::new(),
                    })
                    .collect(),
                camera_set: Instant::now(),
                first_pass_seconds: None,
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
        for image in &mut state.images {
            image.sum.fill(Vec3::ZERO);
            image.panicked.fill(false);
            image.samples = 0;
            image.passes = 0;
        }
        self.changed.notify_all();
        state.generation
    }

    /// Waits (at most `timeout`) until the state is no longer at `generation` and `updates`,
    /// and returns it locked.
    pub fn wait_for_change(
        &self,
        generation: u64,
        updates: u64,
        timeout: Duration,
    ) -> MutexGuard<'_, State> {
        let state = self.lock();
        self.changed
            .wait_timeout_while(state, timeout, |s| {
                s.generation == generation && s.updates == updates
            })
            .map_or_else(|e| e.into_inner().0, |(state, _)| state)
    }

    /// The worker: renders pass after pass for the current camera, through every pipeline
    /// (the last, the reference beside the student's code, first: it is the quicker to show),
    /// publishes each pipeline's pass as it is done, and starts again whenever the camera
    /// moves.
    fn render_forever(&self, settings: RenderSettings) {
        let shown = &self.shown;
        'camera: loop {
            let (generation, pass, marked, camera) = {
                let state = self.lock();
                let state = self
                    .changed
                    .wait_while(state, |s| s.passes() >= MAX_PASSES || s.all_marked())
                    .unwrap_or_else(|e| e.into_inner());
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
                    Ok(partial) => {
                        for (i, &radiance) in partial.film.pixels.iter().enumerate() {
                            image.sum[i] += radiance * samples as f32;
                            image.panicked[i] |= partial.panicked[i];
                        }
                        // The failures of the pixels computed in this pass; the ones
                        // marked before are named by the earlier passes' lines.
                        if pass == 0 || !partial.failures.is_empty() {
                            image.failures = failure_lines(&partial.failures, image.sum.len());
                        }
                    }
                    Err(e) => {
                        image.panicked.fill(true);
                        image.failures = vec![format!("error: {e}")];
                    }
                }
                image.samples += samples;
                image.passes += 1;
                state.updates += 1;
                if state.first_pass_seconds.is_none() {
                    state.first_pass_seconds = Some(state.camera_set.elapsed().as_secs_f64());
                }
                self.changed.notify_all();
            }
        }
    }
}
