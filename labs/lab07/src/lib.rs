//! # Lab 07 — anti-aliasing
//!
//! One ray through the centre of each pixel samples the image at one point per pixel, so
//! every edge comes out as a staircase ("jaggies"), and detail smaller than a pixel flickers
//! in and out. Here you divide each pixel into `s × s` subpixels, shoot one ray through a
//! random point of each subpixel (*jittered*, or *stratified*, sampling) and average
//! (DTU `RayCaster::compute_jitters` and `RayCaster::compute_pixel`). The framework calls
//! your two functions for every pixel when the pipeline is at lab 7 and `s > 1`.
//!
//! Read `docs/lab07.md` first. Then fill in the functions below in order and run
//!
//! ```text
//! cargo test -p lab07                # both exercises
//! cargo test -p lab07 exercise_7_1   # one exercise
//! raylab render --lab 7 --pipeline student --subdivisions 4
//! ```
//!
//! Raster positions are in pixels, with `(0, 0)` at the top-left corner of the image and
//! y pointing down; pixel `(x, y)` covers `[x, x + 1) × [y, y + 1)`.

// The parameters of the stubs below are unused until you fill them in.
#![allow(unused_variables)]

use contracts::glam::{UVec2, Vec2, Vec3};
use contracts::lab07::Antialiasing;
use contracts::sampling::Rng;

/// Your pixel subdivision. The framework calls it through the `Antialiasing` trait.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Antialiasing for Student {
    /// **Exercise 7.1** — jittered subpixel offsets (docs/lab07.md, §7.1; DTU
    /// `RayCaster::compute_jitters`).
    ///
    /// Divide the pixel `[0, 1)²` into `s × s` subpixels of side `1/s`, `s = subdivisions`.
    /// Subpixel `(i, j)` covers `[i/s, (i+1)/s) × [j/s, (j+1)/s)`. Put one uniformly random
    /// point in each:
    ///
    /// ```text
    /// ξ = rng.next_vec2()                       a fresh one for every subpixel
    /// jitter(i, j) = ((i + ξ.x)/s, (j + ξ.y)/s)
    /// ```
    ///
    /// Return the `s²` jitters, subpixels in row-major order (`j` outer, `i` inner). The
    /// checks only look at where the jitters lie, so another order is fine too.
    fn compute_jitters(&self, subdivisions: u32, rng: &mut Rng) -> Vec<Vec2> {
        todo!("Exercise 7.1: compute_jitters (docs/lab07.md, Exercise 7.1)")
    }

    /// **Exercise 7.2** — the pixel value (docs/lab07.md, §7.2; DTU
    /// `RayCaster::compute_pixel`).
    ///
    /// `radiance(raster)` traces the camera ray through a raster position and returns the
    /// radiance arriving along it. The jitters are offsets from the pixel's top-left corner,
    /// so the ray of jitter `j` goes through `pixel + j`. The pixel value is the average
    ///
    /// ```text
    /// L_pixel = (1/N) · Σ_k radiance(pixel + jitter_k),     N = jitters.len() = s²
    /// ```
    ///
    /// (`pixel.as_vec2()` turns the pixel's integer coordinates into a `Vec2`.)
    fn compute_pixel(
        &self,
        pixel: UVec2,
        jitters: &[Vec2],
        radiance: &mut dyn FnMut(Vec2) -> Vec3,
    ) -> Vec3 {
        todo!("Exercise 7.2: compute_pixel (docs/lab07.md, Exercise 7.2)")
    }
}
