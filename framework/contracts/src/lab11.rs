//! Lab 11 — ambient occlusion and HDR light probes: directions drawn over the hemisphere (by
//! rejection and cosine-weighted), the accessibility of a surface point and its bent normal,
//! the RGBE pixels of a Radiance file, and the two light-probe mappings between directions
//! and texture coordinates (docs/lab11.md).
//!
//! The integrator (`Pipeline::radiance`, from lab 11 on, in a scene with an
//! `EnvironmentMap` of `raylab-core`) looks the probe up for every ray that
//! leaves the scene — the background, and what mirrors and glass show — and shades a
//! Lambertian surface with [`shade_ambient_occlusion`] of its [`ambient_occlusion`], whose
//! rays it traces with `trace_to_any`.
//!
//! Texture coordinates of a probe are image coordinates: `u` from the left edge (0) to the
//! right (1), `v` from the top row (0) to the bottom (1). The world is y-up and the camera of
//! a probe looks along −z.
//!
//! [`shade_ambient_occlusion`]: AmbientOcclusion::shade_ambient_occlusion
//! [`ambient_occlusion`]: AmbientOcclusion::ambient_occlusion

use glam::{Vec2, Vec3};

use crate::math::Ray;
use crate::sampling::Rng;

/// A direction drawn over a hemisphere and the probability density (per steradian) with
/// which the sampler draws it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HemisphereSample {
    /// The unit direction.
    pub direction: Vec3,
    /// Its probability density per unit solid angle.
    pub pdf: f32,
}

/// What ambient occlusion finds at a surface point.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Occlusion {
    /// The accessibility `A ∈ [0, 1]`: the cosine-weighted fraction of the hemisphere from
    /// which the environment is seen (1 on an open plane).
    pub accessibility: f32,
    /// The bent normal: the unit, cosine-weighted mean direction of the unoccluded rays (the
    /// surface normal when every ray is occluded).
    pub bent_normal: Vec3,
}

/// Which hemisphere sampler the integrator's ambient occlusion draws its directions with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum HemisphereSampler {
    /// Uniform directions by rejection (Exercise 11.1).
    Rejection,
    /// Cosine-weighted directions (Exercise 11.2).
    #[default]
    Cosine,
}

/// The lab's contract: what the student's `Student` implements, and the answer key's `Lab11`.
pub type Contract = dyn AmbientOcclusion;

/// Lab 11's contract: one method per exercise.
#[crate::contract]
pub trait AmbientOcclusion: Send + Sync {
    /// Exercise 11.1 — a direction uniformly distributed over the hemisphere about the unit
    /// `normal` (density `1/(2π)`), by rejection: draw points of the cube `[−1, 1]³` with
    /// three `rng.next_f32()` each until one lies inside the unit ball and on the normal's
    /// side, and return it normalized, with its density.
    fn sample_hemisphere_rejection(&self, normal: Vec3, rng: &mut Rng) -> HemisphereSample;

    /// Exercise 11.2 — a cosine-weighted direction about the unit `normal` (density
    /// `cos θ/π`, `θ` the angle to the normal) from one `rng.next_vec2()`, with its density.
    fn sample_hemisphere_cosine(&self, normal: Vec3, rng: &mut Rng) -> HemisphereSample;

    /// Exercise 11.3 — the accessibility and bent normal at `position` on a surface with unit
    /// `normal`, from `samples` rays: each draws a direction with `sampler(rng)`, leaves
    /// `position` along it (`tmin = RAY_EPSILON`, no `tmax`), and counts where
    /// `occluded(&ray)` is false. The estimate must be right for any sampler whose `pdf` is
    /// its density.
    fn ambient_occlusion(
        &self,
        position: Vec3,
        normal: Vec3,
        samples: u32,
        sampler: &dyn Fn(&mut Rng) -> HemisphereSample,
        occluded: &dyn Fn(&Ray) -> bool,
        rng: &mut Rng,
    ) -> Occlusion;

    /// Exercise 11.4 — the linear RGB of one Radiance RGBE pixel `[r, g, b, e]`: three 8-bit
    /// mantissas and a shared exponent biased by 128 (`e = 0` is black).
    fn rgbe_to_rgb(&self, rgbe: [u8; 4]) -> Vec3;

    /// Exercise 11.5 — the texture coordinates of the unit `direction` in an angular map
    /// (Debevec's light probe): the centre `(½, ½)` is −z, the distance from the centre is
    /// proportional to the angle from −z, reaching ½ (the rim) at +z; +x is to the right and
    /// +y up.
    fn angular_map_uv(&self, direction: Vec3) -> Vec2;

    /// Exercise 11.6 — the unit direction of the texture coordinates `uv` of an angular map,
    /// the inverse of Exercise 11.5; `None` outside the map's disc.
    fn angular_map_direction(&self, uv: Vec2) -> Option<Vec3>;

    /// Exercise 11.7 — the texture coordinates of the unit `direction` in a latitude–longitude
    /// map: `v` grows with the angle from +y (0 at +y, 1 at −y), `u` with the azimuth about
    /// +y, `u = ½` at −z and `u` growing towards +x.
    fn latlong_uv(&self, direction: Vec3) -> Vec2;

    /// Exercise 11.8 — the unit direction of the texture coordinates `uv` of a
    /// latitude–longitude map, the inverse of Exercise 11.7.
    fn latlong_direction(&self, uv: Vec2) -> Vec3;

    /// Exercise 11.9 — the radiance a Lambertian surface of reflectance `diffuse` reflects
    /// under an environment, by ambient occlusion: the environment's radiance is taken as
    /// `environment` (looked up along the bent normal) wherever it is seen.
    fn shade_ambient_occlusion(
        &self,
        diffuse: Vec3,
        occlusion: &Occlusion,
        environment: Vec3,
    ) -> Vec3;
}
