use glam::{Vec2, Vec3};

use super::Scene;
use crate::geometry::BuiltinIntersection;
use crate::labs::lab02::Intersection;
use crate::math::{Hit, Ray};

/// Which primitive a closest-hit query found, with what the intersection routine returned.
#[derive(Clone, Copy)]
enum Found {
    Plane(usize, Vec3),
    Sphere(usize, Vec3),
    Triangle(usize, Vec2, Vec3),
}

impl Scene {
    /// The closest surface along `ray` in `[tmin, tmax]` (DTU `RayTracer::trace_to_closest`),
    /// using the framework's intersection kernels.
    ///
    /// The same hit as `trace_to_closest_with(ray, &BuiltinIntersection)`, bit for bit, found
    /// faster: the triangles are tested four at a time
    /// ([`TriangleBvh::closest_hit_watertight`](crate::accel::TriangleBvh::closest_hit_watertight)).
    pub fn trace_to_closest(&self, ray: &Ray) -> Option<Hit> {
        self.closest_with(ray, &BuiltinIntersection, |r| {
            self.triangle_bvh.closest_hit_watertight(r).map(|h| {
                let [v0, v1, v2] = self.mesh.triangle(h.face as usize);
                let normal = BuiltinIntersection::triangle_normal(v0, v1, v2);
                (h.face, h.t, Vec2::new(h.beta, h.gamma), normal)
            })
        })
    }

    /// Whether anything lies along `ray` in `[tmin, tmax]` (DTU `RayTracer::trace_to_any`): the
    /// shadow-ray query, which may stop at the first hit it finds.
    pub fn trace_to_any(&self, ray: &Ray) -> bool {
        self.any_with(ray, &BuiltinIntersection, |r| {
            self.triangle_bvh.any_hit_watertight(r)
        })
    }

    /// [`trace_to_closest`](Self::trace_to_closest) with the primitive tests of `isect`
    /// (a student's lab02 code, say). As in the DTU framework, the answer of each test is
    /// trusted: a routine that ignores `tmin`/`tmax` changes which hit is "closest".
    pub fn trace_to_closest_with<I: Intersection + ?Sized>(
        &self,
        ray: &Ray,
        isect: &I,
    ) -> Option<Hit> {
        self.closest_with(ray, isect, |r| {
            let mut last = (Vec2::ZERO, Vec3::ZERO);
            self.triangle_bvh
                .closest_hit(r, |&[v0, v1, v2], r| {
                    isect.intersect_triangle(r, v0, v1, v2).map(|h| {
                        last = (Vec2::new(h.beta, h.gamma), h.normal);
                        h.distance
                    })
                })
                .map(|(f, t)| (f, t, last.0, last.1))
        })
    }

    /// The closest hit with `isect`'s plane and sphere tests and the triangle query
    /// `triangles(ray)`, which returns the face, `t`, the barycentrics and the normal.
    #[inline(always)]
    fn closest_with<I: Intersection + ?Sized>(
        &self,
        ray: &Ray,
        isect: &I,
        triangles: impl FnOnce(&Ray) -> Option<(u32, f32, Vec2, Vec3)>,
    ) -> Option<Hit> {
        let mut r = *ray;
        let mut found = None;
        for (i, plane) in self.planes.iter().enumerate() {
            if let Some(h) = isect.intersect_plane(&r, plane) {
                r.tmax = h.distance;
                found = Some(Found::Plane(i, h.normal));
            }
        }
        let mut sphere_normal = Vec3::ZERO;
        if let Some((i, t)) = self.sphere_bvh.closest_hit(&r, |i, r| {
            isect
                .intersect_sphere(r, &self.spheres[i as usize])
                .map(|h| {
                    sphere_normal = h.normal;
                    h.distance
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
        let (normal, shading_normal, texcoord, material) = match found {
            Found::Plane(i, n) => {
                let p = &self.planes[i];
                (n, n, p.texcoord(position), p.material)
            }
            Found::Sphere(i, n) => {
                let s = &self.spheres[i];
                (n, n, s.texcoord(position), s.material)
            }
            Found::Triangle(f, bary, n) => {
                let (shading, uv) = self.interpolate(f, bary, n);
                (n, shading, uv, self.mesh.face_materials[f])
            }
        };
        Some(Hit {
            distance: t,
            position,
            geometric_normal: normal,
            shading_normal,
            texcoord,
            material,
            trace_depth: 0,
            ior: 1.0,
        })
    }

    /// [`trace_to_any`](Self::trace_to_any) with the primitive tests of `isect`.
    pub fn trace_to_any_with<I: Intersection + ?Sized>(&self, ray: &Ray, isect: &I) -> bool {
        self.any_with(ray, isect, |r| {
            self.triangle_bvh.any_hit(r, |&[v0, v1, v2], r| {
                isect.intersect_triangle(r, v0, v1, v2).is_some()
            })
        })
    }

    /// Whether `isect`'s plane or sphere tests or the triangle query `triangles(ray)` find
    /// anything along `ray`.
    #[inline(always)]
    fn any_with<I: Intersection + ?Sized>(
        &self,
        ray: &Ray,
        isect: &I,
        triangles: impl FnOnce(&Ray) -> bool,
    ) -> bool {
        self.planes
            .iter()
            .any(|p| isect.intersect_plane(ray, p).is_some())
            || self.sphere_bvh.any_hit(ray, |i, r| {
                isect
                    .intersect_sphere(r, &self.spheres[i as usize])
                    .is_some()
            })
            || triangles(ray)
    }

    /// Shading normal and texture coordinates of face `f` at barycentrics `(β, γ)`: vertex
    /// attributes interpolated where the mesh has them, the geometric normal otherwise.
    fn interpolate(&self, f: usize, bary: Vec2, geometric: Vec3) -> (Vec3, Vec2) {
        let [a, b, c] = self.mesh.faces[f].map(|i| i as usize);
        let w = [1.0 - bary.x - bary.y, bary.x, bary.y];
        let mesh = &self.mesh;
        let shading = if mesh.normals.is_empty() {
            geometric
        } else {
            let n = w[0] * mesh.normals[a] + w[1] * mesh.normals[b] + w[2] * mesh.normals[c];
            let n = n.normalize_or_zero();
            if n == Vec3::ZERO || !n.is_finite() {
                geometric
            } else {
                n
            }
        };
        let uv = if mesh.texcoords.is_empty() {
            Vec2::ZERO
        } else {
            w[0] * mesh.texcoords[a] + w[1] * mesh.texcoords[b] + w[2] * mesh.texcoords[c]
        };
        (shading, uv)
    }
}
