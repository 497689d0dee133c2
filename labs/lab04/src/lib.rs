//! # Lab 04 — reflection and refraction
#![allow(unused_variables)]

use framework::glam::Vec3;
use framework::labs::lab02::LightSample;
use framework::labs::lab04::{Interface, Reflection};
use framework::math::{Hit, Ray};

/// Your reflection, refraction and Phong shading.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Reflection for Student {
    fn reflect(&self, direction: Vec3, normal: Vec3) -> Vec3 {
        todo!("Exercise 4.1: reflect (docs/lab04.md, Exercise 4.1)")
    }
    fn reflected_ray(&self, ray: &Ray, hit: &Hit) -> Ray {
        todo!("Exercise 4.2: reflected_ray (docs/lab04.md, Exercise 4.2)")
    }
    fn interface(&self, direction: Vec3, hit: &Hit, material_ior: f32) -> Interface {
        todo!("Exercise 4.3: interface (docs/lab04.md, Exercise 4.3)")
    }
    fn refract(&self, direction: Vec3, normal: Vec3, eta_i: f32, eta_t: f32) -> Option<Vec3> {
        todo!("Exercise 4.4: refract (docs/lab04.md, Exercise 4.4)")
    }
    fn refracted_ray(&self, ray: &Ray, hit: &Hit, material_ior: f32) -> Option<(Ray, f32)> {
        todo!("Exercise 4.5: refracted_ray (docs/lab04.md, Exercise 4.5)")
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
        todo!("Exercise 4.6: shade_phong (docs/lab04.md, Exercise 4.6)")
    }
}
