use glam::{Vec2, Vec3};

use super::MaterialId;

/// Everything a shader needs to know about a ray–surface intersection (the DTU `HitInfo`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance `t` along the ray to the hit.
    pub distance: f32,
    /// World-space hit point `origin + t·direction`.
    pub position: Vec3,
    /// Unit normal of the surface itself (the triangle's plane, the sphere's radius direction).
    pub geometric_normal: Vec3,
    /// Unit normal used for shading (interpolated vertex normals on smooth meshes).
    pub shading_normal: Vec3,
    /// Texture coordinates at the hit (zero when the surface has none).
    pub texcoord: Vec2,
    /// Material of the surface that was hit.
    pub material: MaterialId,
    /// How many bounces led to this hit (0 for camera rays).
    pub trace_depth: u32,
    /// Index of refraction of the medium the ray travelled through before the hit.
    pub ior: f32,
}
