//! Lab 04 — reflection and refraction: mirror reflection, refraction with the bookkeeping of
//! the medium's index of refraction, total internal reflection, and the Phong model
//! (docs/lab04.md).

use glam::Vec3;

use crate::lab02::LightSample;
use crate::math::Ray;
use crate::scene::Hit;

/// The two sides of a surface as a ray meets it (DTU `get_ior_out`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Interface {
    /// Unit normal on the side the ray comes from (`normal · direction ≤ 0`).
    pub normal: Vec3,
    /// Index of refraction of the medium the ray travels in, `η₁`.
    pub eta_incident: f32,
    /// Index of refraction on the other side, `η₂`.
    pub eta_transmitted: f32,
}

/// The lab's contract: what the student's `Student` implements, and the answer key's `Lab04`.
pub type Contract = dyn Reflection;

/// Lab 04's contract.
#[crate::contract]
pub trait Reflection: Send + Sync {
    /// Exercise 4.1 — the mirror direction of `direction` about the unit `normal`:
    /// `r = ω − 2(ω·n)n`.
    fn reflect(&self, direction: Vec3, normal: Vec3) -> Vec3;

    /// Exercise 4.2 — the reflected ray of `ray` at `hit` (DTU `trace_reflected` without the
    /// tracing): from the hit point along the mirror direction about the shading normal,
    /// valid on `[RAY_EPSILON, ∞)`.
    fn reflected_ray(&self, ray: &Ray, hit: &Hit) -> Ray;

    /// Exercise 4.3 — entering or leaving, with `n = hit.shading_normal`: a ray with
    /// `direction·n < 0` enters the material (from the medium of index `hit.ior` into
    /// `material_ior`); otherwise it leaves it (from `material_ior` into air, index 1) and the
    /// normal is flipped to face it.
    fn interface(&self, direction: Vec3, hit: &Hit, material_ior: f32) -> Interface;

    /// Exercise 4.4 — Snell's law: the refracted unit direction of the unit `direction`
    /// through a surface with unit `normal` facing the incident side, from index `eta_i` into
    /// `eta_t`; `None` for total internal reflection.
    fn refract(&self, direction: Vec3, normal: Vec3, eta_i: f32, eta_t: f32) -> Option<Vec3>;

    /// Exercise 4.5 — the refracted ray of `ray` at `hit` (DTU `trace_refracted` without the
    /// tracing): the ray from the hit point along the direction refracted about the shading
    /// normal (through [`interface`](Reflection::interface)), valid on
    /// `[RAY_EPSILON, ∞)`, with the index of refraction of the medium it enters; `None` for
    /// total internal reflection.
    fn refracted_ray(&self, ray: &Ray, hit: &Hit, material_ior: f32) -> Option<(Ray, f32)>;

    /// Exercise 4.6 — the (normalized) Phong model: radiance reflected towards `view` (unit,
    /// from the surface to the eye),
    /// `Σ (ρ_d/π + ρ_s·(s+2)/(2π)·max(0, r_i·v)^s) · L_i · max(0, n·ω_i)` with `r_i` the
    /// mirror direction of `−ω_i` about `n`.
    fn shade_phong(
        &self,
        rho_d: Vec3,
        rho_s: Vec3,
        shininess: f32,
        normal: Vec3,
        view: Vec3,
        lights: &[LightSample],
    ) -> Vec3;
}
