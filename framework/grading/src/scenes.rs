//! Scenes more than one lab's checks render: variations of the embedded scenes.

use glam::Vec3;
use raylab_core::scene::{IllumModel, Scene, builtin_scene};

/// The default scene with its glass sphere glossy (illum 5): no diffuse part, a white Phong
/// highlight of shininess 100 — the glass ball of the worksheet's "combining it all".
pub fn glossy_default_scene() -> Result<Scene, raylab_core::Error> {
    let mut scene = builtin_scene("default")?;
    scene.name = "default-glossy".into();
    for m in scene
        .materials
        .iter_mut()
        .filter(|m| m.illum == IllumModel::Transparent)
    {
        m.illum = IllumModel::Glossy;
        m.diffuse = Vec3::ZERO;
        m.specular = Vec3::ONE;
        m.shininess = 100.0;
    }
    Ok(scene)
}
