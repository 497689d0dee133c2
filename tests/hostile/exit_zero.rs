//! Hostile submission `exit_zero`: every function ends the test process with
//! `std::process::exit(0)` before the check can reach a verdict, hoping that a grader which
//! trusts the exit status of the test process counts the exercise as passed.
//!
//! The grader must fail every exercise (0 of 14 points): a process that exits without the
//! check's own verdict did not complete its check, whatever its exit status. Each exercise's
//! reason says that the check "did not complete".

use contracts::glam::Vec3;
use contracts::lab02::{Intersection, LightSample, Shading, SurfaceHit, TriangleHit};
use contracts::math::Ray;
use contracts::scene::{DirectionalLight, Plane, PointLight, Sphere};

/// Leaves with a successful status before the check can fail.
fn leave() -> ! {
    std::process::exit(0)
}

/// Exits instead of answering.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Intersection for Student {
    fn intersect_plane(&self, _ray: &Ray, _plane: &Plane) -> Option<SurfaceHit> {
        leave()
    }

    fn intersect_triangle(
        &self,
        _ray: &Ray,
        _v0: Vec3,
        _v1: Vec3,
        _v2: Vec3,
    ) -> Option<TriangleHit> {
        leave()
    }

    fn intersect_sphere(&self, _ray: &Ray, _sphere: &Sphere) -> Option<SurfaceHit> {
        leave()
    }
}

impl Shading for Student {
    fn sample_point_light(&self, _light: &PointLight, _position: Vec3) -> LightSample {
        leave()
    }

    fn sample_directional_light(&self, _light: &DirectionalLight, _position: Vec3) -> LightSample {
        leave()
    }

    fn shade_lambertian(&self, _rho_d: Vec3, _normal: Vec3, _lights: &[LightSample]) -> Vec3 {
        leave()
    }
}
