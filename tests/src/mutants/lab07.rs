//! Lab 07 variants.

use super::Verdict;
use framework::glam::{UVec2, Vec2, Vec3};
use framework::labs::lab07::Antialiasing;
use framework::sampling::Rng;
use reference::lab07::Lab07 as Reference;

impl Antialiasing for Variant {
    fn compute_jitters(&self, subdivisions: u32, rng: &mut Rng) -> Vec<Vec2> {
        Reference.compute_jitters(subdivisions, rng)
    }
    fn compute_pixel(
        &self,
        pixel: UVec2,
        jitters: &[Vec2],
        radiance: &mut dyn FnMut(Vec2) -> Vec3,
    ) -> Vec3 {
        Reference.compute_pixel(pixel, jitters, radiance)
    }
}

/// A lab 07 variant: the reference with some functions replaced.
#[derive(Clone, Copy)]
pub struct Variant {
    /// What the variant does.
    pub name: &'static str,
    /// Mistake or alternative.
    pub verdict: Verdict,
}

/// Every lab 07 variant.
pub fn variants() -> Vec<Variant> {
    Vec::new()
}
