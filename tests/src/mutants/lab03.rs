//! Lab 03 variants.

use super::Verdict;
use framework::glam::{Vec2, Vec3};
use framework::labs::lab02::LightSample;
use framework::labs::lab03::Shadows;
use framework::math::Ray;
use framework::sampling::Rng;
use reference::lab03::Lab03 as Reference;

impl Shadows for Variant {
    fn shadow_ray(&self, position: Vec3, light: &LightSample) -> Ray {
        Reference.shadow_ray(position, light)
    }
    fn stratified_samples(&self, n: u32, rng: &mut Rng) -> Vec<Vec2> {
        Reference.stratified_samples(n, rng)
    }
    fn sample_triangle(&self, triangle: [Vec3; 3], u: Vec2) -> Vec3 {
        Reference.sample_triangle(triangle, u)
    }
    fn area_light_sample(
        &self,
        position: Vec3,
        light_point: Vec3,
        light_normal: Vec3,
        emission: Vec3,
        pdf_area: f32,
    ) -> LightSample {
        Reference.area_light_sample(position, light_point, light_normal, emission, pdf_area)
    }
}

/// A lab 03 variant: the reference with some functions replaced.
#[derive(Clone, Copy)]
pub struct Variant {
    /// What the variant does.
    pub name: &'static str,
    /// Mistake or alternative.
    pub verdict: Verdict,
}

/// Every lab 03 variant.
pub fn variants() -> Vec<Variant> {
    Vec::new()
}
