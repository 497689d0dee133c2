use glam::Vec3;

/// An isotropic point light of radiant intensity `intensity` (W/sr per channel).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    /// Position of the light.
    pub position: Vec3,
    /// Radiant intensity `I`.
    pub intensity: Vec3,
}

/// A light infinitely far away: parallel rays travelling along `direction`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionalLight {
    /// Unit direction the light travels in (from the light towards the scene).
    pub direction: Vec3,
    /// Irradiance `E` delivered to a surface facing the light (W/m² per channel).
    pub emission: Vec3,
}

/// A light made of the scene's emissive triangles (faces whose material has `Ke > 0`).
#[derive(Clone, Debug, PartialEq)]
pub struct AreaLight {
    /// Indices into [`Mesh::faces`](super::Mesh::faces) of the emitting triangles.
    pub faces: Vec<u32>,
    /// Total area of the faces.
    pub area: f32,
}

/// A light source of the scene.
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Point light.
    Point(PointLight),
    /// Directional light.
    Directional(DirectionalLight),
    /// Emissive triangle mesh.
    Area(AreaLight),
}
