//! A BVH over the triangles of a mesh that keeps their vertices in its leaf order, four
//! triangles to a block side by side, so that a leaf's triangles are read from consecutive
//! memory and tested in SIMD lanes by the built-in watertight test.

use glam::Vec3;

use super::Bvh;
use super::stats::{Counter, TraversalStats};
use super::wide::HOLE;
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
        let mut closest = None;
        self.bvh.traverse_leaves::<true>(
            ray,
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
        self.bvh.traverse_leaves::<false>(
            ray,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::TriangleRay;
    use crate::test_rng::Rng;

    /// A bumpy grid of `n × n` quads (two triangles each) over [-1, 1]², sharing edges and
    /// vertices, and a few random triangles through it.
    fn mesh(rng: &mut Rng, n: usize) -> Vec<[Vec3; 3]> {
        let p = |i: usize, j: usize| {
            let (x, y) = (
                i as f32 / n as f32 * 2.0 - 1.0,
                j as f32 / n as f32 * 2.0 - 1.0,
            );
            Vec3::new(x, y, 0.1 * (3.0 * x).sin() * (2.0 * y).cos())
        };
        let mut tris = Vec::new();
        for i in 0..n {
            for j in 0..n {
                tris.push([p(i, j), p(i + 1, j), p(i + 1, j + 1)]);
                tris.push([p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
            }
        }
        tris.extend((0..n).map(|_| [rng.vec(), rng.vec(), rng.vec()]));
        tris
    }

    #[test]
    fn watertight_queries_agree_with_one_triangle_at_a_time() {
        let mut rng = Rng::new(17);
        let tris = mesh(&mut rng, 24);
        let bvh = TriangleBvh::build(&tris);
        // The blocks hold every triangle once, in leaf order.
        let mut faces: Vec<u32> = bvh
            .bvh
            .leaf_order()
            .iter()
            .copied()
            .filter(|&f| f != HOLE)
            .collect();
        faces.sort_unstable();
        assert!(faces.iter().copied().eq(0..tris.len() as u32));
        for (slot, &f) in bvh.bvh.leaf_order().iter().enumerate() {
            if f != HOLE {
                assert_eq!(bvh.triangle(slot as u32), tris[f as usize]);
            }
        }
        for i in 0..20_000 {
            // Rays at grid vertices and edges (shared by several triangles: ties in `t`) and at
            // random points, some with a shrunk interval.
            let k = 2.0 / 24.0;
            let target = match i % 3 {
                0 => Vec3::new(
                    (rng.next() * 24.0).floor() * k - 1.0,
                    (rng.next() * 24.0).floor() * k - 1.0,
                    0.0,
                ),
                1 => Vec3::new(
                    (rng.next() * 24.0).floor() * k - 1.0,
                    rng.next() * 2.0 - 1.0,
                    0.0,
                ),
                _ => rng.vec(),
            };
            let origin = rng.vec() * 3.0;
            let mut ray = Ray::unbounded(origin, target - origin, 0.0);
            if i % 4 == 0 {
                (ray.tmin, ray.tmax) = (0.5 * rng.next(), 0.5 + rng.next());
            }
            let prepared = TriangleRay::new(&ray);
            let mut last = (0.0, 0.0);
            let scalar = bvh
                .closest_hit(&ray, |&[a, b, c], r| {
                    prepared.intersect(r, a, b, c).map(|(t, beta, gamma)| {
                        last = (beta, gamma);
                        t
                    })
                })
                .map(|(face, t)| MeshHit {
                    face,
                    t,
                    beta: last.0,
                    gamma: last.1,
                });
            let simd = bvh.closest_hit_watertight(&ray);
            let bits =
                |h: Option<MeshHit>| h.map(|h| (h.face, [h.t, h.beta, h.gamma].map(f32::to_bits)));
            assert_eq!(bits(simd), bits(scalar), "{ray:?}");
            let any = bvh.any_hit(&ray, |&[a, b, c], r| {
                prepared.intersect(r, a, b, c).is_some()
            });
            assert_eq!(bvh.any_hit_watertight(&ray), any, "{ray:?}");
            assert_eq!(any, scalar.is_some());
        }
    }

    #[test]
    fn empty_and_tiny_meshes() {
        let empty = TriangleBvh::build(&[]);
        let ray = Ray::unbounded(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z, 0.0);
        assert_eq!(empty.closest_hit_watertight(&ray), None);
        assert!(!empty.any_hit_watertight(&ray));
        let one = TriangleBvh::build(&[[Vec3::ZERO, Vec3::X, Vec3::Y]]);
        let hit = one.closest_hit_watertight(&ray).unwrap();
        assert_eq!(hit.face, 0);
        assert!((hit.t - 1.0).abs() < 1e-6 && (hit.beta - 0.2).abs() < 1e-6);
        assert!(one.any_hit_watertight(&ray));
    }
}
