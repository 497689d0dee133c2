//! Closed forms of radiometry that more than one lab's checks compare estimates with, and the
//! light samples shading checks pass.

use contracts::lab02::LightSample;
use glam::{DVec3, Vec3};

/// Light samples at distance 1 from `(direction, radiance)` pairs: the lights a shading
/// function is checked with.
pub fn samples_of(lights: &[(Vec3, Vec3)]) -> Vec<LightSample> {
    lights
        .iter()
        .map(|&(direction, radiance)| LightSample {
            direction,
            distance: 1.0,
            radiance,
        })
        .collect()
}

/// Irradiance at `p` (normal `n`) from a Lambertian polygon of radiance `le` lying wholly above
/// the point's horizon, by Lambert's formula `E = (L_e/2)·|Σ Θ_i (n·γ̂_i)|`, where `Θ_i` is the
/// angle that edge `i` subtends at `p` and `γ̂_i` the unit normal of the plane through `p` and
/// the edge.
pub fn irradiance_polygon(le: f64, p: DVec3, n: DVec3, polygon: &[DVec3]) -> f64 {
    let mut sum = 0.0;
    for i in 0..polygon.len() {
        let a = (polygon[i] - p).normalize();
        let b = (polygon[(i + 1) % polygon.len()] - p).normalize();
        let theta = a.dot(b).clamp(-1.0, 1.0).acos();
        sum += theta * n.dot(a.cross(b).normalize());
    }
    0.5 * le * sum.abs()
}
