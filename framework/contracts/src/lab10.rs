//! Lab 10 — Fresnel reflectance and absorption (docs/lab10.md).
//!
//! With a pipeline at lab 10 or later the integrator weights the reflected and the refracted
//! ray of a dielectric (`illum 4`, 5, 11, 12) by the Fresnel reflectance `R` and `1 − R` —
//! [`Fresnel::fresnel_reflectance`] at the cosine of incidence and the two indices that lab
//! 04's `interface` gives — instead of lab 04's fixed weights, and attenuates the radiance
//! that crossed an absorbing volume (`illum 11`, 12) by [`Fresnel::transmittance`] over the
//! distance travelled inside it. Photon tracing takes the same transmittance
//! (`Pipeline::medium_transmittance`).
//!
//! The cosines are of the angles between the rays and the normal: `cos θ₁ ≥ 0` of the
//! incident ray, `cos θ₂ ≥ 0` of the transmitted one, `η₁` the index of refraction of the
//! medium the light comes from, `η₂` of the other side.

use glam::Vec3;

use crate::scene::Material;

/// The lab's contract: what the student's `Student` implements, and the answer key's `Lab10`.
pub type Contract = dyn Fresnel;

/// Lab 10's contract (DTU `fresnel.h` and `Volume::get_transmittance`).
#[crate::contract]
pub trait Fresnel: Send + Sync {
    /// Exercise 10.1 — `fresnel_r_s`: the Fresnel amplitude reflection coefficient `r_s` of
    /// light polarised perpendicular to the plane of incidence, from `cos θ₁`, `cos θ₂`
    /// (related by Snell's law), `η₁` and `η₂`. A signed amplitude, not squared: negative
    /// when the light enters a denser medium (docs/lab10.md, §10.1).
    fn fresnel_r_s(&self, cos_theta_i: f32, cos_theta_t: f32, eta_i: f32, eta_t: f32) -> f32;

    /// Exercise 10.2 — `fresnel_r_p`: the amplitude reflection coefficient `r_p` of light
    /// polarised parallel to the plane of incidence, with the sign convention of the DTU
    /// framework (`r_p = −r_s` at normal incidence); zero at Brewster's angle (docs/lab10.md,
    /// §10.2).
    fn fresnel_r_p(&self, cos_theta_i: f32, cos_theta_t: f32, eta_i: f32, eta_t: f32) -> f32;

    /// Exercise 10.3 — `fresnel_R`: the reflectance of unpolarised light, the mean of the two
    /// polarisations' reflectances (the squared amplitudes of Exercises 10.1 and 10.2), in
    /// `[0, 1]` (docs/lab10.md, §10.3).
    #[allow(non_snake_case)]
    fn fresnel_R(&self, cos_theta_i: f32, cos_theta_t: f32, eta_i: f32, eta_t: f32) -> f32;

    /// Exercise 10.4 — `fresnel_reflectance`: the reflectance `R` of the interface for light
    /// arriving at `cos θ₁ = cos_theta_i` from index `eta_i` into `eta_t`, with `cos θ₂` from
    /// Snell's law; `1` under total internal reflection (DTU `trace_refracted`'s `R`;
    /// docs/lab10.md, §10.4). The integrator calls it at every dielectric.
    fn fresnel_reflectance(&self, cos_theta_i: f32, eta_i: f32, eta_t: f32) -> f32;

    /// Exercise 10.5 — `transmittance`: the fraction of radiance, per colour channel, that
    /// crosses `distance` inside an absorbing medium of `material` (the Bouguer–Lambert–Beer
    /// law, with the DTU framework's absorption coefficient from the diffuse colour
    /// `material.diffuse` in `[0, 1]`; DTU `Volume::get_transmittance`; docs/lab10.md, §10.5).
    fn transmittance(&self, distance: f32, material: &Material) -> Vec3;
}
