//! The pipeline: the components a render calls, one slot per lab contract. Every slot holds the
//! reference implementation by default (see the `reference` crate's `pipeline()`); a lab's
//! checks and `raylab render --pipeline student` replace the slots of one lab with the
//! student's code, so a mistake in one lab does not spread into the others.

use std::sync::Arc;

use glam::{UVec2, Vec2, Vec3};

use crate::labs::{lab01, lab02};
use crate::math::{Hit, Ray};
use crate::sampling::Rng;
use crate::scene::{Light, Scene};

/// What a render shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum View {
    /// Full shading with every lab up to the pipeline's `lab` enabled.
    #[default]
    Shaded,
    /// The diffuse reflectance of the surface hit (lab 01's flat image).
    BaseColour,
    /// The shading normal mapped from `[−1, 1]` to `[0, 1]`.
    Normals,
}

/// The components of a render, one slot per lab contract.
#[derive(Clone)]
pub struct Pipeline {
    /// Lab 01: pixel to camera ray.
    pub camera: Arc<dyn lab01::CameraRays>,
    /// Lab 02, intersections; `None` uses the framework's built-in kernels (fast, and equal to
    /// the reference's results up to floating-point rounding).
    pub intersection: Option<Arc<dyn lab02::Intersection>>,
    /// Lab 02, lights and Lambertian shading.
    pub shading: Arc<dyn lab02::Shading>,
    /// The highest lab whose features the integrator uses (1: flat colour, 2: Lambertian
    /// shading from point and directional lights without shadows).
    pub lab: u32,
    /// What to show.
    pub view: View,
}

/// A camera prepared for one render: the basis computed once through the pipeline.
#[derive(Clone, Copy, Debug)]
pub struct PreparedCamera {
    /// Eye point.
    pub eye: Vec3,
    /// Camera basis from lab 01.
    pub basis: lab01::CameraBasis,
    /// Focal distance in image-plane heights.
    pub focal_distance: f32,
    /// Image size in pixels.
    pub resolution: UVec2,
}

impl Pipeline {
    /// Prepares the scene camera for an image of `resolution` (Exercise 1.2).
    pub fn prepare_camera(&self, scene: &Scene, resolution: UVec2) -> PreparedCamera {
        let c = &scene.camera;
        PreparedCamera {
            eye: c.eye,
            basis: self.camera.camera_basis(c.eye, c.look_at, c.up),
            focal_distance: c.focal_distance,
            resolution,
        }
    }

    /// The camera ray through raster position `raster` (Exercises 1.1, 1.4, 1.5).
    pub fn camera_ray(&self, camera: &PreparedCamera, raster: Vec2) -> Ray {
        let ip = self.camera.image_plane_coords(raster, camera.resolution);
        let dir = self
            .camera
            .ray_direction(&camera.basis, camera.focal_distance, ip);
        self.camera.camera_ray(camera.eye, dir)
    }

    /// The closest hit along `ray`, through the lab 02 slot.
    pub fn trace_to_closest(&self, scene: &Scene, ray: &Ray) -> Option<Hit> {
        match &self.intersection {
            Some(isect) => scene.trace_to_closest_with(ray, isect.as_ref()),
            None => scene.trace_to_closest(ray),
        }
    }

    /// Radiance arriving along `ray` (the DTU `RayTracer::compute_pixel` body).
    pub fn radiance(&self, scene: &Scene, ray: &Ray, _rng: &mut Rng) -> Vec3 {
        let Some(hit) = self.trace_to_closest(scene, ray) else {
            return scene.background;
        };
        let material = scene.material(hit.material);
        match self.view {
            View::Normals => 0.5 * (hit.shading_normal + Vec3::ONE),
            View::BaseColour => material.diffuse,
            View::Shaded if self.lab < 2 => material.diffuse,
            View::Shaded => material.emission + self.shade_direct(scene, &hit),
        }
    }

    /// Lambertian reflection of the point and directional lights at a hit (lab 02).
    fn shade_direct(&self, scene: &Scene, hit: &Hit) -> Vec3 {
        let samples: Vec<lab02::LightSample> = scene
            .lights
            .iter()
            .filter_map(|light| match light {
                Light::Point(p) => Some(self.shading.sample_point_light(p, hit.position)),
                Light::Directional(d) => {
                    Some(self.shading.sample_directional_light(d, hit.position))
                }
                Light::Area(_) => None,
            })
            .collect();
        let material = scene.material(hit.material);
        self.shading
            .shade_lambertian(material.diffuse, hit.shading_normal, &samples)
    }
}
