//! The scene-level ray queries of the DTU `RayTracer`: the closest hit and any hit over the
//! scene's planes, spheres and triangles, with the framework's kernels or with primitive tests
//! given by the caller ([`PrimitiveTests`]).

use glam::{Vec2, Vec3};

use super::{Plane, Scene, Sphere};
use crate::geometry::{intersect_plane, intersect_sphere, intersect_triangle};
use crate::math::Ray;
use crate::scene::{Hit, HitSurface};

/// What one ray–primitive test of [`PrimitiveTests`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrimitiveHit {
    /// Ray parameter `t` of the hit.
    pub t: f32,
    /// Unit geometric normal at the hit.
    pub normal: Vec3,
    /// Barycentric weights `(β, γ)` of a triangle's second and third vertex (zero for planes
    /// and spheres).
    pub barycentrics: Vec2,
}

/// The ray–primitive tests that [`Scene::trace_to_closest_with`] and
/// [`Scene::trace_to_any_with`] run on the scene's planes, spheres and triangles.
///
/// Each test reports only hits with `ray.tmin ≤ t ≤ ray.tmax`. As in the DTU framework, the
/// answers are trusted: a test that ignores `tmin`/`tmax` changes which hit is "closest".
pub trait PrimitiveTests {
    /// The hit of `ray` with `plane`.
    fn plane(&self, ray: &Ray, plane: &Plane) -> Option<PrimitiveHit>;
    /// The hit of `ray` with the triangle of `vertices`, with its barycentrics.
    fn triangle(&self, ray: &Ray, vertices: &[Vec3; 3]) -> Option<PrimitiveHit>;
    /// The nearest hit of `ray` with `sphere` (normal outward).
    fn sphere(&self, ray: &Ray, sphere: &Sphere) -> Option<PrimitiveHit>;
}

/// The framework's own kernels ([`crate::geometry`]) as primitive tests: what
/// [`Scene::trace_to_closest`] and [`Scene::trace_to_any`] run on planes and spheres (their
/// triangles go four at a time through the same watertight test).
struct Kernels;

impl PrimitiveTests for Kernels {
    #[inline(always)]
    fn plane(&self, ray: &Ray, plane: &Plane) -> Option<PrimitiveHit> {
        intersect_plane(ray, plane.normal, plane.d).map(|t| PrimitiveHit {
            t,
            normal: plane.normal,
            barycentrics: Vec2::ZERO,
        })
    }

    #[inline(always)]
    fn triangle(&self, ray: &Ray, &[v0, v1, v2]: &[Vec3; 3]) -> Option<PrimitiveHit> {
        intersect_triangle(ray, v0, v1, v2).map(|(t, beta, gamma)| PrimitiveHit {
            t,
            normal: super::triangle_normal([v0, v1, v2]),
            barycentrics: Vec2::new(beta, gamma),
        })
    }

    #[inline(always)]
    fn sphere(&self, ray: &Ray, sphere: &Sphere) -> Option<PrimitiveHit> {
        intersect_sphere(ray, sphere.center, sphere.radius).map(|t| PrimitiveHit {
            t,
            normal: (ray.at(t) - sphere.center) / sphere.radius,
            barycentrics: Vec2::ZERO,
        })
    }
}

/// Which primitive a closest-hit query found, with what the intersection routine returned.
#[derive(Clone, Copy)]
enum Found {
    Plane(usize, Vec3),
    Sphere(usize, Vec3),
    Triangle(usize, Vec2, Vec3),
}

impl Scene {
    /// The closest surface along `ray` in `[tmin, tmax]` (DTU `RayTracer::trace_to_closest`),
    /// using the framework's intersection kernels; none along a ray that is not
    /// [traceable](Ray::is_traceable).
    ///
    /// The same hit as the framework's kernels give one triangle at a time, bit for bit, found
    /// faster: the triangles are tested four at a time
    /// ([`TriangleBvh::closest_hit_watertight`](crate::accel::TriangleBvh::closest_hit_watertight)).
    pub fn trace_to_closest(&self, ray: &Ray) -> Option<Hit> {
        self.closest_with(ray, &Kernels, |r| {
            self.triangle_bvh.closest_hit_watertight(r).map(|h| {
                let normal = self.mesh.face_normal(h.face as usize);
                (h.face, h.t, Vec2::new(h.beta, h.gamma), normal)
            })
        })
    }

    /// Whether anything lies along `ray` in `[tmin, tmax]` (DTU `RayTracer::trace_to_any`): the
    /// shadow-ray query, which may stop at the first hit it finds.
    pub fn trace_to_any(&self, ray: &Ray) -> bool {
        self.any_with(ray, &Kernels, |r| self.triangle_bvh.any_hit_watertight(r))
    }

    /// [`trace_to_closest`](Self::trace_to_closest) with the primitive tests `tests` (a
    /// student's lab02 code, say), one triangle at a time.
    pub fn trace_to_closest_with<T: PrimitiveTests + ?Sized>(
        &self,
        ray: &Ray,
        tests: &T,
    ) -> Option<Hit> {
        self.closest_with(ray, tests, |r| {
            let mut last = (Vec2::ZERO, Vec3::ZERO);
            self.triangle_bvh
                .closest_hit(r, |vertices, r| {
                    tests.triangle(r, vertices).map(|h| {
                        last = (h.barycentrics, h.normal);
                        h.t
                    })
                })
                .map(|(f, t)| (f, t, last.0, last.1))
        })
    }

    /// The closest hit with the plane and sphere tests of `tests` and the triangle query
    /// `triangles(ray)`, which returns the face, `t`, the barycentrics and the normal.
    #[inline(always)]
    fn closest_with<T: PrimitiveTests + ?Sized>(
        &self,
        ray: &Ray,
        tests: &T,
        triangles: impl FnOnce(&Ray) -> Option<(u32, f32, Vec2, Vec3)>,
    ) -> Option<Hit> {
        if !ray.is_traceable() {
            return None;
        }
        let mut r = *ray;
        let mut found = None;
        for (i, plane) in self.planes.iter().enumerate() {
            if let Some(h) = tests.plane(&r, plane) {
                r.tmax = h.t;
                found = Some(Found::Plane(i, h.normal));
            }
        }
        let mut sphere_normal = Vec3::ZERO;
        if let Some((i, t)) = self.sphere_bvh.closest_hit(&r, |i, r| {
            tests.sphere(r, &self.spheres[i as usize]).map(|h| {
                sphere_normal = h.normal;
                h.t
            })
        }) {
            r.tmax = t;
            found = Some(Found::Sphere(i as usize, sphere_normal));
        }
        if let Some((f, t, bary, normal)) = triangles(&r) {
            r.tmax = t;
            found = Some(Found::Triangle(f as usize, bary, normal));
        }
        let found = found?;
        let t = r.tmax;
        let position = ray.at(t);
        let (normal, shading_normal, surface, material) = match found {
            Found::Plane(i, n) => (n, n, HitSurface::Plane(i as u32), self.planes[i].material),
            Found::Sphere(i, n) => (n, n, HitSurface::Sphere(i as u32), self.spheres[i].material),
            Found::Triangle(f, bary, n) => {
                let shading = self.shading_normal(f, bary, n);
                let surface = HitSurface::Triangle {
                    face: f as u32,
                    barycentrics: bary,
                };
                (n, shading, surface, self.mesh.face_materials[f])
            }
        };
        Some(Hit {
            distance: t,
            position,
            geometric_normal: normal,
            shading_normal,
            texcoord: Vec2::ZERO,
            surface,
            material,
            trace_depth: 0,
            ior: 1.0,
        })
    }

    /// [`trace_to_any`](Self::trace_to_any) with the primitive tests `tests`.
    pub fn trace_to_any_with<T: PrimitiveTests + ?Sized>(&self, ray: &Ray, tests: &T) -> bool {
        self.any_with(ray, tests, |r| {
            self.triangle_bvh
                .any_hit(r, |vertices, r| tests.triangle(r, vertices).is_some())
        })
    }

    /// Whether the plane or sphere tests of `tests` or the triangle query `triangles(ray)` find
    /// anything along `ray`.
    #[inline(always)]
    fn any_with<T: PrimitiveTests + ?Sized>(
        &self,
        ray: &Ray,
        tests: &T,
        triangles: impl FnOnce(&Ray) -> bool,
    ) -> bool {
        if !ray.is_traceable() {
            return false;
        }
        self.planes.iter().any(|p| tests.plane(ray, p).is_some())
            || self.sphere_bvh.any_hit(ray, |i, r| {
                tests.sphere(r, &self.spheres[i as usize]).is_some()
            })
            || triangles(ray)
    }

    /// Shading normal of face `f` at barycentrics `(β, γ)`: the vertex normals interpolated
    /// where the mesh has them, the geometric normal otherwise.
    fn shading_normal(&self, f: usize, bary: Vec2, geometric: Vec3) -> Vec3 {
        let mesh = &self.mesh;
        if mesh.normals.is_empty() {
            return geometric;
        }
        let [a, b, c] = mesh.faces[f].map(|i| i as usize);
        let w = [1.0 - bary.x - bary.y, bary.x, bary.y];
        let n = w[0] * mesh.normals[a] + w[1] * mesh.normals[b] + w[2] * mesh.normals[c];
        let n = n.normalize_or_zero();
        if n == Vec3::ZERO || !n.is_finite() {
            geometric
        } else {
            n
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{BUILTIN_SCENES, builtin_scene};
    use crate::test_rng::Rng;

    /// A ray with a NaN or infinite origin or direction, or a NaN interval, hits nothing in
    /// every query (and the queries return: a NaN ray passes every slab test).
    #[test]
    fn untraceable_rays_hit_nothing() {
        let scene = builtin_scene("cornell-spheres").unwrap();
        let eye = scene.camera.eye;
        let towards = (scene.camera.look_at - eye).normalize();
        for ray in [
            Ray::unbounded(eye, Vec3::NAN, 1e-4),
            Ray::unbounded(eye, Vec3::new(f32::NAN, 0.0, 1.0), 1e-4),
            Ray::unbounded(Vec3::splat(f32::NAN), towards, 1e-4),
            Ray::unbounded(Vec3::splat(f32::INFINITY), towards, 1e-4),
            Ray::new(eye, towards, f32::NAN, f32::INFINITY),
            Ray::new(eye, towards, 1e-4, f32::NAN),
        ] {
            assert!(scene.trace_to_closest(&ray).is_none(), "{ray:?}");
            assert!(!scene.trace_to_any(&ray), "{ray:?}");
            assert!(
                scene.trace_to_closest_with(&ray, &Kernels).is_none(),
                "{ray:?}"
            );
            assert!(!scene.trace_to_any_with(&ray, &Kernels), "{ray:?}");
        }
        // The same ray with a finite direction hits the box.
        assert!(
            scene
                .trace_to_closest(&Ray::unbounded(eye, towards, 1e-4))
                .is_some()
        );
    }

    /// The fast queries (triangles four at a time) answer as the kernels do one triangle at a
    /// time, bit for bit, on every built-in scene: rays from the camera and from points inside.
    #[test]
    fn fast_queries_equal_the_kernels_one_primitive_at_a_time() {
        let mut rng = Rng::new(21);
        for name in BUILTIN_SCENES {
            let scene = builtin_scene(name).unwrap();
            let mut hits = 0;
            for k in 0..4000 {
                let camera = &scene.camera;
                let size = camera.eye.distance(camera.look_at);
                // From the eye towards the scene, and from points near its centre.
                let target = camera.look_at + 0.3 * size * rng.coords();
                let (origin, direction) = if k % 2 == 0 {
                    (camera.eye, target - camera.eye)
                } else {
                    (target, rng.vec())
                };
                // Unbounded rays, and one in four stopping short.
                let tmax = if k % 4 == 3 {
                    size * rng.next()
                } else {
                    f32::INFINITY
                };
                let ray = Ray::new(origin, direction.normalize(), 1e-4, tmax);
                let fast = scene.trace_to_closest(&ray);
                let one_by_one = scene.trace_to_closest_with(&ray, &Kernels);
                assert_eq!(
                    format!("{fast:?}"),
                    format!("{one_by_one:?}"),
                    "{name}: {ray:?}"
                );
                assert_eq!(
                    scene.trace_to_any(&ray),
                    scene.trace_to_any_with(&ray, &Kernels),
                    "{name}: {ray:?}"
                );
                hits += fast.is_some() as u32;
            }
            assert!(
                hits > 2000,
                "{name}: only {hits} hits, the test is too weak"
            );
        }
    }
}
