//! # Lab 10 — Fresnel reflectance and absorption
//!
//! Lab 04's glass reflects 10 % and refracts 90 % of the light whatever the angle. Real glass
//! reflects about 4 % head-on and almost everything at grazing angles, and coloured glass
//! absorbs light along the way through it. In this lab you compute both: the Fresnel
//! reflectance `R` of a dielectric interface from the two polarisations' amplitudes, and the
//! transmittance of an absorbing medium by the Bouguer–Lambert–Beer law (DTU `fresnel.h` and
//! `Volume::get_transmittance`). With the pipeline at lab 10 the framework's shaders weight the
//! reflected ray by `R` and the refracted one by `1 − R` (`illum 4`, 5, 11, 12), and multiply
//! the light that crossed a volume (`illum 11`, 12) by your transmittance.
//!
//! Read `docs/lab10.md` first. Then fill in the functions below in order and run
//!
//! ```text
//! cargo test -p lab10                 # all exercises
//! cargo test -p lab10 exercise_10_4   # one exercise
//! raylab render --lab 10 --pipeline student
//! ```
//!
//! The cosines are of the angles between the rays and the normal, both in `[0, 1]`:
//! `cos θ₁` of the incident ray, `cos θ₂` of the transmitted one; `η₁` is the index of
//! refraction on the side the light comes from, `η₂` on the other side.

// The parameters of the stubs below are unused until you fill them in.
#![allow(unused_variables)]

use contracts::glam::Vec3;
use contracts::lab10::Fresnel;
use contracts::scene::Material;

/// Your Fresnel reflectance and absorption. The framework calls them through the `Fresnel`
/// trait.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Fresnel for Student {
    /// **Exercise 10.1** — the amplitude reflection coefficient `r_s` of light polarised
    /// perpendicular to the plane of incidence (docs/lab10.md, §10.1; DTU `fresnel_r_s`).
    ///
    /// A signed amplitude from `cos θ₁`, `cos θ₂`, `η₁`, `η₂` — do not square it.
    fn fresnel_r_s(&self, cos_theta_i: f32, cos_theta_t: f32, eta_i: f32, eta_t: f32) -> f32 {
        todo!("Exercise 10.1: fresnel_r_s (docs/lab10.md, Exercise 10.1)")
    }

    /// **Exercise 10.2** — the amplitude reflection coefficient `r_p` of light polarised
    /// parallel to the plane of incidence (docs/lab10.md, §10.2; DTU `fresnel_r_p`).
    ///
    /// A signed amplitude with the sign convention of the docs: at normal incidence
    /// `r_p = −r_s`, and `r_p = 0` at Brewster's angle.
    fn fresnel_r_p(&self, cos_theta_i: f32, cos_theta_t: f32, eta_i: f32, eta_t: f32) -> f32 {
        todo!("Exercise 10.2: fresnel_r_p (docs/lab10.md, Exercise 10.2)")
    }

    /// **Exercise 10.3** — the reflectance of unpolarised light (docs/lab10.md, §10.3; DTU
    /// `fresnel_R`).
    ///
    /// Combine your `fresnel_r_s` and `fresnel_r_p` (call them as `self.fresnel_r_s(…)`):
    /// unpolarised light is half of each polarisation.
    fn fresnel_R(&self, cos_theta_i: f32, cos_theta_t: f32, eta_i: f32, eta_t: f32) -> f32 {
        todo!("Exercise 10.3: fresnel_R (docs/lab10.md, Exercise 10.3)")
    }

    /// **Exercise 10.4** — the reflectance `R` of the interface for light arriving at
    /// `cos θ₁ = cos_theta_i` from index `eta_i` into `eta_t` (docs/lab10.md, §10.4; DTU
    /// `trace_refracted`'s `R`).
    ///
    /// Find `cos θ₂` by Snell's law and call your `fresnel_R`; past the critical angle there is
    /// no transmitted ray (total internal reflection) and `R = 1`.
    fn fresnel_reflectance(&self, cos_theta_i: f32, eta_i: f32, eta_t: f32) -> f32 {
        todo!("Exercise 10.4: fresnel_reflectance (docs/lab10.md, Exercise 10.4)")
    }

    /// **Exercise 10.5** — the transmittance over `distance` inside an absorbing medium of
    /// `material`, per colour channel (docs/lab10.md, §10.5; DTU
    /// `Volume::get_transmittance`).
    ///
    /// The Bouguer–Lambert–Beer law with the absorption coefficient of each channel taken from
    /// the diffuse colour `material.diffuse` as the docs say (mind a channel of colour 0).
    fn transmittance(&self, distance: f32, material: &Material) -> Vec3 {
        todo!("Exercise 10.5: transmittance (docs/lab10.md, Exercise 10.5)")
    }
}
