//! Lab 01 — the image loop and camera rays (docs/lab01.md).
//!
//! The framework loops over the pixels (in parallel, see `raylab_core::render`); the student turns
//! a pixel into a ray through the pinhole camera of the DTU framework.

use glam::{UVec2, Vec2, Vec3};

use crate::math::Ray;

/// The orthonormal camera basis of the DTU framework: the image-plane axes and the viewing
/// direction, all unit length (docs/lab01.md, Exercise 1.2).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CameraBasis {
    /// Image-plane x axis (screen right).
    pub ip_xaxis: Vec3,
    /// Image-plane y axis (screen up).
    pub ip_yaxis: Vec3,
    /// Viewing direction, the normal of the image plane.
    pub ip_normal: Vec3,
}

/// The lab's contract: what the student's `Student` implements, and the answer key's `Lab01`.
pub type Contract = dyn CameraRays;

/// Lab 01's contract: from pixel to camera ray.
#[crate::contract]
pub trait CameraRays: Send + Sync {
    /// Exercise 1.1 — image-plane coordinates of a raster position.
    ///
    /// `raster` is a position in pixel units with `(0, 0)` the top-left corner of the image
    /// and `(W, H)` the bottom-right one (pixel `(i, j)` has its centre at `(i + ½, j + ½)`).
    /// The image plane is one unit high, centred on the optical axis, with `y` pointing up:
    /// `x_ip = (raster.x − W/2)/H`, `y_ip = (H/2 − raster.y)/H`.
    fn image_plane_coords(&self, raster: Vec2, resolution: UVec2) -> Vec2;

    /// Exercise 1.2 — the camera basis from eye point, look-at point and up vector.
    fn camera_basis(&self, eye: Vec3, look_at: Vec3, up: Vec3) -> CameraBasis;

    /// Exercise 1.3 — the vertical field of view in degrees, `fov = 2·atan(1/(2d))`, for a
    /// focal distance `d` in image-plane heights.
    fn field_of_view(&self, focal_distance: f32) -> f32;

    /// Exercise 1.4 — unit direction of the ray from the eye through image-plane point `ip`:
    /// `normalize(x_ip·ip_xaxis + y_ip·ip_yaxis + d·ip_normal)`.
    fn ray_direction(&self, basis: &CameraBasis, focal_distance: f32, ip: Vec2) -> Vec3;

    /// Exercise 1.5 — the camera ray: from the eye along `direction`, valid on `[0, ∞)`.
    fn camera_ray(&self, eye: Vec3, direction: Vec3) -> Ray;
}
