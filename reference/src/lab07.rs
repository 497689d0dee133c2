//! Reference solution of lab 07 (docs/lab07.md).

use contracts::glam::{UVec2, Vec2, Vec3};
use contracts::lab03::Shadows;
use contracts::lab07::Antialiasing;
use contracts::sampling::Rng;

/// The reference pixel subdivision.
#[derive(Clone, Copy, Debug, Default)]
pub struct Lab07;

impl Antialiasing for Lab07 {
    /// Jittered subpixel offsets are the stratified samples of lab 03 over the pixel.
    fn compute_jitters(&self, subdivisions: u32, rng: &mut Rng) -> Vec<Vec2> {
        crate::lab03::Lab03.stratified_samples(subdivisions, rng)
    }

    fn compute_pixel(
        &self,
        pixel: UVec2,
        jitters: &[Vec2],
        radiance: &mut dyn FnMut(Vec2) -> Vec3,
    ) -> Vec3 {
        let corner = pixel.as_vec2();
        let sum: Vec3 = jitters.iter().map(|&j| radiance(corner + j)).sum();
        sum / jitters.len() as f32
    }
}
