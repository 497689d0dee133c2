//! The path tracer's surface models: a lab's material, called where a scene's material names
//! it (`model = "NAME"` in the scene file).
//!
//! A lab whose code is a material registers it from its contract's file
//! (`#[contract(register = path)]`, whose function calls [`Parts::add_surface`]); the path
//! tracer then draws and weighs directions at those surfaces by the model instead of lab 12's
//! Lambertian and glossy lobes. Directions are as lab 12's: `wo` back along the path, `wi`
//! towards the light, both unit vectors; `normal` the unit shading normal on the side of `wo`.
//!
//! [`Parts::add_surface`]: crate::parts::Parts::add_surface

use glam::Vec3;

use crate::lab12::{BsdfSample, BsdfValue};
use crate::sampling::Rng;
use crate::scene::Material;

/// A material of the path tracer: its BSDF and a direction drawn from it.
pub trait SurfaceModel: Send + Sync {
    /// `f(wo, wi)` (without the cosine of `wi`) of `material`, whose diffuse colour at the hit
    /// is `diffuse` (textured where the material has a texture), and the density per unit
    /// solid angle with which [`Self::sample_bsdf`] draws `wi`.
    fn bsdf(
        &self,
        material: &Material,
        diffuse: Vec3,
        normal: Vec3,
        wo: Vec3,
        wi: Vec3,
    ) -> BsdfValue;

    /// A direction drawn from the BSDF, with the BSDF's value and density there; `None` when
    /// the draw is absorbed.
    fn sample_bsdf(
        &self,
        material: &Material,
        diffuse: Vec3,
        normal: Vec3,
        wo: Vec3,
        rng: &mut Rng,
    ) -> Option<BsdfSample>;
}
