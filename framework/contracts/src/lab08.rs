//! Lab 08 — photon-mapped caustics (docs/lab08.md).
//!
//! Before a render at lab 8 or later, the framework's photon tracer
//! (the `pipeline` crate's `photon::trace_caustic_photons`) emits photons from the scene's point and area
//! lights through [`PhotonMapping::emit_point_light`] and [`PhotonMapping::emit_area_light`],
//! follows each through mirrors and glass, asking [`PhotonMapping::russian_roulette`] at every
//! glass surface whether it is reflected or refracted, and stores it at the first diffuse
//! surface it reaches after at least one specular bounce: the caustic photon map. While
//! shading a diffuse surface, the integrator finds the `k` photons of the map nearest to the
//! shading point within a maximum radius and asks [`PhotonMapping::caustic_radiance`] for the
//! radiance they reflect, which it adds to the direct lighting.
//!
//! `raylab render --photons N --photon-k K --photon-radius R` sets the number emitted, `k` and
//! the maximum radius.

use glam::Vec3;

use crate::math::Ray;
use crate::sampling::Rng;
use crate::scene::PointLight;

/// A photon leaving a light: the ray it travels along and the power (radiant flux, W per
/// channel) it carries.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EmittedPhoton {
    /// From the point of emission along the unit direction of travel.
    pub ray: Ray,
    /// The photon's power `Φ_p`.
    pub power: Vec3,
}

/// What a photon does at a glass surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Scatter {
    /// It is reflected about the surface.
    Reflect,
    /// It is refracted into the other medium.
    Refract,
}

/// A photon of the map found near a shading point.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct NearbyPhoton {
    /// The power the photon carries.
    pub power: Vec3,
    /// The unit direction the photon travelled in when it arrived (towards the surface).
    pub direction: Vec3,
    /// The squared distance from the shading point to where the photon was stored.
    pub distance_squared: f32,
}

/// The lab's contract: what the student's `Student` implements, and the answer key's `Lab08`.
pub type Contract = dyn PhotonMapping;

/// Lab 08's contract (DTU `PointLight::emit`, `ParticleTracer::trace_particle`'s roulette and
/// `PhotonCaustics::shade`).
#[crate::contract]
pub trait PhotonMapping: Send + Sync {
    /// Exercise 8.1 — a photon from the isotropic point `light`, one of `emitted` photons the
    /// light sends out: from the light's position in a uniformly random direction (rejection
    /// sampling in the unit ball, drawing from `rng`), carrying an equal share of the light's
    /// power.
    fn emit_point_light(&self, light: &PointLight, emitted: u32, rng: &mut Rng) -> EmittedPhoton;

    /// Exercise 8.2 — a photon from an area light of total area `light_area` and uniform
    /// radiance `emitted_radiance`, one of `emitted` photons the light sends out. The
    /// framework has chosen the point `position` on the light (uniformly by area) and its unit
    /// `normal` (the side that emits); the photon leaves it in a cosine-weighted random
    /// direction about the normal (drawing from `rng`), carrying an equal share of the light's
    /// power.
    fn emit_area_light(
        &self,
        position: Vec3,
        normal: Vec3,
        emitted_radiance: Vec3,
        light_area: f32,
        emitted: u32,
        rng: &mut Rng,
    ) -> EmittedPhoton;

    /// Exercise 8.3 — Russian roulette at a glass surface whose reflectance is `reflectance`
    /// (`R ∈ [0, 1]`): reflect the photon with probability `R`, refract it otherwise, drawing
    /// from `rng`; returns the choice and the power the photon carries on (`power` arrived).
    fn russian_roulette(&self, reflectance: f32, power: Vec3, rng: &mut Rng) -> (Scatter, Vec3);

    /// Exercise 8.4 — the caustic radiance reflected by a diffuse surface of reflectance
    /// `diffuse` and unit `normal` from the photons near the shading point: `photons` are the
    /// at most `k` photons of the map nearest to it within `max_radius`, nearest first.
    ///
    /// The zero-radius rule: when the disc of the estimate has no area (`r² = 0`: the `k`
    /// photons found all lie at the shading point, or fewer were found and `max_radius` is 0),
    /// the estimate is zero, as it is without photons.
    fn caustic_radiance(
        &self,
        diffuse: Vec3,
        normal: Vec3,
        photons: &[NearbyPhoton],
        k: usize,
        max_radius: f32,
    ) -> Vec3;
}
