use glam::{Vec2, Vec3};

use super::MaterialId;

/// Everything a shader needs to know about a ray–surface intersection (the DTU `HitInfo`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Hit {
    /// Distance `t` along the ray to the hit.
    pub distance: f32,
    /// World-space hit point `origin + t·direction`.
    pub position: Vec3,
    /// Unit normal of the surface itself (the triangle's plane, the sphere's radius direction).
    pub geometric_normal: Vec3,
    /// Unit normal used for shading (interpolated vertex normals on smooth meshes).
    pub shading_normal: Vec3,
    /// Texture coordinates at the hit: computed by the pipeline through lab 09's slot when the
    /// material has a texture (zero otherwise, and from the scene's own queries).
    pub texcoord: Vec2,
    /// Which primitive was hit, for what depends on it (lab 09's texture coordinates).
    pub surface: HitSurface,
    /// Material of the surface that was hit.
    pub material: MaterialId,
    /// How many bounces led to this hit (0 for camera rays).
    pub trace_depth: u32,
    /// Index of refraction of the medium the ray travelled through before the hit.
    pub ior: f32,
}

/// The primitive a [`Hit`] lies on.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum HitSurface {
    /// Not known (a hit made up by hand).
    #[default]
    Unknown,
    /// The scene's plane with this index.
    Plane(u32),
    /// The scene's sphere with this index.
    Sphere(u32),
    /// The mesh's face with this index, at barycentric coordinates `(β, γ)`.
    Triangle {
        /// Index of the face in the scene's mesh.
        face: u32,
        /// Barycentric coordinates `(β, γ)` of the hit (weights of vertices 1 and 2).
        barycentrics: Vec2,
    },
}
