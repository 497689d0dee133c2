//! Reference solution of lab 01 (docs/lab01.md).

use contracts::glam::{UVec2, Vec2, Vec3};
use contracts::lab01::{CameraBasis, CameraRays};
use contracts::math::Ray;

/// The reference camera.
#[derive(Clone, Copy, Debug, Default)]
pub struct Lab01;

impl CameraRays for Lab01 {
    fn image_plane_coords(&self, raster: Vec2, resolution: UVec2) -> Vec2 {
        let (w, h) = (resolution.x as f32, resolution.y as f32);
        Vec2::new((raster.x - 0.5 * w) / h, (0.5 * h - raster.y) / h)
    }

    fn camera_basis(&self, eye: Vec3, look_at: Vec3, up: Vec3) -> CameraBasis {
        let ip_normal = (look_at - eye).normalize();
        let ip_xaxis = ip_normal.cross(up).normalize();
        let ip_yaxis = ip_xaxis.cross(ip_normal);
        CameraBasis {
            ip_xaxis,
            ip_yaxis,
            ip_normal,
        }
    }

    fn field_of_view(&self, focal_distance: f32) -> f32 {
        (2.0 * (1.0 / (2.0 * focal_distance)).atan()).to_degrees()
    }

    fn ray_direction(&self, basis: &CameraBasis, focal_distance: f32, ip: Vec2) -> Vec3 {
        (ip.x * basis.ip_xaxis + ip.y * basis.ip_yaxis + focal_distance * basis.ip_normal)
            .normalize()
    }

    fn camera_ray(&self, eye: Vec3, direction: Vec3) -> Ray {
        Ray::new(eye, direction, 0.0, f32::INFINITY)
    }
}
