//! # Lab 07 — anti-aliasing
#![allow(unused_variables)]

use framework::glam::{UVec2, Vec2, Vec3};
use framework::labs::lab07::Antialiasing;
use framework::sampling::Rng;

/// Your pixel subdivision.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Antialiasing for Student {
    fn compute_jitters(&self, subdivisions: u32, rng: &mut Rng) -> Vec<Vec2> {
        todo!("Exercise 7.1: compute_jitters (docs/lab07.md, Exercise 7.1)")
    }
    fn compute_pixel(
        &self,
        pixel: UVec2,
        jitters: &[Vec2],
        radiance: &mut dyn FnMut(Vec2) -> Vec3,
    ) -> Vec3 {
        todo!("Exercise 7.2: compute_pixel (docs/lab07.md, Exercise 7.2)")
    }
}
