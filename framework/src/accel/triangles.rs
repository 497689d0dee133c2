//! A BVH over the triangles of a mesh that keeps their vertices in its leaf order, so that a
//! leaf's triangles are read from consecutive memory instead of through face and vertex indices.

use glam::Vec3;

use super::Bvh;
use super::stats::TraversalStats;
use crate::math::{Aabb, Ray};

/// A [`Bvh`] over triangles, with each triangle's three vertices stored in leaf order.
///
/// Queries hand the triangle test the vertices `[v0, v1, v2]` and report the triangle by its
/// index in the list given to [`TriangleBvh::build`] (the face index of a mesh).
#[derive(Debug, Clone, Default)]
pub struct TriangleBvh {
    bvh: Bvh,
    /// `vertices[k]` is the triangle in leaf slot `k`.
    vertices: Vec<[Vec3; 3]>,
}

impl TriangleBvh {
    /// Builds the hierarchy over `triangles` (see [`Bvh::build`]).
    pub fn build(triangles: &[[Vec3; 3]]) -> TriangleBvh {
        let bounds: Vec<Aabb> = triangles.iter().map(|&t| Aabb::from_points(t)).collect();
        let bvh = Bvh::build(&bounds);
        let vertices = bvh
            .leaf_order()
            .iter()
            .map(|&f| triangles[f as usize])
            .collect();
        TriangleBvh { bvh, vertices }
    }

    /// The hierarchy over the triangles' boxes.
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// Finds the closest triangle along `ray`: its index and the ray parameter `t`.
    ///
    /// `intersect(vertices, ray)` has the contract of [`Bvh::closest_hit`]'s closure (in
    /// particular, the last call that returned `Some` is the closest hit).
    #[inline]
    pub fn closest_hit<F: FnMut(&[Vec3; 3], &Ray) -> Option<f32>>(
        &self,
        ray: &Ray,
        mut intersect: F,
    ) -> Option<(u32, f32)> {
        self.bvh
            .closest_hit_in_leaf_order(
                ray,
                |k, r| intersect(&self.vertices[k as usize], r),
                &mut (),
            )
            .map(|(k, t)| (self.bvh.leaf_order()[k as usize], t))
    }

    /// Whether any triangle intersects `ray`; stops at the first one `intersect` reports hit
    /// (see [`Bvh::any_hit`]).
    #[inline]
    pub fn any_hit<F: FnMut(&[Vec3; 3], &Ray) -> bool>(&self, ray: &Ray, mut intersect: F) -> bool {
        self.bvh.any_hit_in_leaf_order(
            ray,
            |k, r| intersect(&self.vertices[k as usize], r),
            &mut (),
        )
    }

    /// [`closest_hit`](Self::closest_hit), adding the work done to `stats`.
    pub fn closest_hit_counted<F: FnMut(&[Vec3; 3], &Ray) -> Option<f32>>(
        &self,
        ray: &Ray,
        mut intersect: F,
        stats: &mut TraversalStats,
    ) -> Option<(u32, f32)> {
        self.bvh
            .closest_hit_in_leaf_order(ray, |k, r| intersect(&self.vertices[k as usize], r), stats)
            .map(|(k, t)| (self.bvh.leaf_order()[k as usize], t))
    }

    /// [`any_hit`](Self::any_hit), adding the work done to `stats`.
    pub fn any_hit_counted<F: FnMut(&[Vec3; 3], &Ray) -> bool>(
        &self,
        ray: &Ray,
        mut intersect: F,
        stats: &mut TraversalStats,
    ) -> bool {
        self.bvh
            .any_hit_in_leaf_order(ray, |k, r| intersect(&self.vertices[k as usize], r), stats)
    }
}
