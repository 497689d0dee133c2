//! Lab 07 — anti-aliasing by pixel subdivision with jittered samples (docs/lab07.md).
//!
//! With a pipeline at lab 7 or later and `RenderSettings::pixel_subdivisions = s > 1`, the
//! renderer (`render::render_pixel`) asks [`Antialiasing::compute_jitters`] for `s²` offsets
//! inside the pixel, then [`Antialiasing::compute_pixel`] for the average of the radiance
//! through them. `raylab render --subdivisions S` sets `s`.

use glam::{UVec2, Vec2, Vec3};

use crate::sampling::Rng;

/// The lab's contract: what the student's `Student` implements, and the answer key's `Lab07`.
pub type Contract = dyn Antialiasing;

/// Lab 07's contract (DTU `RayCaster::compute_jitters` and `RayCaster::compute_pixel`).
#[crate::contract]
pub trait Antialiasing: Send + Sync {
    /// Exercise 7.1 — `compute_jitters`: for a pixel divided into `s × s` subpixels, one
    /// uniformly random offset in each subpixel, in pixel units (`[0, 1)²`), drawing
    /// `rng.next_vec2()` once per subpixel, subpixels in row-major order. The numbers come from
    /// `rng` itself, not a copy: the renderer goes on drawing from it (area-light samples).
    ///
    /// Subpixel `(i, j)` gets `((i + ξ.x)/s, (j + ξ.y)/s)`. The checks judge only where the
    /// jitters lie (one per subpixel, uniform within it, independent), so another order of the
    /// subpixels or of the random numbers is equally correct.
    fn compute_jitters(&self, subdivisions: u32, rng: &mut Rng) -> Vec<Vec2>;

    /// Exercise 7.2 — `compute_pixel`: the average of the radiance arriving through the raster
    /// positions `pixel + jitter` for every jitter (`radiance` traces the camera ray through a
    /// raster position).
    ///
    /// `pixel` is the pixel's top-left corner in raster space (y down), so the result is
    /// `(1/N) Σ_k radiance(pixel + jitter_k)` with `N = jitters.len()`.
    fn compute_pixel(
        &self,
        pixel: UVec2,
        jitters: &[Vec2],
        radiance: &mut dyn FnMut(Vec2) -> Vec3,
    ) -> Vec3;
}
