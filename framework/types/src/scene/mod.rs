//! The scene's plain data: shapes, lights, materials, textures, the camera set-up and the hit
//! of a ray. `raylab-core` loads them from files and traces rays against them.

mod camera;
mod hit;
mod light;
mod material;
mod shapes;
mod texture;

pub use camera::CameraSetup;
pub use hit::{Hit, HitSurface};
pub use light::{AreaLight, DirectionalLight, Light, PointLight};
pub use material::{IllumModel, Material, MaterialId};
pub use shapes::{Mesh, Plane, Sphere, triangle_normal};
pub use texture::Texture;
