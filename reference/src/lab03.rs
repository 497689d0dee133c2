//! Reference solution of lab 03 (docs/lab03.md).

use contracts::glam::{Vec2, Vec3};
use contracts::lab02::LightSample;
use contracts::lab03::Shadows;
use contracts::math::{RAY_EPSILON, Ray};
use contracts::sampling::Rng;

/// The reference shadow rays and area-light sampling.
#[derive(Clone, Copy, Debug, Default)]
pub struct Lab03;

impl Shadows for Lab03 {
    fn shadow_ray(&self, position: Vec3, light: &LightSample) -> Ray {
        Ray::new(
            position,
            light.direction,
            RAY_EPSILON,
            light.distance - RAY_EPSILON,
        )
    }

    fn stratified_samples(&self, n: u32, rng: &mut Rng) -> Vec<Vec2> {
        let cell = 1.0 / n as f32;
        let mut samples = Vec::with_capacity((n * n) as usize);
        for j in 0..n {
            for i in 0..n {
                let u = rng.next_vec2();
                samples.push((Vec2::new(i as f32, j as f32) + u) * cell);
            }
        }
        samples
    }

    fn sample_triangle(&self, [v0, v1, v2]: [Vec3; 3], u: Vec2) -> Vec3 {
        let s = u.x.sqrt();
        (1.0 - s) * v0 + s * (1.0 - u.y) * v1 + s * u.y * v2
    }

    fn area_light_sample(
        &self,
        position: Vec3,
        light_point: Vec3,
        light_normal: Vec3,
        emission: Vec3,
        pdf_area: f32,
    ) -> LightSample {
        let to_light = light_point - position;
        let distance = to_light.length();
        let direction = to_light / distance;
        let cos_light = (-light_normal.dot(direction)).max(0.0);
        LightSample {
            direction,
            distance,
            radiance: emission * cos_light / (distance * distance * pdf_area),
        }
    }
}
