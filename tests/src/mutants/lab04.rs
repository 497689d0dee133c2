//! Lab 04 variants.

use super::Verdict;
use framework::glam::Vec3;
use framework::labs::lab02::LightSample;
use framework::labs::lab04::{Interface, Reflection};
use framework::math::{Hit, Ray};
use reference::lab04::Lab04 as Reference;

impl Reflection for Variant {
    fn reflect(&self, direction: Vec3, normal: Vec3) -> Vec3 {
        Reference.reflect(direction, normal)
    }
    fn reflected_ray(&self, ray: &Ray, hit: &Hit) -> Ray {
        Reference.reflected_ray(ray, hit)
    }
    fn interface(&self, direction: Vec3, hit: &Hit, material_ior: f32) -> Interface {
        Reference.interface(direction, hit, material_ior)
    }
    fn refract(&self, direction: Vec3, normal: Vec3, eta_i: f32, eta_t: f32) -> Option<Vec3> {
        Reference.refract(direction, normal, eta_i, eta_t)
    }
    fn refracted_ray(&self, ray: &Ray, hit: &Hit, material_ior: f32) -> Option<(Ray, f32)> {
        Reference.refracted_ray(ray, hit, material_ior)
    }
    fn shade_phong(
        &self,
        rho_d: Vec3,
        rho_s: Vec3,
        shininess: f32,
        normal: Vec3,
        view: Vec3,
        lights: &[LightSample],
    ) -> Vec3 {
        Reference.shade_phong(rho_d, rho_s, shininess, normal, view, lights)
    }
}

/// A lab 04 variant: the reference with some functions replaced.
#[derive(Clone, Copy)]
pub struct Variant {
    /// What the variant does.
    pub name: &'static str,
    /// Mistake or alternative.
    pub verdict: Verdict,
}

/// Every lab 04 variant.
pub fn variants() -> Vec<Variant> {
    Vec::new()
}
