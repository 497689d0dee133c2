//! Geometric building blocks on top of glam: rays, orthonormal bases and boxes.

mod aabb;
mod onb;
mod ray;

pub use aabb::Aabb;
pub use glam::{UVec2, Vec2, Vec3, Vec3A};
pub use onb::Onb;
pub use ray::Ray;

/// Offset used as `tmin` of secondary rays (shadow, reflected, refracted) to prevent a surface
/// from occluding itself ("shadow acne") through floating-point error in the hit position.
pub const RAY_EPSILON: f32 = 1e-4;
