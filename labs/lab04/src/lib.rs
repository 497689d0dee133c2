//! # Lab 04 — reflection and refraction
//!
//! Until now every ray stopped at the first surface it hit. In this lab the shaders spawn new
//! rays: a mirror sends the ray on in the mirror direction, glass bends it into the material
//! by Snell's law (or, past the critical angle, reflects it totally), and a glossy surface
//! adds a Phong highlight. The framework's integrator does the recursion (DTU
//! `RayTracer::trace_reflected`, `trace_refracted` and the shaders' `shade_new_ray`); your code
//! computes the new rays and the Phong model:
//!
//! - `illum 3` (mirror): the radiance along [`reflected_ray`](Reflection::reflected_ray);
//! - `illum 4` (glass): the radiance along [`refracted_ray`](Reflection::refracted_ray), or
//!   along the reflected ray under total internal reflection;
//! - `illum 2` (Phong): [`shade_phong`](Reflection::shade_phong);
//! - `illum 5` (glossy): `0.1·Phong + 0.1·reflected + 0.9·refracted`.
//!
//! Past `max_depth` bounces the integrator returns black, so two facing mirrors end.
//!
//! Read `docs/lab04.md` first. Then fill in the functions below in order and run
//!
//! ```text
//! cargo test -p lab04                # all exercises
//! cargo test -p lab04 exercise_4_4   # one exercise
//! raylab render --lab 4 --pipeline student
//! ```
//!
//! Directions are unit vectors. `ω` (`ray.direction`, `direction`) points the way the light
//! travels in the ray tracer: from the eye *towards* the surface.

// The parameters of the stubs below are unused until you fill them in.
#![allow(unused_variables)]

use contracts::glam::Vec3;
use contracts::lab02::LightSample;
use contracts::lab04::{Interface, Reflection};
use contracts::math::Ray;
use contracts::scene::Hit;

/// Your reflection, refraction and Phong shading. The framework calls them through the
/// `Reflection` trait.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Reflection for Student {
    /// **Exercise 4.1** — the law of reflection (docs/lab04.md, §4.1).
    ///
    /// The mirror direction keeps the part of `ω` along the surface and flips the part along
    /// the unit normal `n`:
    ///
    /// ```text
    /// r = ω − 2(ω·n)n
    /// ```
    ///
    /// (Heckbert's form in the ELUMI thesis, eq. 4.8: `c₁ = −n·ω`, `r = ω + 2c₁n`.) The
    /// result is a unit vector with `r·n = −ω·n`, in the plane of `ω` and `n`; it does not
    /// matter which side `n` faces.
    fn reflect(&self, direction: Vec3, normal: Vec3) -> Vec3 {
        todo!("Exercise 4.1: reflect (docs/lab04.md, Exercise 4.1)")
    }

    /// **Exercise 4.2** — the reflected ray (docs/lab04.md, §4.2; DTU
    /// `RayTracer::trace_reflected` without the tracing).
    ///
    /// The ray starts at the hit point `hit.position` and goes in the mirror direction of
    /// `ray.direction` about the **shading** normal `hit.shading_normal`. It must not hit the
    /// surface it starts on: give it a small positive `tmin` (`RAY_EPSILON` from
    /// `contracts::math`) and an unbounded `tmax` (`Ray::unbounded` does both). Do not copy
    /// `ray.tmax`: after the closest-hit search it is the distance to this hit.
    fn reflected_ray(&self, ray: &Ray, hit: &Hit) -> Ray {
        todo!("Exercise 4.2: reflected_ray (docs/lab04.md, Exercise 4.2)")
    }

    /// **Exercise 4.3** — entering or leaving (docs/lab04.md, §4.3; DTU
    /// `RayTracer::get_ior_out`).
    ///
    /// The shading normal `n = hit.shading_normal` points out of the material. With `ω =
    /// direction`:
    ///
    /// ```text
    /// ω·n < 0   the ray enters:  normal =  n, η₁ = hit.ior,      η₂ = material_ior
    /// ω·n ≥ 0   the ray leaves:  normal = −n, η₁ = material_ior, η₂ = 1 (air)
    /// ```
    ///
    /// `hit.ior` is the index of the medium the ray travelled in before the hit. The returned
    /// normal always faces the incoming ray, as `refract` expects.
    fn interface(&self, direction: Vec3, hit: &Hit, material_ior: f32) -> Interface {
        todo!("Exercise 4.3: interface (docs/lab04.md, Exercise 4.3)")
    }

    /// **Exercise 4.4** — Snell's law in vector form (docs/lab04.md, §4.4).
    ///
    /// `normal` faces the incident side (`ω·n ≤ 0`); `η = η₁/η₂ = eta_i/eta_t`. With
    /// `cos θ₁ = −ω·n`:
    ///
    /// ```text
    /// sin²θ₂ = η²(1 − cos²θ₁)              Snell: η₁ sin θ₁ = η₂ sin θ₂
    /// sin²θ₂ > 1  →  None                  total internal reflection
    /// cos θ₂ = √(1 − sin²θ₂)
    /// t = η ω + (η cos θ₁ − cos θ₂) n      a unit vector on the far side (t·n < 0)
    /// ```
    ///
    /// Total internal reflection happens exactly when `sin θ₁ > η₂/η₁` (only possible when
    /// `η₁ > η₂`); return `None` then, never a vector holding NaN.
    fn refract(&self, direction: Vec3, normal: Vec3, eta_i: f32, eta_t: f32) -> Option<Vec3> {
        todo!("Exercise 4.4: refract (docs/lab04.md, Exercise 4.4)")
    }

    /// **Exercise 4.5** — the refracted ray (docs/lab04.md, §4.5; DTU
    /// `RayTracer::trace_refracted` without the tracing).
    ///
    /// Use `interface` to find the normal facing the ray and the two indices, then `refract`.
    /// Return `None` under total internal reflection (the integrator then reflects); otherwise
    /// the ray from `hit.position` along the refracted direction on `[RAY_EPSILON, ∞)`,
    /// together with the index of the medium it now travels in, `η₂` (it becomes the next
    /// hit's `hit.ior`).
    fn refracted_ray(&self, ray: &Ray, hit: &Hit, material_ior: f32) -> Option<(Ray, f32)> {
        todo!("Exercise 4.5: refracted_ray (docs/lab04.md, Exercise 4.5)")
    }

    /// **Exercise 4.6** — the normalized Phong model (docs/lab04.md, §4.6; DTU
    /// `Phong::shade`).
    ///
    /// `view` is the unit direction from the surface to the eye (`−ω`); each light sample
    /// gives the direction `ω_i` towards the light and its radiance `L_i`. With `r_i` the
    /// mirror direction of `−ω_i` about `n` (the way the light bounces off):
    ///
    /// ```text
    /// L_r = Σ_i ( ρ_d/π + ρ_s · (s+2)/(2π) · max(0, r_i·v)^s ) · L_i · max(0, n·ω_i)
    /// ```
    ///
    /// The factor `(s+2)/(2π)` normalizes the lobe (it keeps the reflected energy independent
    /// of the shininess `s`). Lights below the surface (`n·ω_i ≤ 0`) contribute nothing.
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
