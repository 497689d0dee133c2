//! # Lab 01 — camera rays
//!
//! The framework loops over the pixels of the image and asks your camera for the ray through
//! each of them; the scene, the intersections and the shading are done for you. Your job is
//! the pinhole camera of the DTU framework: turn a pixel into a point on the image plane, set
//! up the camera basis, and shoot the ray from the eye through that point.
//!
//! Read `docs/lab01.md` first. Then fill in the functions below in order and run
//!
//! ```text
//! cargo test -p lab01                # all exercises
//! cargo test -p lab01 exercise_1_2   # one exercise
//! raylab render --lab 1 --pipeline student   # look at the image your camera makes
//! ```
//!
//! A failing test names the exercise and the function, and for images writes your render, the
//! reference and their difference as PNG files (the paths are in the message).

// The parameters of the stubs below are unused until you fill them in.
#![allow(unused_variables)]

use contracts::glam::{UVec2, Vec2, Vec3};
use contracts::lab01::{CameraBasis, CameraRays};
use contracts::math::Ray;

/// Your camera. The framework calls it through the `CameraRays` trait.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl CameraRays for Student {
    /// **Exercise 1.1** — image-plane coordinates of a raster position (docs/lab01.md, §1.1).
    ///
    /// `raster` is measured in pixels from the **top-left** corner of the image: pixel
    /// `(i, j)` covers `[i, i+1] × [j, j+1]`, so its centre is `(i + 0.5, j + 0.5)`.
    /// `resolution` is `(W, H)`.
    ///
    /// The image plane is **one unit high** and centred on the viewing direction; its `y` axis
    /// points **up** (raster `y` points down). Square pixels, so the width is `W/H` units:
    ///
    /// ```text
    /// x_ip = (raster.x − W/2) / H
    /// y_ip = (H/2 − raster.y) / H
    /// ```
    ///
    /// Mind the integer division: convert `resolution` to `f32` first.
    fn image_plane_coords(&self, raster: Vec2, resolution: UVec2) -> Vec2 {
        todo!("Exercise 1.1: image_plane_coords (docs/lab01.md, Exercise 1.1)")
    }

    /// **Exercise 1.2** — the camera basis (docs/lab01.md, §1.2; DTU `Camera::set`).
    ///
    /// ```text
    /// ip_normal = normalize(look_at − eye)        the viewing direction
    /// ip_xaxis  = normalize(ip_normal × up)       screen right
    /// ip_yaxis  = ip_xaxis × ip_normal            screen up (already unit length)
    /// ```
    ///
    /// `up` need not be perpendicular to the viewing direction, nor unit length.
    fn camera_basis(&self, eye: Vec3, look_at: Vec3, up: Vec3) -> CameraBasis {
        todo!("Exercise 1.2: camera_basis (docs/lab01.md, Exercise 1.2)")
    }

    /// **Exercise 1.3** — the vertical field of view, in **degrees**, of a camera whose image
    /// plane (one unit high) is `focal_distance` units from the eye (docs/lab01.md, §1.3).
    ///
    /// From `h = 2·d·tan(fov/2)` with `h = 1`: `fov = 2·atan(1 / (2d))`.
    fn field_of_view(&self, focal_distance: f32) -> f32 {
        todo!("Exercise 1.3: field_of_view (docs/lab01.md, Exercise 1.3)")
    }

    /// **Exercise 1.4** — the unit direction from the eye through the image-plane point `ip`
    /// (docs/lab01.md, §1.4; DTU `Camera::get_ray_dir`): a change of basis from image-plane
    /// coordinates to world space,
    ///
    /// ```text
    /// direction = normalize(ip.x · ip_xaxis + ip.y · ip_yaxis + d · ip_normal)
    /// ```
    fn ray_direction(&self, basis: &CameraBasis, focal_distance: f32, ip: Vec2) -> Vec3 {
        todo!("Exercise 1.4: ray_direction (docs/lab01.md, Exercise 1.4)")
    }

    /// **Exercise 1.5** — the camera ray (docs/lab01.md, §1.5; DTU `Camera::get_ray`): it
    /// starts at the eye, goes along `direction`, and is valid for `0 ≤ t < ∞`
    /// (`tmin = 0.0`, `tmax = f32::INFINITY`). Use `Ray::new(origin, direction, tmin, tmax)`.
    fn camera_ray(&self, eye: Vec3, direction: Vec3) -> Ray {
        todo!("Exercise 1.5: camera_ray (docs/lab01.md, Exercise 1.5)")
    }
}
