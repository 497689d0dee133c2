use glam::Vec3;

use crate::contracts::lab02::{Intersection, SurfaceHit, TriangleHit};
use crate::math::Ray;
use crate::scene::{Plane, Sphere};

/// The framework's own primitive tests, packaged as a lab02 [`Intersection`] so that
/// [`Scene::trace_to_closest`](crate::scene::Scene::trace_to_closest) runs at full speed.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct BuiltinIntersection;

impl BuiltinIntersection {
    /// The unit normal of the triangle `(v0, v1, v2)` that
    /// [`intersect_triangle`](Intersection::intersect_triangle) reports: `(v1 − v0) × (v2 − v0)`,
    /// normalized.
    #[inline(always)]
    pub(crate) fn triangle_normal(v0: Vec3, v1: Vec3, v2: Vec3) -> Vec3 {
        (v1 - v0).cross(v2 - v0).normalize()
    }
}

impl Intersection for BuiltinIntersection {
    fn intersect_plane(&self, ray: &Ray, plane: &Plane) -> Option<SurfaceHit> {
        crate::geometry::intersect_plane(ray, plane.normal, plane.d).map(|distance| SurfaceHit {
            distance,
            normal: plane.normal,
        })
    }

    fn intersect_triangle(&self, ray: &Ray, v0: Vec3, v1: Vec3, v2: Vec3) -> Option<TriangleHit> {
        crate::geometry::intersect_triangle(ray, v0, v1, v2).map(|(distance, beta, gamma)| {
            TriangleHit {
                distance,
                beta,
                gamma,
                normal: Self::triangle_normal(v0, v1, v2),
            }
        })
    }

    fn intersect_sphere(&self, ray: &Ray, sphere: &Sphere) -> Option<SurfaceHit> {
        crate::geometry::intersect_sphere(ray, sphere.center, sphere.radius).map(|distance| {
            SurfaceHit {
                distance,
                normal: (ray.at(distance) - sphere.center) / sphere.radius,
            }
        })
    }
}
