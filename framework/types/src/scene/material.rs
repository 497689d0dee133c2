use std::sync::Arc;

use glam::Vec3;

use super::Texture;

/// Index of a material in [`Scene::materials`](super::Scene::materials).
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    PartialOrd,
    Ord,
    serde::Serialize,
    serde::Deserialize,
)]
pub struct MaterialId(pub u32);

/// Which shader a material uses, keyed by the MTL `illum` number as in the DTU framework.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum IllumModel {
    /// `illum 0` or `1`: Lambertian diffuse reflection.
    Lambertian,
    /// `illum 2`: Phong (diffuse plus glossy highlight).
    Phong,
    /// `illum 3`: perfect mirror.
    Mirror,
    /// `illum 4`: transparent (refracting) dielectric.
    Transparent,
    /// `illum 5` (in the MTL specification, reflection weighted by Fresnel), the glossy glass of
    /// the DTU worksheets: a dielectric that reflects and refracts under a Phong highlight of
    /// `Ks`, `Ns` — below lab 10 with the worksheet's fixed weights (0.1 Phong on the diffuse
    /// colour, 0.1 mirror, 0.9 refraction), from lab 10 on with the Fresnel reflectance and no
    /// diffuse part. An opaque glossy surface (the seed renderers' glossy material) is `illum 2`.
    Glossy,
    /// `illum 11`: absorbing volume (Bouguer–Lambert–Beer law) behind a transparent surface.
    AbsorbingVolume,
    /// `illum 12`: absorbing volume with a glossy surface.
    GlossyVolume,
}

impl IllumModel {
    /// The model for an MTL `illum` number, or `None` if raylab has no shader for it.
    pub fn from_illum(illum: u8) -> Option<Self> {
        Some(match illum {
            0 | 1 => Self::Lambertian,
            2 => Self::Phong,
            3 => Self::Mirror,
            4 | 6 | 7 => Self::Transparent,
            5 => Self::Glossy,
            11 => Self::AbsorbingVolume,
            12 => Self::GlossyVolume,
            _ => return None,
        })
    }

    /// The MTL `illum` number that selects this model.
    pub fn illum(self) -> u8 {
        match self {
            Self::Lambertian => 1,
            Self::Phong => 2,
            Self::Mirror => 3,
            Self::Transparent => 4,
            Self::Glossy => 5,
            Self::AbsorbingVolume => 11,
            Self::GlossyVolume => 12,
        }
    }
}

/// A surface material with the MTL parameters the labs use.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Material {
    /// Name from the MTL file or scene file.
    pub name: String,
    /// Shader selection (`illum`).
    pub illum: IllumModel,
    /// Diffuse reflectance `ρ_d` (`Kd`).
    pub diffuse: Vec3,
    /// Specular reflectance `ρ_s` (`Ks`).
    pub specular: Vec3,
    /// Ambient colour (`Ka`).
    pub ambient: Vec3,
    /// Emitted radiance `L_e` (`Ke`); non-zero makes the surface an area light.
    pub emission: Vec3,
    /// Phong exponent `s` (`Ns`).
    pub shininess: f32,
    /// Roughness `r ∈ (0, 1]` (`Pr`): lab 12's glossy lobe has the exponent `2/r² − 2`; `None`
    /// takes the Phong exponent.
    pub roughness: Option<f32>,
    /// Index of refraction (`Ni`).
    pub ior: f32,
    /// Absorption/transmission filter of a volume (`Tf`).
    pub transmission: Vec3,
    /// Diffuse texture (`map_Kd`), multiplied with `diffuse` when present.
    pub diffuse_texture: Option<Arc<Texture>>,
    /// The path tracer's surface model that draws it, by the name a lab registers it under
    /// (`model` in a scene file); `None`, or a name no lab of the pipeline registers, draws it
    /// with lab 12's lobes.
    pub model: Option<String>,
}

impl Material {
    /// A Lambertian material of reflectance `diffuse`.
    pub fn lambertian(name: impl Into<String>, diffuse: Vec3) -> Self {
        Self {
            name: name.into(),
            illum: IllumModel::Lambertian,
            diffuse,
            specular: Vec3::ZERO,
            ambient: Vec3::ZERO,
            emission: Vec3::ZERO,
            shininess: 0.0,
            roughness: None,
            ior: 1.0,
            transmission: Vec3::ONE,
            diffuse_texture: None,
            model: None,
        }
    }

    /// Whether the surface emits light.
    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }
}
