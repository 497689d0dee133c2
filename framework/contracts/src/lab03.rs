//! Lab 03 — shadows: shadow rays for point and directional lights, and soft shadows from area
//! lights sampled with stratified jittered samples (docs/lab03.md).
//!
//! The integrator (`Pipeline::light_samples`) drops every light sample whose [`shadow_ray`]
//! is blocked (`trace_to_any`). An area light is sampled `n × n` times per shading point: the
//! unit-square samples of [`stratified_samples`] choose a triangle by area
//! (`AreaLight::pick_face`) and a point on it ([`sample_triangle`]), with density `1/A`;
//! [`area_light_sample`] turns the point into a [`LightSample`], weighted by `1/n²`, that the
//! Lambertian shader of lab 02 shades.
//!
//! [`shadow_ray`]: Shadows::shadow_ray
//! [`stratified_samples`]: Shadows::stratified_samples
//! [`sample_triangle`]: Shadows::sample_triangle
//! [`area_light_sample`]: Shadows::area_light_sample

use glam::{Vec2, Vec3};

use crate::lab02::LightSample;
use crate::math::Ray;
use crate::sampling::Rng;

/// The lab's contract: what the student's `Student` implements, and the answer key's `Lab03`.
pub type Contract = dyn Shadows;

/// Lab 03's contract.
#[crate::contract]
pub trait Shadows: Send + Sync {
    /// Exercise 3.1 — the shadow ray from a surface point towards a light sample: it starts at
    /// `position`, goes along `light.direction`, and is valid on
    /// `[RAY_EPSILON, light.distance − RAY_EPSILON]` (the offset keeps the surface from
    /// shadowing itself; for a directional light the interval stays unbounded). The checks
    /// accept `tmin ∈ [1e-5, 1e-3]` and `tmax` between `1e-6·max(1, d)` and `1e-3·max(1, d)`
    /// short of the distance `d`.
    fn shadow_ray(&self, position: Vec3, light: &LightSample) -> Ray;

    /// Exercise 3.2 — `n × n` stratified jittered samples of the unit square: one uniformly
    /// random point in each cell `[i/n, (i+1)/n) × [j/n, (j+1)/n)`, drawing `rng.next_vec2()`
    /// once per cell, cells in row-major order (`j` outer, `i` inner).
    fn stratified_samples(&self, n: u32, rng: &mut Rng) -> Vec<Vec2>;

    /// Exercise 3.3 — a point on a triangle, uniformly distributed by area, from
    /// `u ∈ [0, 1)²`: `(1 − √u₁)·v0 + √u₁(1 − u₂)·v1 + √u₁·u₂·v2`.
    fn sample_triangle(&self, triangle: [Vec3; 3], u: Vec2) -> Vec3;

    /// Exercise 3.4 — one sample of an area light seen from `position`: the point
    /// `light_point` on the light, with unit normal `light_normal` and emitted radiance
    /// `emission`, was chosen with probability density `pdf_area` (per unit area). Return the
    /// direction towards it, its distance `r`, and the radiance that, put through the
    /// Lambertian shader (which multiplies by `ρ_d/π · cos θ`), gives the area-form estimator:
    /// `L_e · max(0, −n_y·ω) / (r² · pdf_area)`.
    fn area_light_sample(
        &self,
        position: Vec3,
        light_point: Vec3,
        light_normal: Vec3,
        emission: Vec3,
        pdf_area: f32,
    ) -> LightSample;
}
