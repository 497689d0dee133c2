//! The Cornell box of the lab's image checks, lit by its point light or by its area light.

use raylab_core::scene::{Light, Scene, builtin_scene};

/// The Cornell box with only its point light (`point = true`) or only its area light.
pub fn snapshot_scene(point: bool) -> Result<Scene, raylab_core::Error> {
    let mut scene = builtin_scene("cornell")?;
    scene.lights.retain(|l| match l {
        Light::Point(_) => point,
        Light::Area(_) => !point,
        Light::Directional(_) => false,
    });
    scene.name = if point {
        "cornell, point light only".into()
    } else {
        "cornell, area light only".into()
    };
    Ok(scene)
}
