//! # Lab 12 — Path tracing
//!
//! Read `docs/lab12.md` first. Then fill in the functions below in order and run
//!
//! ```text
//! cargo test -p lab12                 # all exercises
//! cargo test -p lab12 exercise_12_3   # one exercise
//! cargo run --release -p raylab -- report --lab 12 --pipeline student
//! ```
//!
//! `wo` points back along the path, `wi` towards the light; both are unit vectors, and
//! `normal` is the unit shading normal on the side of `wo`.

// The parameters of the stubs below are unused until you fill them in.
#![allow(unused_variables)]

use contracts::glam::Vec3;
use contracts::lab12::{
    BsdfSample, BsdfValue, EmitterSample, PathHit, PathMaterial, PathTracing, PathVertex,
    PixelStatistics, SkyDistribution, SkySample,
};
use contracts::math::Ray;
use contracts::sampling::Rng;

/// Your code of lab 12. The framework calls it through the `PathTracing` trait.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl PathTracing for Student {
    /// **Exercise 12.1** — the luminance of a linear RGB colour (docs/lab12.md, §12.1).
    ///
    /// ```text
    /// Y = 0.2126 R + 0.7152 G + 0.0722 B
    /// ```
    fn luminance(&self, colour: Vec3) -> f32 {
        todo!("Exercise 12.1: luminance (docs/lab12.md, Exercise 12.1)")
    }

    /// **Exercise 12.2** — the BSDF's value and density for the pair `wo`, `wi`
    /// (docs/lab12.md, §12.2):
    ///
    /// ```text
    /// f   = ρ_d/π + ρ_s (n + 2)/(2π) cos^n α          r = 2 (n·wo) n − wo, cos α = max(0, r·wi)
    /// pdf = (1 − P_s) cos θ_i/π + P_s (n + 1)/(2π) cos^n α      P_s = Σρ_s / (Σρ_d + Σρ_s)
    /// ```
    ///
    /// Both are zero when `wi` or `wo` is below the surface.
    fn bsdf(&self, material: &PathMaterial, normal: Vec3, wo: Vec3, wi: Vec3) -> BsdfValue {
        todo!("Exercise 12.2: bsdf (docs/lab12.md, Exercise 12.2)")
    }

    /// **Exercise 12.3** — a direction drawn from the BSDF (docs/lab12.md, §12.3): choose the
    /// glossy lobe with probability `P_s` from one `rng.next_f32()`, then draw the direction
    /// from one `rng.next_vec2()` — about the mirror direction with `cos α = ξ₁^(1/(n+1))`, or
    /// cosine-weighted about the normal. Return the whole BSDF's value and the mixture's
    /// density at the direction drawn; `None` when it is below the surface.
    fn sample_bsdf(
        &self,
        material: &PathMaterial,
        normal: Vec3,
        wo: Vec3,
        rng: &mut Rng,
    ) -> Option<BsdfSample> {
        todo!("Exercise 12.3: sample_bsdf (docs/lab12.md, Exercise 12.3)")
    }

    /// **Exercise 12.4** — a uniform point on the emitting `triangle` from one
    /// `rng.next_vec2()`, as a direction and distance from `position`, with the emitted
    /// `radiance` and the density per unit solid angle (docs/lab12.md, §12.4):
    ///
    /// ```text
    /// pdf_ω = d² / (A cos θ_l)     θ_l between the triangle's normal and the way back to `position`
    /// ```
    ///
    /// `None` when `position` sees the triangle's back or the triangle has no area.
    fn sample_emitter(
        &self,
        triangle: [Vec3; 3],
        radiance: Vec3,
        position: Vec3,
        rng: &mut Rng,
    ) -> Option<EmitterSample> {
        todo!("Exercise 12.4: sample_emitter (docs/lab12.md, Exercise 12.4)")
    }

    /// **Exercise 12.5** — the density per unit solid angle with which `sample_emitter` would
    /// draw the point at `distance` along `direction` from `position` on `triangle`
    /// (docs/lab12.md, §12.5); 0 from the triangle's back.
    fn emitter_pdf(
        &self,
        triangle: [Vec3; 3],
        position: Vec3,
        direction: Vec3,
        distance: f32,
    ) -> f32 {
        todo!("Exercise 12.5: emitter_pdf (docs/lab12.md, Exercise 12.5)")
    }

    /// **Exercise 12.6** — the power heuristic's weight of a sample drawn with density `pdf`,
    /// against a strategy that draws it with `other_pdf` (docs/lab12.md, §12.6):
    ///
    /// ```text
    /// w = pdf² / (pdf² + other_pdf²)
    /// ```
    fn power_heuristic(&self, pdf: f32, other_pdf: f32) -> f32 {
        todo!("Exercise 12.6: power_heuristic (docs/lab12.md, Exercise 12.6)")
    }

    /// **Exercise 12.7** — Russian roulette (docs/lab12.md, §12.7): go on with probability
    /// `q = min(1, max(throughput))`, drawn with one `rng.next_f32()`, and return `Some(1/q)`,
    /// the factor that keeps the estimate unbiased; `None` when the path ends.
    fn roulette(&self, throughput: Vec3, rng: &mut Rng) -> Option<f32> {
        todo!("Exercise 12.7: roulette (docs/lab12.md, Exercise 12.7)")
    }

    /// **Exercise 12.8** — the radiance arriving along the camera `ray` by a path of at most
    /// `max_depth` bounces (docs/lab12.md, §12.8). Call only the closures (they are the
    /// scene and Exercises 12.2–12.7), never your own functions above. At each vertex
    /// `trace` finds:
    ///
    /// ```text
    /// L += β · L_e · w         w = 1 for the camera ray, else power_heuristic(p_bsdf, light_pdf)
    /// L += β · f · L_l · cos θ / p_l · power_heuristic(p_l, p_f)   if the shadow ray is free
    ///                                                   (weight 1 for a delta light)
    /// β *= f · cos θ / p        the next direction from sample_bsdf
    /// ```
    ///
    /// and from the third bounce on `roulette` may end the path or scale `β`.
    fn path_radiance(
        &self,
        ray: &Ray,
        max_depth: u32,
        trace: &dyn Fn(&Ray) -> PathHit,
        occluded: &dyn Fn(&Ray) -> bool,
        sample_light: &dyn Fn(Vec3, &mut Rng) -> Option<EmitterSample>,
        sample_bsdf: &dyn Fn(&PathVertex, Vec3, &mut Rng) -> Option<BsdfSample>,
        bsdf: &dyn Fn(&PathVertex, Vec3, Vec3) -> BsdfValue,
        power_heuristic: &dyn Fn(f32, f32) -> f32,
        roulette: &dyn Fn(Vec3, &mut Rng) -> Option<f32>,
        rng: &mut Rng,
    ) -> Vec3 {
        todo!("Exercise 12.8: path_radiance (docs/lab12.md, Exercise 12.8)")
    }

    /// **Exercise 12.9** — `stats` with one more estimate `radiance` (docs/lab12.md, §12.9), by
    /// Welford's update, per channel:
    ///
    /// ```text
    /// n' = n + 1,   mean' = mean + (x − mean)/n',   m2' = m2 + (x − mean)(x − mean')
    /// ```
    fn accumulate(&self, stats: &PixelStatistics, radiance: Vec3) -> PixelStatistics {
        todo!("Exercise 12.9: accumulate (docs/lab12.md, Exercise 12.9)")
    }

    /// **Exercise 12.10** — the relative standard error of the pixel's mean
    /// (docs/lab12.md, §12.10): the largest over the channels of
    ///
    /// ```text
    /// √(s²/n) / mean,   s² = m2/(n − 1)
    /// ```
    ///
    /// a channel of mean 0 counting 0; `f32::INFINITY` with fewer than two estimates.
    fn relative_error(&self, stats: &PixelStatistics) -> f32 {
        todo!("Exercise 12.10: relative_error (docs/lab12.md, Exercise 12.10)")
    }

    /// **Exercise 12.11** — the distribution of the sky's brightness over its
    /// `width × height` latitude–longitude image (docs/lab12.md, §12.11). Texel `(x, y)` is
    /// `luminance[y·width + x]` and weighs
    ///
    /// ```text
    /// luminance · sin θ_y,   θ_y = π (y + ½)/height
    /// ```
    ///
    /// Return the rows' cumulative table (`height + 1` values, 0 to 1) and each row's
    /// (`width + 1` values per row, 0 to 1); a row, or a sky, that weighs nothing is uniform.
    fn sky_distribution(&self, luminance: &[f32], width: u32, height: u32) -> SkyDistribution {
        todo!("Exercise 12.11: sky_distribution (docs/lab12.md, Exercise 12.11)")
    }

    /// **Exercise 12.12** — a direction drawn from the sky (docs/lab12.md, §12.12): with one
    /// `rng.next_vec2()`, the row from its first number by the marginal, the texel from its
    /// second by the row's conditional, each at a continuous position in its cell; then
    ///
    /// ```text
    /// θ = π v,  φ = 2π (u − ½),  d = (sin θ sin φ, cos θ, −sin θ cos φ)
    /// pdf = p(u, v) / (2π² sin θ),   p(u, v) = P(row) · P(texel | row) · width · height
    /// ```
    ///
    /// `None` where `sin θ` or `p(u, v)` is 0.
    fn sample_sky(&self, sky: &SkyDistribution, rng: &mut Rng) -> Option<SkySample> {
        todo!("Exercise 12.12: sample_sky (docs/lab12.md, Exercise 12.12)")
    }

    /// **Exercise 12.13** — the density per unit solid angle with which `sample_sky` draws
    /// the unit `direction` (docs/lab12.md, §12.13): its texel's `p(u, v)/(2π² sin θ)`, and
    /// 0 where `sin θ` is 0.
    fn sky_pdf(&self, sky: &SkyDistribution, direction: Vec3) -> f32 {
        todo!("Exercise 12.13: sky_pdf (docs/lab12.md, Exercise 12.13)")
    }
}
