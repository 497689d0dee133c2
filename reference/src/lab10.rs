//! Reference solution of lab 10 (docs/lab10.md).

use contracts::glam::Vec3;
use contracts::lab10::Fresnel;
use contracts::scene::Material;

/// Below this diffuse reflectance a channel absorbs everything it can (DTU
/// `Volume::get_transmittance`).
const MIN_REFLECTANCE: f32 = 1e-6;
/// The absorption coefficient of a channel whose reflectance is below [`MIN_REFLECTANCE`].
const MAX_ABSORPTION: f32 = 1e7;

/// The reference Fresnel reflectance and absorption.
#[derive(Clone, Copy, Debug, Default)]
pub struct Lab10;

impl Fresnel for Lab10 {
    fn fresnel_r_s(&self, cos_theta_i: f32, cos_theta_t: f32, eta_i: f32, eta_t: f32) -> f32 {
        let (a, b) = (eta_i * cos_theta_i, eta_t * cos_theta_t);
        (a - b) / (a + b)
    }

    fn fresnel_r_p(&self, cos_theta_i: f32, cos_theta_t: f32, eta_i: f32, eta_t: f32) -> f32 {
        let (a, b) = (eta_t * cos_theta_i, eta_i * cos_theta_t);
        (a - b) / (a + b)
    }

    fn fresnel_R(&self, cos_theta_i: f32, cos_theta_t: f32, eta_i: f32, eta_t: f32) -> f32 {
        let r_s = self.fresnel_r_s(cos_theta_i, cos_theta_t, eta_i, eta_t);
        let r_p = self.fresnel_r_p(cos_theta_i, cos_theta_t, eta_i, eta_t);
        0.5 * (r_s * r_s + r_p * r_p)
    }

    fn fresnel_reflectance(&self, cos_theta_i: f32, eta_i: f32, eta_t: f32) -> f32 {
        let eta = eta_i / eta_t;
        let sin2_t = eta * eta * (1.0 - cos_theta_i * cos_theta_i).max(0.0);
        if sin2_t >= 1.0 {
            return 1.0;
        }
        let cos_theta_t = (1.0 - sin2_t).sqrt();
        self.fresnel_R(cos_theta_i, cos_theta_t, eta_i, eta_t)
    }

    fn transmittance(&self, distance: f32, material: &Material) -> Vec3 {
        let sigma = material.diffuse.to_array().map(|rho| {
            if rho < MIN_REFLECTANCE {
                MAX_ABSORPTION
            } else {
                1.0 / rho - 1.0
            }
        });
        Vec3::from(sigma.map(|s| (-s * distance).exp()))
    }
}
