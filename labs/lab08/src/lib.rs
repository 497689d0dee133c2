//! # Lab 08 — photon-mapped caustics
//!
//! A glass sphere focuses the light that passes through it into a bright spot on the floor: a
//! *caustic*. A ray tracer that sends shadow rays to the lights cannot find it (the shadow ray
//! hits the glass), so here you trace light the other way, from the lights: photons emitted
//! from the lights, followed through mirrors and glass, and stored in a *photon map* where they
//! land on a diffuse surface after at least one specular bounce. While rendering, the density
//! of the photons near a shading point gives the caustic radiance, added to the direct light
//! (DTU `PointLight::emit`, `ParticleTracer::trace_particle`, `PhotonCaustics::shade`).
//!
//! The framework traces the photons, keeps the map (a k-d tree) and finds the photons nearest a
//! shading point; you write the four functions below. Read `docs/lab08.md` first. Then fill
//! them in order and run
//!
//! ```text
//! cargo test -p lab08                # all exercises
//! cargo test -p lab08 exercise_8_1   # one exercise
//! raylab render --lab 8 --pipeline student --scene cornell-spheres
//! ```

// The parameters of the stubs below are unused until you fill them in.
#![allow(unused_variables)]

use contracts::glam::Vec3;
use contracts::lab08::{EmittedPhoton, NearbyPhoton, PhotonMapping, Scatter};
use contracts::sampling::Rng;
use contracts::scene::PointLight;

/// Your photon mapping. The framework calls it through the `PhotonMapping` trait.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl PhotonMapping for Student {
    /// **Exercise 8.1** — a photon from a point light (docs/lab08.md, §8.1; DTU
    /// `PointLight::emit`).
    ///
    /// Pick a uniformly random direction by rejection sampling: draw points of the cube
    /// `[−1, 1]³` from `rng` until one lies inside the unit ball, and normalise it. The photon
    /// starts at the light's position (`Ray::unbounded(origin, direction, 0.0)`) and carries
    /// the light's power shared equally among the `emitted` photons.
    fn emit_point_light(&self, light: &PointLight, emitted: u32, rng: &mut Rng) -> EmittedPhoton {
        todo!("Exercise 8.1: emit_point_light (docs/lab08.md, Exercise 8.1)")
    }

    /// **Exercise 8.2** — a photon from an area light (docs/lab08.md, §8.2).
    ///
    /// The framework chose `position` on the light by area. Send the photon in a
    /// cosine-weighted direction about `normal` (`contracts::math::Onb` turns a local
    /// direction about the normal into a world one) from `position`, valid from `RAY_EPSILON`,
    /// carrying the light's power (radiance `emitted_radiance` over area `light_area`) shared
    /// equally among the `emitted` photons.
    fn emit_area_light(
        &self,
        position: Vec3,
        normal: Vec3,
        emitted_radiance: Vec3,
        light_area: f32,
        emitted: u32,
        rng: &mut Rng,
    ) -> EmittedPhoton {
        todo!("Exercise 8.2: emit_area_light (docs/lab08.md, Exercise 8.2)")
    }

    /// **Exercise 8.3** — Russian roulette at glass (docs/lab08.md, §8.3; DTU
    /// `ParticleTracer::trace_particle`).
    ///
    /// Reflect the photon with probability `reflectance`, refract it otherwise, with one
    /// number from `rng`. Return the choice and the power the photon carries on.
    fn russian_roulette(&self, reflectance: f32, power: Vec3, rng: &mut Rng) -> (Scatter, Vec3) {
        todo!("Exercise 8.3: russian_roulette (docs/lab08.md, Exercise 8.3)")
    }

    /// **Exercise 8.4** — the caustic radiance estimate (docs/lab08.md, §8.4; DTU
    /// `PhotonCaustics::shade`).
    ///
    /// `photons` are the at most `k` photons nearest to the shading point within
    /// `max_radius`, nearest first. Sum the power of those that arrived at the front of the
    /// surface (travelling against `normal`), divide by the area of the disc they were found
    /// in, and turn that irradiance into the radiance a diffuse surface of reflectance
    /// `diffuse` reflects. The disc's radius is the distance of the farthest photon when `k`
    /// were found, `max_radius` when fewer were. With no photons, or a disc of no area (radius
    /// 0: the `k` photons found all at the shading point, or `max_radius` 0), return zero.
    fn caustic_radiance(
        &self,
        diffuse: Vec3,
        normal: Vec3,
        photons: &[NearbyPhoton],
        k: usize,
        max_radius: f32,
    ) -> Vec3 {
        todo!("Exercise 8.4: caustic_radiance (docs/lab08.md, Exercise 8.4)")
    }
}
