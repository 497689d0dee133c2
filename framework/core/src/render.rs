//! Deterministic parallel rendering: the image is cut into tiles that rayon renders in
//! parallel, each pixel by a function of its coordinates (the pipeline's, which seeds every
//! (pixel, sample) from its own generator), so the same seed gives the same image on any number
//! of threads; panics are caught and marked instead of stopping the image.

use glam::{UVec2, Vec3};
use rayon::prelude::*;

use crate::Error;
use crate::film::{Film, ToneMap};
pub use crate::panic::CaughtPanic;
use crate::panic::catch_panic;
use crate::progress::Progress;

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
    /// Pixel subdivision `s`: for a pixel function that subdivides (lab 07's anti-aliasing in
    /// the pipeline), every sample of a pixel averages `s × s` jittered subpixel rays.
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

/// Renders the image of `settings` with `pixel(&prepared, x, y)` as each pixel's radiance,
/// `prepared` made once by `prepare` (a camera, say). A panic in either stops the render and
/// is returned as [`Error::Panic`] naming `what`; [`render_partial_with`] carries on instead
/// and marks the pixels it cost.
pub fn render_with<C: Sync>(
    settings: &RenderSettings,
    what: &str,
    prepare: impl FnOnce() -> C,
    pixel: impl Fn(&C, u32, u32) -> Vec3 + Sync,
) -> Result<Film, Error> {
    settings.validate()?;
    let rendered = crate::catch_quietly(what, || {
        let prepared = prepare();
        render_tiles(settings, |x, y| pixel(&prepared, x, y))
    })?;
    let mut film = Film::new(settings.width, settings.height);
    for (x, y, value) in rendered.into_iter().flatten() {
        film.set(x, y, value);
    }
    Ok(film)
}

/// Colour of the pixels whose computation panicked (an unfinished `todo!()`, say) in
/// [`PartialRender::marked`]: magenta.
pub const PANICKED_COLOUR: Vec3 = Vec3::new(1.0, 0.0, 1.0);

/// Colour of the pixels whose radiance is NaN or infinite in [`PartialRender::marked`]: cyan.
pub const NON_FINITE_COLOUR: Vec3 = Vec3::new(0.0, 1.0, 1.0);

/// One cause of failed pixels: an unfinished exercise, or one place that panicked.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PixelFailure {
    /// The panic of the first failed pixel of this cause, in tile order.
    pub panic: CaughtPanic,
    /// How many pixels it cost.
    pub pixels: usize,
}

impl PixelFailure {
    /// The exercise an unfinished stub names ("Exercise N.M" in the panic message).
    pub fn exercise(&self) -> Option<&str> {
        self.panic.exercise()
    }
}

/// What failures are counted together by: the exercise, else the place, else the message.
fn cause(panic: &CaughtPanic) -> (&str, &str) {
    match (panic.exercise(), &panic.location) {
        (Some(id), _) => ("exercise", id),
        (None, Some(at)) => ("location", at),
        (None, None) => ("message", &panic.message),
    }
}

/// The failed pixels of one or more renders, counted by cause (see [`PixelFailure`]), in the
/// order each cause was first met.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PixelFailures(pub Vec<PixelFailure>);

impl PixelFailures {
    /// Counts `pixels` more pixels that failed with `panic`.
    pub fn add(&mut self, panic: &CaughtPanic, pixels: usize) {
        match self.0.iter_mut().find(|f| cause(&f.panic) == cause(panic)) {
            Some(known) => known.pixels += pixels,
            None => self.0.push(PixelFailure {
                panic: panic.clone(),
                pixels,
            }),
        }
    }

    /// Adds every failure of `other`.
    pub fn merge(&mut self, other: &PixelFailures) {
        for f in &other.0 {
            self.add(&f.panic, f.pixels);
        }
    }

    /// All failed pixels.
    pub fn pixels(&self) -> usize {
        self.0.iter().map(|f| f.pixels).sum()
    }

    /// Whether no pixel failed.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The unfinished exercises first, by number, then the other causes, most pixels first.
    pub fn sorted(&self) -> Vec<&PixelFailure> {
        let key = |f: &PixelFailure| match f.exercise() {
            Some(id) => {
                let (major, minor) = id.split_once('.').unwrap_or((id, ""));
                (
                    0,
                    major.parse().unwrap_or(0u32),
                    minor.parse().unwrap_or(0u32),
                    0,
                )
            }
            None => (1, 0, 0, usize::MAX - f.pixels),
        };
        let mut sorted: Vec<&PixelFailure> = self.0.iter().collect();
        sorted.sort_by_key(|f| key(f));
        sorted
    }
}

/// A render that carried on past panicking pixels (see [`render_partial_with`]).
#[derive(Clone, Debug, PartialEq)]
pub struct PartialRender {
    /// Radiance; NaN in the pixels whose computation panicked.
    pub film: Film,
    /// Per pixel, row by row like [`Film::pixels`]: whether its computation panicked.
    pub panicked: Vec<bool>,
    /// What the panicked pixels failed on.
    pub failures: PixelFailures,
}

impl PartialRender {
    /// The image to look at: [`PANICKED_COLOUR`] where the computation panicked,
    /// [`NON_FINITE_COLOUR`] where the radiance is NaN or infinite, the radiance elsewhere.
    pub fn marked(&self) -> Film {
        let pixels = self.film.pixels.iter().enumerate();
        Film {
            pixels: pixels.map(|(i, &p)| self.mark(i).unwrap_or(p)).collect(),
            ..self.film.clone()
        }
    }

    /// The image to show after tone mapping: the radiance mapped by `tonemap` (a global tone
    /// map sees only the finished, finite pixels), then the marks of [`PartialRender::marked`]
    /// painted over it, so that they keep their colours under any tone map. Display values in
    /// `[0, 1]`, to write with the identity `ToneMap::Clamp { exposure: 1.0 }`.
    pub fn display(&self, tonemap: ToneMap) -> Film {
        let mapped = tonemap.apply(&self.film.pixels).into_iter().enumerate();
        Film {
            pixels: mapped.map(|(i, m)| self.mark(i).unwrap_or(m)).collect(),
            ..self.film.clone()
        }
    }

    /// The mark of pixel `index`, if it has one.
    fn mark(&self, index: usize) -> Option<Vec3> {
        if self.panicked[index] {
            Some(PANICKED_COLOUR)
        } else if !self.film.pixels[index].is_finite() {
            Some(NON_FINITE_COLOUR)
        } else {
            None
        }
    }

    /// Pixels whose computation finished with NaN or infinite radiance.
    pub fn non_finite_pixels(&self) -> usize {
        self.film
            .pixels
            .iter()
            .zip(&self.panicked)
            .filter(|&(p, &panicked)| !panicked && !p.is_finite())
            .count()
    }
}

/// Renders like [`render_with`], but a pixel whose computation panics (an unfinished
/// `todo!()` in a student's stub, or any other panic) does not stop the image: it gets NaN
/// radiance, is flagged in [`PartialRender::panicked`] and counted in
/// [`PartialRender::failures`], and no panic message is printed. A panic in `prepare` (the
/// camera of Exercise 1.2, say) fails every pixel. Deterministic: the same image and failures
/// on any number of threads.
pub fn render_partial_with<C: Sync>(
    settings: &RenderSettings,
    prepare: impl FnOnce() -> C,
    pixel: impl Fn(&C, u32, u32) -> Vec3 + Sync,
) -> Result<PartialRender, Error> {
    settings.validate()?;
    let pixels = settings.width as usize * settings.height as usize;
    let mut out = PartialRender {
        film: Film::new(settings.width, settings.height),
        panicked: vec![false; pixels],
        failures: PixelFailures::default(),
    };
    let prepared = match catch_panic(prepare) {
        Ok(prepared) => prepared,
        Err(panic) => {
            out.film.pixels.fill(Vec3::NAN);
            out.panicked.fill(true);
            out.failures.add(&panic, pixels);
            return Ok(out);
        }
    };
    let rendered = render_tiles(settings, |x, y| {
        // Boxed: the rare panic should not widen every pixel of the tile buffers.
        catch_panic(|| pixel(&prepared, x, y)).map_err(Box::new)
    });
    for (x, y, value) in rendered.into_iter().flatten() {
        let index = (y * settings.width + x) as usize;
        out.film.pixels[index] = match value {
            Ok(radiance) => radiance,
            Err(panic) => {
                out.panicked[index] = true;
                out.failures.add(&panic, 1);
                Vec3::NAN
            }
        };
    }
    Ok(out)
}

/// The image size of `settings`.
pub fn resolution(settings: &RenderSettings) -> UVec2 {
    UVec2::new(settings.width, settings.height)
}

/// `pixel(x, y)` of every pixel, tile by tile in parallel (with a progress bar when the
/// settings ask for one); the tiles in order, each row by row.
pub fn render_tiles<T: Send>(
    settings: &RenderSettings,
    pixel: impl Fn(u32, u32) -> T + Sync,
) -> Vec<Vec<(u32, u32, T)>> {
    let tiles: Vec<(u32, u32)> = (0..settings.height.div_ceil(TILE_SIZE))
        .flat_map(|ty| (0..settings.width.div_ceil(TILE_SIZE)).map(move |tx| (tx, ty)))
        .collect();
    let bar = Progress::new(tiles.len() as u64, settings.progress);
    let rendered = tiles
        .par_iter()
        .map(|&(tx, ty)| {
            let x_end = ((tx + 1) * TILE_SIZE).min(settings.width);
            let y_end = ((ty + 1) * TILE_SIZE).min(settings.height);
            let mut out = Vec::with_capacity((TILE_SIZE * TILE_SIZE) as usize);
            for y in ty * TILE_SIZE..y_end {
                for x in tx * TILE_SIZE..x_end {
                    out.push((x, y, pixel(x, y)));
                }
            }
            bar.inc();
            out
        })
        .collect();
    bar.finish();
    rendered
}
