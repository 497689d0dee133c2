//! # Lab 03 — shadows and area lights
//!
//! In lab 02 every light reached every surface that faced it. Now the framework asks your code
//! for a *shadow ray* towards each light sample and drops the samples whose ray is blocked
//! (`trace_to_any`, the DTU `RayTracer::trace_to_any`): hard shadows from point and
//! directional lights. Then the ceiling lamp of the Cornell box becomes an *area light*: the
//! framework draws `n × n` stratified samples of the unit square (your 3.2), picks a triangle of
//! the lamp by area, turns the sample into a point on it (your 3.3) and asks for the light that
//! point sends towards the surface (your 3.4) — soft shadows.
//!
//! Read `docs/lab03.md` first. Then fill in the functions below in order and run
//!
//! ```text
//! cargo test -p lab03                # all exercises
//! cargo test -p lab03 exercise_3_2   # one exercise
//! raylab render --scene cornell --lab 3 --pipeline student --light-samples 10
//! raylab report --lab 3 --pipeline student
//! ```

// The parameters of the stubs below are unused until you fill them in.
#![allow(unused_variables)]

use contracts::glam::{Vec2, Vec3};
use contracts::lab02::LightSample;
use contracts::lab03::Shadows;
use contracts::math::Ray;
use contracts::sampling::Rng;

/// Your shadow rays and area-light sampling. The framework calls them through the `Shadows`
/// trait.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Shadows for Student {
    /// **Exercise 3.1** — the shadow ray from a surface point towards a light sample
    /// (docs/lab03.md, §3.1; the DTU worksheet's hard shadows, ELUMI §4.2.2).
    ///
    /// `light` is what lab 02's `sample_point_light` / `sample_directional_light` (or 3.4)
    /// returned for this point: the unit `direction` towards the light and its `distance`
    /// (`f32::INFINITY` for a directional light). The point is in shadow when anything lies on
    /// the segment between it and the light, so the ray is
    ///
    /// ```text
    /// origin    = position
    /// direction = light.direction
    /// tmin      = RAY_EPSILON                    (contracts::math::RAY_EPSILON)
    /// tmax      = light.distance − RAY_EPSILON
    /// ```
    ///
    /// Why the offsets: `position` was computed in floating point and lies a hair above or
    /// below the surface; with `tmin = 0` the ray would hit the surface it starts on about half
    /// of the time (*shadow acne*). And the ray must stop short of the light: anything behind
    /// the light — the ceiling above a lamp, or the lamp's own triangle for an area light —
    /// does not cast a shadow. For a directional light `∞ − ε` stays `∞`, as it should.
    fn shadow_ray(&self, position: Vec3, light: &LightSample) -> Ray {
        todo!("Exercise 3.1: shadow_ray (docs/lab03.md, Exercise 3.1)")
    }

    /// **Exercise 3.2** — `n × n` stratified (jittered) samples of the unit square
    /// (docs/lab03.md, §3.2; ELUMI §2.3 and §4.2.2, Fig. 4.7).
    ///
    /// Cut `[0, 1)²` into `n × n` cells and put one uniformly random point in each:
    ///
    /// ```text
    /// for j in 0..n {            // rows
    ///     for i in 0..n {        // columns
    ///         let ξ = rng.next_vec2();
    ///         push( (i + ξ.x) / n,  (j + ξ.y) / n )
    ///     }
    /// }
    /// ```
    ///
    /// Return exactly `n²` points, one per cell. The jitter must come from `rng` (fresh
    /// numbers for every cell): cell centres would turn the area light into `n²` point
    /// lights and the penumbra into bands.
    fn stratified_samples(&self, n: u32, rng: &mut Rng) -> Vec<Vec2> {
        todo!("Exercise 3.2: stratified_samples (docs/lab03.md, Exercise 3.2)")
    }

    /// **Exercise 3.3** — a point on the triangle `v0 v1 v2`, uniformly distributed by area,
    /// from a uniform `u ∈ [0, 1)²` (docs/lab03.md, §3.3):
    ///
    /// ```text
    /// s = √u.x
    /// p = (1 − s)·v0 + s·(1 − u.y)·v1 + s·u.y·v2
    /// ```
    ///
    /// `s` picks the distance from `v0` across the triangle; the square root is there because
    /// the triangle's width grows linearly with that distance, so the far strips hold more
    /// area (the density of `s` must be `2s`). `u.y` then picks the point along the strip.
    fn sample_triangle(&self, triangle: [Vec3; 3], u: Vec2) -> Vec3 {
        todo!("Exercise 3.3: sample_triangle (docs/lab03.md, Exercise 3.3)")
    }

    /// **Exercise 3.4** — one sample of an area light seen from `position` (docs/lab03.md,
    /// §3.4). The point `light_point` on the light, with unit normal `light_normal` and
    /// emitted radiance `emission`, was chosen with density `pdf_area` per unit area (`1/A`
    /// for a light of area `A`). With `r = |light_point − position|` and
    /// `ω = (light_point − position)/r`, return
    ///
    /// ```text
    /// direction = ω
    /// distance  = r
    /// radiance  = emission · max(0, −light_normal · ω) / (r² · pdf_area)
    /// ```
    ///
    /// The Lambertian shader multiplies this by `ρ_d/π · cos θ` at the surface, which gives one
    /// term of the area-form estimator `L_r ≈ (1/N) Σ f_r L_e cos θ cos θ' / (r² p_A)`;
    /// `cos θ' = −n'·ω` is the cosine at the light (the light faces along its normal and
    /// sends nothing backwards). The framework weights each of the `n²` samples by `1/n²`.
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
