//! The framework's kernels as a lab02 `Intersection`.

use glam::Vec3;

use contracts::lab02::{Intersection, SurfaceHit, TriangleHit};
use raylab_core::math::Ray;
use raylab_core::scene::{Plane, Sphere};

/// The framework's own primitive tests (`raylab_core::geometry`), packaged as a lab02
/// [`Intersection`]: the base of lab02's checks for the shapes that are not the student's when
/// the pipeline has no intersection code of its own.
#[derive(Clone, Copy, Debug, Default)]
pub struct BuiltinIntersection;

impl BuiltinIntersection {
    /// The unit normal of the triangle `(v0, v1, v2)` that
    /// [`intersect_triangle`](Intersection::intersect_triangle) reports: `(v1 − v0) × (v2 − v0)`,
    /// normalized.
    #[inline(always)]
    pub fn triangle_normal(v0: Vec3, v1: Vec3, v2: Vec3) -> Vec3 {
        (v1 - v0).cross(v2 - v0).normalize()
    }
}

impl Intersection for BuiltinIntersection {
    fn intersect_plane(&self, ray: &Ray, plane: &Plane) -> Option<SurfaceHit> {
        raylab_core::geometry::intersect_plane(ray, plane.normal, plane.d).map(|distance| {
            SurfaceHit {
                distance,
                normal: plane.normal,
            }
        })
    }

    fn intersect_triangle(&self, ray: &Ray, v0: Vec3, v1: Vec3, v2: Vec3) -> Option<TriangleHit> {
        raylab_core::geometry::intersect_triangle(ray, v0, v1, v2).map(|(distance, beta, gamma)| {
            TriangleHit {
                distance,
                beta,
                gamma,
                normal: Self::triangle_normal(v0, v1, v2),
            }
        })
    }

    fn intersect_sphere(&self, ray: &Ray, sphere: &Sphere) -> Option<SurfaceHit> {
        raylab_core::geometry::intersect_sphere(ray, sphere.center, sphere.radius).map(|distance| {
            SurfaceHit {
                distance,
                normal: (ray.at(distance) - sphere.center) / sphere.radius,
            }
        })
    }
}
