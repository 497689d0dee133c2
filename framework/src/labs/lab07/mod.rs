//! Lab 07 — anti-aliasing by pixel subdivision with jittered samples (docs/lab07.md).

pub mod checks;
mod golden;

pub use golden::generate_golden;

use glam::{UVec2, Vec2, Vec3};

use crate::sampling::Rng;

/// Lab 07's contract.
pub trait Antialiasing: Send + Sync {
    /// Exercise 7.1 — `compute_jitters`: for a pixel divided into `s × s` subpixels, one
    /// uniformly random offset in each subpixel, in pixel units (`[0, 1)²`), drawing
    /// `rng.next_vec2()` once per subpixel, subpixels in row-major order.
    fn compute_jitters(&self, subdivisions: u32, rng: &mut Rng) -> Vec<Vec2>;

    /// Exercise 7.2 — `compute_pixel`: the average of the radiance arriving through the raster
    /// positions `pixel + jitter` for every jitter (`radiance` traces the camera ray through a
    /// raster position).
    fn compute_pixel(
        &self,
        pixel: UVec2,
        jitters: &[Vec2],
        radiance: &mut dyn FnMut(Vec2) -> Vec3,
    ) -> Vec3;
}
