use glam::Vec3;

/// An isotropic point light of radiant intensity `intensity` (W/sr per channel).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PointLight {
    /// Position of the light.
    pub position: Vec3,
    /// Radiant intensity `I`.
    pub intensity: Vec3,
}

/// A light infinitely far away: parallel rays travelling along `direction`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DirectionalLight {
    /// Unit direction the light travels in (from the light towards the scene).
    pub direction: Vec3,
    /// Irradiance `E` delivered to a surface facing the light (W/m² per channel).
    pub emission: Vec3,
}

/// A light made of the scene's emissive triangles (faces whose material has `Ke > 0`).
#[derive(Clone, Debug, PartialEq)]
pub struct AreaLight {
    /// Indices into [`Mesh::faces`](super::Mesh::faces) of the emitting triangles, in
    /// increasing order (so that a face's place among them is a binary search).
    pub faces: Vec<u32>,
    /// Total area of the faces.
    pub area: f32,
    /// Cumulative areas of the faces divided by the total (last entry 1), for choosing a face
    /// with probability proportional to its area.
    pub cdf: Vec<f32>,
}

impl AreaLight {
    /// A light over `faces` (in increasing order) with the given areas.
    pub fn new(faces: Vec<u32>, areas: &[f32]) -> Self {
        assert!(
            faces.is_sorted_by(|a, b| a < b),
            "an area light's faces are listed in increasing order"
        );
        let area: f32 = areas.iter().sum();
        let mut running = 0.0;
        let mut cdf: Vec<f32> = areas
            .iter()
            .map(|a| {
                running += a;
                running / area
            })
            .collect();
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        Self { faces, area, cdf }
    }

    /// Chooses a face with probability proportional to its area from `u ∈ [0, 1)`; returns the
    /// index into [`faces`](Self::faces) and `u` rescaled to `[0, 1)` within that face's
    /// interval, so it can be reused as a fresh uniform number.
    pub fn pick_face(&self, u: f32) -> (usize, f32) {
        let i = self
            .cdf
            .partition_point(|&c| c <= u)
            .min(self.cdf.len() - 1);
        let lo = if i == 0 { 0.0 } else { self.cdf[i - 1] };
        let width = self.cdf[i] - lo;
        let rescaled = if width > 0.0 {
            ((u - lo) / width).clamp(0.0, 1.0 - f32::EPSILON)
        } else {
            0.0
        };
        (i, rescaled)
    }
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
