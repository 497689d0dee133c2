//! # Lab 03 — shadows and area lights
#![allow(unused_variables)]

use framework::glam::{Vec2, Vec3};
use framework::labs::lab02::LightSample;
use framework::labs::lab03::Shadows;
use framework::math::Ray;
use framework::sampling::Rng;

/// Your shadow rays and area-light sampling.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Shadows for Student {
    fn shadow_ray(&self, position: Vec3, light: &LightSample) -> Ray {
        todo!("Exercise 3.1: shadow_ray (docs/lab03.md, Exercise 3.1)")
    }
    fn stratified_samples(&self, n: u32, rng: &mut Rng) -> Vec<Vec2> {
        todo!("Exercise 3.2: stratified_samples (docs/lab03.md, Exercise 3.2)")
    }
    fn sample_triangle(&self, triangle: [Vec3; 3], u: Vec2) -> Vec3 {
        todo!("Exercise 3.3: sample_triangle (docs/lab03.md, Exercise 3.3)")
    }
    fn area_light_sample(
        &self,
        position: Vec3,
        light_point: Vec3,
        light_normal: Vec3,
        emission: Vec3,
        pdf_area: f32,
    ) -> LightSample {
        todo!("Exercise 3.4: area_light_sample (docs/lab03.md, Exercise 3.4)")
    }
}
