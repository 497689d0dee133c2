//! # The data types of the rendering core
//!
//! What the lab contracts speak in, and nothing that computes an exercise: rays, orthonormal
//! frames and boxes ([`math`]), the seeded random numbers ([`sampling`]), and the scene's
//! plain data — planes, spheres, triangle meshes, lights, materials keyed by the MTL `illum`
//! number, textures as texels, the camera set-up and the [`Hit`](scene::Hit) of a ray
//! ([`scene`]). Only glam and serde below it, so that it and the contracts build quickly and for
//! other targets (wasm32); loading, acceleration and rendering are `raylab-core`'s.

pub mod math;
pub mod sampling;
pub mod scene;

pub use glam;
