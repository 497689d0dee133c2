//! A BVH over the triangles of a mesh that keeps their vertices in its leaf order, four
//! triangles to a block side by side, so that a leaf's triangles are read from consecutive
//! memory and tested in SIMD lanes by the built-in watertight test.

use glam::Vec3;

use super::Bvh;
use super::bvh::HOLE;
use super::stats::{Counter, TraversalStats};
use crate::geometry::{TriangleBlock, TriangleRay};
use crate::math::{Aabb, Ray};

/// Triangles per block: leaves start at a multiple of this slot.
const BLOCK: usize = 4;

/// A [`Bvh`] over triangles, with each triangle's three vertices stored in leaf order.
///
/// Two kinds of query: with the built-in watertight test
/// ([`closest_hit_watertight`](Self::closest_hit_watertight),
/// [`any_hit_watertight`](Self::any_hit_watertight)), which tests a leaf's triangles four at a
/// time; and with any triangle test given as a closure ([`closest_hit`](Self::closest_hit),
/// [`any_hit`](Self::any_hit)), one triangle at a time — a student's lab02 code, say. Both
/// report the triangle by its index in the list given to [`TriangleBvh::build`] (the face index
/// of a mesh).
#[derive(Debug, Clone, Default)]
pub struct TriangleBvh {
    /// The hierarchy, with every leaf starting at a multiple of [`BLOCK`] slots.
    bvh: Bvh,
    /// `blocks[b]` holds the triangles in leaf slots `4b..4b + 4` (empty lanes for holes).
    blocks: Vec<TriangleBlock>,
}

/// A closest hit of the built-in watertight test: the face, the ray parameter and the
/// barycentrics, as [`intersect_triangle`](crate::geometry::intersect_triangle) returns them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshHit {
    /// Index of the triangle in the list given to [`TriangleBvh::build`].
    pub face: u32,
    /// Ray parameter of the hit.
    pub t: f32,
    /// Weight of the triangle's second vertex.
    pub beta: f32,
    /// Weight of the triangle's third vertex.
    pub gamma: f32,
}

impl TriangleBvh {
    /// Builds the hierarchy over `triangles` (see [`Bvh::build`]).
    ///
    /// # Panics
    ///
    /// If the leaves, padded to blocks of four, need more than 2²⁸ slots (at least 2²⁶ = 67
    /// million triangles).
    pub fn build(triangles: &[[Vec3; 3]]) -> TriangleBvh {
        let bounds: Vec<Aabb> = triangles.iter().map(|&t| Aabb::from_points(t)).collect();
        let bvh = Bvh::build_with_leaf_alignment(&bounds, BLOCK);
        let order = bvh.leaf_order();
        let mut blocks = vec![TriangleBlock::EMPTY; order.len().div_ceil(BLOCK)];
        for (slot, &face) in order.iter().enumerate() {
            if face != HOLE {
                blocks[slot / BLOCK].set(slot % BLOCK, triangles[face as usize]);
            }
        }
        TriangleBvh { bvh, blocks }
    }

    /// The hierarchy over the triangles' boxes.
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// The vertices of the triangle in leaf slot `slot`.
    #[inline(always)]
    fn triangle(&self, slot: u32) -> [Vec3; 3] {
        let slot = slot as usize;
        self.blocks[slot / BLOCK].get(slot % BLOCK)
    }

    /// The blocks that hold the leaf with slots `first..first + count`.
    #[inline(always)]
    fn leaf_blocks(&self, first: usize, count: usize) -> &[TriangleBlock] {
        &self.blocks[first / BLOCK..(first + count).div_ceil(BLOCK)]
    }

    /// Finds the closest triangle along `ray` with the built-in watertight test
    /// ([`intersect_triangle`](crate::geometry::intersect_triangle)), four triangles at a time;
    /// the answer is bit for bit the one [`closest_hit`](Self::closest_hit) gives with that test
    /// (the same hit, also between triangles at the same `t`).
    #[inline]
    pub fn closest_hit_watertight(&self, ray: &Ray) -> Option<MeshHit> {
        self.closest_hit_watertight_with(ray, &mut ())
    }

    /// [`closest_hit_watertight`](Self::closest_hit_watertight), adding the work done to
    /// `stats`.
    pub fn closest_hit_watertight_counted(
        &self,
        ray: &Ray,
        stats: &mut TraversalStats,
    ) -> Option<MeshHit> {
        self.closest_hit_watertight_with(ray, stats)
    }

    #[inline(always)]
    fn closest_hit_watertight_with(&self, ray: &Ray, stats: &mut impl Counter) -> Option<MeshHit> {
        let prepared = TriangleRay::new(ray);
        let mut ray = *ray;
        let mut closest = None;
        self.bvh.traverse_leaves(
            &mut ray,
            |first, count, ray| {
                for (b, block) in (first / BLOCK..).zip(self.leaf_blocks(first, count)) {
                    let hits = prepared.intersect4(ray, block);
                    // Lanes in slot order, each against the closest hit so far: what testing
                    // the triangles one by one with `closest_hit` would accept.
                    let mut mask = hits.mask;
                    while mask != 0 {
                        let lane = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        let t = hits.t[lane & (BLOCK - 1)];
                        if t <= ray.tmax {
                            ray.tmax = t;
                            closest = Some((BLOCK * b + lane, t, hits.barycentrics(lane)));
                        }
                    }
                }
                false
            },
            stats,
        );
        closest.map(|(slot, t, (beta, gamma))| MeshHit {
            face: self.bvh.leaf_order()[slot],
            t,
            beta,
            gamma,
        })
    }

    /// Whether any triangle intersects `ray` with the built-in watertight test, four triangles
    /// at a time; stops at the first leaf with a hit.
    #[inline]
    pub fn any_hit_watertight(&self, ray: &Ray) -> bool {
        self.any_hit_watertight_with(ray, &mut ())
    }

    /// [`any_hit_watertight`](Self::any_hit_watertight), adding the work done to `stats`.
    pub fn any_hit_watertight_counted(&self, ray: &Ray, stats: &mut TraversalStats) -> bool {
        self.any_hit_watertight_with(ray, stats)
    }

    #[inline(always)]
    fn any_hit_watertight_with(&self, ray: &Ray, stats: &mut impl Counter) -> bool {
        let prepared = TriangleRay::new(ray);
        let mut ray = *ray;
        self.bvh.traverse_leaves(
            &mut ray,
            |first, count, ray| {
                self.leaf_blocks(first, count)
                    .iter()
                    .any(|block| prepared.intersect4(ray, block).mask != 0)
            },
            stats,
        )
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
            .closest_hit_in_leaf_order(ray, |k, r| intersect(&self.triangle(k), r), &mut ())
            .map(|(k, t)| (self.bvh.leaf_order()[k as usize], t))
    }

    /// Whether any triangle intersects `ray`; stops at the first one `intersect` reports hit
    /// (see [`Bvh::any_hit`]).
    #[inline]
    pub fn any_hit<F: FnMut(&[Vec3; 3], &Ray) -> bool>(&self, ray: &Ray, mut intersect: F) -> bool {
        self.bvh
            .any_hit_in_leaf_order(ray, |k, r| intersect(&self.triangle(k), r), &mut ())
    }

    /// [`closest_hit`](Self::closest_hit), adding the work done to `stats`.
    pub fn closest_hit_counted<F: FnMut(&[Vec3; 3], &Ray) -> Option<f32>>(
        &self,
        ray: &Ray,
        mut intersect: F,
        stats: &mut TraversalStats,
    ) -> Option<(u32, f32)> {
        self.bvh
            .closest_hit_in_leaf_order(ray, |k, r| intersect(&self.triangle(k), r), stats)
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
            .any_hit_in_leaf_order(ray, |k, r| intersect(&self.triangle(k), r), stats)
    }
}
