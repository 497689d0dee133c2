//! Reference solution of lab 08 (docs/lab08.md).

use std::f32::consts::PI;

use contracts::glam::Vec3;
use contracts::lab08::{EmittedPhoton, NearbyPhoton, PhotonMapping, Scatter};
use contracts::math::{Onb, RAY_EPSILON, Ray};
use contracts::sampling::Rng;
use contracts::scene::PointLight;

/// The reference photon emission, roulette and radiance estimate.
#[derive(Clone, Copy, Debug, Default)]
pub struct Lab08;

impl PhotonMapping for Lab08 {
    fn emit_point_light(&self, light: &PointLight, emitted: u32, rng: &mut Rng) -> EmittedPhoton {
        let direction = loop {
            let p = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - Vec3::ONE;
            let l2 = p.length_squared();
            if l2 <= 1.0 && l2 > 1e-12 {
                break p / l2.sqrt();
            }
        };
        EmittedPhoton {
            ray: Ray::unbounded(light.position, direction, 0.0),
            power: 4.0 * PI * light.intensity / emitted as f32,
        }
    }

    fn emit_area_light(
        &self,
        position: Vec3,
        normal: Vec3,
        emitted_radiance: Vec3,
        light_area: f32,
        emitted: u32,
        rng: &mut Rng,
    ) -> EmittedPhoton {
        let (u1, u2) = (rng.next_f32(), rng.next_f32());
        let r = u1.sqrt();
        let phi = 2.0 * PI * u2;
        let local = Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt());
        let direction = Onb::from_w(normal).to_world(local).normalize();
        EmittedPhoton {
            ray: Ray::unbounded(position, direction, RAY_EPSILON),
            power: PI * emitted_radiance * light_area / emitted as f32,
        }
    }

    fn russian_roulette(&self, reflectance: f32, power: Vec3, rng: &mut Rng) -> (Scatter, Vec3) {
        if rng.next_f32() < reflectance {
            (Scatter::Reflect, power)
        } else {
            (Scatter::Refract, power)
        }
    }

    fn caustic_radiance(
        &self,
        diffuse: Vec3,
        normal: Vec3,
        photons: &[NearbyPhoton],
        k: usize,
        max_radius: f32,
    ) -> Vec3 {
        let r2 = if photons.len() >= k {
            photons
                .iter()
                .map(|p| p.distance_squared)
                .fold(0.0, f32::max)
        } else {
            max_radius * max_radius
        };
        if r2 <= 0.0 {
            return Vec3::ZERO;
        }
        let flux: Vec3 = photons
            .iter()
            .filter(|p| p.direction.dot(normal) < 0.0)
            .map(|p| p.power)
            .sum();
        diffuse / PI * flux / (PI * r2)
    }
}
