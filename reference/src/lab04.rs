//! Reference solution of lab 04 (docs/lab04.md).

use std::f32::consts::PI;

use contracts::glam::Vec3;
use contracts::lab02::LightSample;
use contracts::lab04::{Interface, Reflection};
use contracts::math::{RAY_EPSILON, Ray};
use contracts::scene::Hit;

/// The reference reflection, refraction and Phong shading.
#[derive(Clone, Copy, Debug, Default)]
pub struct Lab04;

impl Reflection for Lab04 {
    fn reflect(&self, direction: Vec3, normal: Vec3) -> Vec3 {
        direction - 2.0 * direction.dot(normal) * normal
    }

    fn reflected_ray(&self, ray: &Ray, hit: &Hit) -> Ray {
        Ray::unbounded(
            hit.position,
            self.reflect(ray.direction, hit.shading_normal),
            RAY_EPSILON,
        )
    }

    fn interface(&self, direction: Vec3, hit: &Hit, material_ior: f32) -> Interface {
        let n = hit.shading_normal;
        if direction.dot(n) < 0.0 {
            Interface {
                normal: n,
                eta_incident: hit.ior,
                eta_transmitted: material_ior,
            }
        } else {
            Interface {
                normal: -n,
                eta_incident: material_ior,
                eta_transmitted: 1.0,
            }
        }
    }

    fn refract(&self, direction: Vec3, normal: Vec3, eta_i: f32, eta_t: f32) -> Option<Vec3> {
        let eta = eta_i / eta_t;
        let cos_i = -direction.dot(normal);
        let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
        if sin2_t > 1.0 {
            return None;
        }
        let cos_t = (1.0 - sin2_t).sqrt();
        Some((eta * direction + (eta * cos_i - cos_t) * normal).normalize())
    }

    fn refracted_ray(&self, ray: &Ray, hit: &Hit, material_ior: f32) -> Option<(Ray, f32)> {
        let side = self.interface(ray.direction, hit, material_ior);
        let direction = self.refract(
            ray.direction,
            side.normal,
            side.eta_incident,
            side.eta_transmitted,
        )?;
        Some((
            Ray::unbounded(hit.position, direction, RAY_EPSILON),
            side.eta_transmitted,
        ))
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
        let diffuse = rho_d / PI;
        let glossy_norm = (shininess + 2.0) / (2.0 * PI);
        lights
            .iter()
            .map(|l| {
                let cos_i = normal.dot(l.direction);
                if cos_i <= 0.0 {
                    return Vec3::ZERO;
                }
                let r = self.reflect(-l.direction, normal);
                let highlight = r.dot(view).max(0.0).powf(shininess);
                (diffuse + rho_s * glossy_norm * highlight) * l.radiance * cos_i
            })
            .sum()
    }
}
