//! Lab 12 — path tracing: the BSDF of a diffuse and glossy surface (its value, its density and
//! a direction drawn from it), next-event estimation from emissive triangles (a point drawn on
//! a triangle, its density per solid angle), multiple importance sampling with the power
//! heuristic, Russian roulette by throughput, and the path estimator that puts them together
//! (docs/lab12.md).
//!
//! From lab 12 on the integrator (`Pipeline::radiance`) is a path tracer: for each camera ray
//! it calls [`PathTracing::path_radiance`] with the scene's queries and the lab's other
//! functions as closures.
//!
//! Directions leave the surface: `wo` points back along the path (towards the camera), `wi`
//! towards where light comes from; both are unit vectors. The `normal` is the shading normal,
//! unit length, on the side of `wo`.

use glam::Vec3;

use crate::math::Ray;
use crate::sampling::Rng;

/// A surface as the path tracer shades it: a Lambertian base under a glossy lobe about the
/// mirror direction (the normalised Phong lobe of Lafortune and Willems), docs/lab12.md,
/// "The material".
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PathMaterial {
    /// Diffuse reflectance `ρ_d` (`Kd`).
    pub diffuse: Vec3,
    /// Glossy reflectance `ρ_s` (`Ks`).
    pub glossy: Vec3,
    /// The glossy lobe's exponent `n`, from the roughness `r` as `n = 2/r² − 2`.
    pub exponent: f32,
}

/// The BSDF of a pair of directions: its value and the density with which
/// [`PathTracing::sample_bsdf`] draws the second.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BsdfValue {
    /// `f(wo, wi)`, per steradian, without the cosine of `wi`.
    pub value: Vec3,
    /// The density of `wi` per unit solid angle.
    pub pdf: f32,
}

/// A direction drawn from the BSDF, with the BSDF's value and density there.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BsdfSample {
    /// `wi`, unit length, above the surface.
    pub direction: Vec3,
    /// `f(wo, wi)`: the whole BSDF, not the lobe that drew `wi`.
    pub value: Vec3,
    /// The density of `wi` per unit solid angle: the mixture's, not the lobe's.
    pub pdf: f32,
}

/// A point drawn on a light, seen from the shaded point.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EmitterSample {
    /// Unit direction from the shaded point to the point on the light.
    pub direction: Vec3,
    /// The distance to it (infinite for a directional light).
    pub distance: f32,
    /// The radiance the emitter sends back along `direction`; for a delta light the
    /// irradiance it delivers to a surface facing it (`I/d²` of a point light).
    pub radiance: Vec3,
    /// The density of `direction` per unit solid angle; for a delta light the probability
    /// with which it was chosen.
    pub pdf: f32,
    /// A point or directional light, which no direction drawn from a BSDF can hit: only
    /// next-event estimation finds its light, so its sample has weight one.
    pub delta: bool,
}

/// A surface point a path meets.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PathVertex {
    /// Where the ray met the surface.
    pub position: Vec3,
    /// The unit shading normal, on the side the ray came from.
    pub normal: Vec3,
    /// The surface.
    pub material: PathMaterial,
    /// The radiance the surface emits back along the ray (black unless it is an emitter seen
    /// from its front).
    pub emitted: Vec3,
    /// The density per unit solid angle with which the light sampler draws this point from
    /// the ray's origin (0 unless it is an emitter seen from its front).
    pub light_pdf: f32,
}

/// What a ray of a path finds.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum PathHit {
    /// A surface.
    Surface(PathVertex),
    /// Nothing: the ray left the scene. `radiance` is what arrives along it from the sky
    /// (black without one), `light_pdf` the density with which the light sampler draws its
    /// direction.
    Escaped {
        /// The sky's radiance along the ray.
        radiance: Vec3,
        /// The light sampler's density of the ray's direction.
        light_pdf: f32,
    },
}

/// A pixel's running statistics (Welford's): how many estimates it has, their mean, and the
/// sum of their squared deviations from the mean.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PixelStatistics {
    /// The number of estimates `n`.
    pub count: u32,
    /// Their mean, per channel.
    pub mean: Vec3,
    /// `Σ (xᵢ − mean)²`, per channel.
    pub m2: Vec3,
}

/// A sky's brightness as a distribution over its latitude–longitude image: a row drawn by its
/// marginal, then a texel of that row by the row's conditional (docs/lab12.md, "The sky").
/// Texel `(x, y)` covers `u ∈ [x/w, (x + 1)/w)`, `v ∈ [y/h, (y + 1)/h)`; row 0 is the top
/// (`θ = 0`, +y).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SkyDistribution {
    /// Texels per row, `w`.
    pub width: u32,
    /// Rows, `h`.
    pub height: u32,
    /// The rows' cumulative distribution: `h + 1` values from 0 to 1; row `y` has the
    /// probability `marginal[y + 1] − marginal[y]`.
    pub marginal: Vec<f32>,
    /// Each row's cumulative distribution over its texels, `w + 1` values from 0 to 1 per row,
    /// row `y`'s from index `y·(w + 1)`.
    pub conditional: Vec<f32>,
}

impl SkyDistribution {
    /// Row `y`'s conditional cumulative distribution (`w + 1` values).
    pub fn row(&self, y: usize) -> &[f32] {
        let stride = self.width as usize + 1;
        &self.conditional[y * stride..(y + 1) * stride]
    }

    /// Why this is not a distribution over a `width × height` image, if it is not: wrong
    /// lengths, a table that does not run from 0 to 1, or one that falls.
    pub fn defect(&self) -> Option<String> {
        let (w, h) = (self.width as usize, self.height as usize);
        if w == 0 || h == 0 {
            return Some(format!("it is {w} × {h} texels"));
        }
        if self.marginal.len() != h + 1 || self.conditional.len() != h * (w + 1) {
            return Some(format!(
                "it has {} marginal and {} conditional values; a {w} × {h} sky has {} and {}",
                self.marginal.len(),
                self.conditional.len(),
                h + 1,
                h * (w + 1)
            ));
        }
        let table = |cdf: &[f32], what: String| {
            let (first, last) = (cdf[0], cdf[cdf.len() - 1]);
            if first != 0.0 || (last - 1.0).abs().is_nan() || (last - 1.0).abs() > 1e-4 {
                return Some(format!("{what} runs from {first} to {last}, not from 0 to 1"));
            }
            let falls = cdf.windows(2).position(|p| p[1].is_nan() || p[1] < p[0]);
            falls.map(|i| format!("{what} falls from {} to {} at {}", cdf[i], cdf[i + 1], i + 1))
        };
        table(&self.marginal, "the marginal".into())
            .or_else(|| (0..h).find_map(|y| table(self.row(y), format!("row {y}'s conditional"))))
    }
}

/// A direction drawn from the sky.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SkySample {
    /// The unit direction towards the sky.
    pub direction: Vec3,
    /// Its density per unit solid angle.
    pub pdf: f32,
}

/// The lab's contract: what the student's `Student` implements, and the answer key's `Lab12`.
pub type Contract = dyn PathTracing;

/// Lab 12's contract: one method per exercise.
#[crate::contract]
pub trait PathTracing: Send + Sync {
    /// **Exercise 12.1** — the luminance of a linear RGB colour (docs/lab12.md, §12.1).
    fn luminance(&self, colour: Vec3) -> f32;

    /// **Exercise 12.2** — the BSDF of `material` for light arriving from `wi` and leaving
    /// towards `wo`: its value `ρ_d/π + ρ_s (n + 2)/(2π) cos^n α` (`α` the angle between `wi`
    /// and the mirror direction of `wo`, `cos α` clamped at 0) and the density of the
    /// mixture [`PathTracing::sample_bsdf`] draws from. Zero value and density when `wi` or
    /// `wo` is below the surface.
    fn bsdf(&self, material: &PathMaterial, normal: Vec3, wo: Vec3, wi: Vec3) -> BsdfValue;

    /// **Exercise 12.3** — a direction `wi` drawn from the BSDF: the glossy lobe with
    /// probability `P_s = Σρ_s / (Σρ_d + Σρ_s)` (one `rng.next_f32()`), otherwise the
    /// cosine-weighted hemisphere, the direction from one `rng.next_vec2()`; with the BSDF's
    /// value and the mixture's density there. `None` when `wi` falls below the surface.
    fn sample_bsdf(
        &self,
        material: &PathMaterial,
        normal: Vec3,
        wo: Vec3,
        rng: &mut Rng,
    ) -> Option<BsdfSample>;

    /// **Exercise 12.4** — a point drawn uniformly on the emissive `triangle` (one
    /// `rng.next_vec2()`), seen from `position`, and its density per unit solid angle. The
    /// triangle emits `radiance` on the side its normal `(v1 − v0) × (v2 − v0)` faces; `None`
    /// when `position` sees its back or it has no area.
    fn sample_emitter(
        &self,
        triangle: [Vec3; 3],
        radiance: Vec3,
        position: Vec3,
        rng: &mut Rng,
    ) -> Option<EmitterSample>;

    /// **Exercise 12.5** — the density per unit solid angle with which
    /// [`PathTracing::sample_emitter`] draws the point at `distance` along the unit
    /// `direction` from `position`, a point of `triangle` (for a ray that found it by
    /// sampling the BSDF): 0 when `position` sees the triangle's back.
    fn emitter_pdf(&self, triangle: [Vec3; 3], position: Vec3, direction: Vec3, distance: f32)
    -> f32;

    /// **Exercise 12.6** — the power heuristic's weight (β = 2) of a sample drawn with density
    /// `pdf` by one strategy, when another, one sample too, would draw it with `other_pdf`.
    fn power_heuristic(&self, pdf: f32, other_pdf: f32) -> f32;

    /// **Exercise 12.7** — Russian roulette by throughput: the path goes on with probability
    /// `q = min(1, max(throughput))` (one `rng.next_f32()`), and then its throughput is divided
    /// by `q`: `Some(1/q)`; `None` when it ends.
    fn roulette(&self, throughput: Vec3, rng: &mut Rng) -> Option<f32>;

    /// **Exercise 12.8** — the radiance arriving along the camera `ray`, by a path of at most
    /// `max_depth` bounces: at each vertex found by `trace`, the emitted light weighted by the
    /// power heuristic against the light sampler (in full at the first vertex), next-event
    /// estimation with a point from `sample_light` whose shadow ray `occluded` lets through,
    /// weighted against the BSDF's density from `bsdf`, then the next direction from
    /// `sample_bsdf`, and from the third bounce on `roulette`. A delta light's sample has
    /// weight one (no BSDF sample can find it). The closures are the scene's
    /// queries and Exercises 12.2–12.7's functions (docs/lab12.md, §12.8).
    #[allow(clippy::too_many_arguments)]
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
    ) -> Vec3;

    /// **Exercise 12.9** — `stats` with one more estimate `radiance`, by Welford's update:
    /// `n += 1`, `mean += (x − mean)/n`, `m2 += (x − mean_old)(x − mean_new)` per channel.
    fn accumulate(&self, stats: &PixelStatistics, radiance: Vec3) -> PixelStatistics;

    /// **Exercise 12.10** — the relative standard error of the pixel's mean: the largest over
    /// the channels of `√(s²/n) / mean`, `s² = m2/(n − 1)`; a channel whose mean is 0 counts 0;
    /// infinite with fewer than two estimates.
    fn relative_error(&self, stats: &PixelStatistics) -> f32;

    /// **Exercise 12.11** — the distribution of a sky's brightness over its `width × height`
    /// latitude–longitude image, `luminance` row by row from the top: texel `(x, y)` weighs
    /// `luminance · sin θ_y`, `θ_y = π (y + ½)/h`. The marginal over the rows and each row's
    /// conditional, as cumulative tables from 0 to 1; a row that weighs nothing uniform, and a
    /// sky that weighs nothing uniform in both.
    fn sky_distribution(&self, luminance: &[f32], width: u32, height: u32) -> SkyDistribution;

    /// **Exercise 12.12** — a direction drawn from `sky` (one `rng.next_vec2()`: the row from
    /// its first number by the marginal, the texel from its second by the row's conditional,
    /// each at a continuous position within its cell), through lab 11's latitude–longitude
    /// mapping, with its density per unit solid angle `p(u, v)/(2π² sin θ)`. `None` where
    /// `sin θ` or the density is 0.
    fn sample_sky(&self, sky: &SkyDistribution, rng: &mut Rng) -> Option<SkySample>;

    /// **Exercise 12.13** — the density per unit solid angle with which
    /// [`PathTracing::sample_sky`] draws the unit `direction` (for a ray that left the scene
    /// along it); 0 where `sin θ` is 0.
    fn sky_pdf(&self, sky: &SkyDistribution, direction: Vec3) -> f32;
}
