//! A bounding volume hierarchy over primitive bounding boxes: the binary tree of the SAH
//! builder (`sah.rs`), collapsed into 8-wide nodes (`wide.rs`) that are traversed front to back
//! with a small stack and the slab test of `slabs.rs`.

use std::mem::MaybeUninit;

use super::sah::{self, BinaryTree};
#[cfg(target_arch = "x86_64")]
use super::slabs::Avx;
use super::slabs::{EXIT_SLACK, Portable, SlabTest, Slabs};
use super::stats::{Counter, TraversalStats};
use super::wide::{LEAF, MAX_PRIMITIVES, WIDTH, WideNode, WideTree, collapse, leaf_range};
use crate::math::{Aabb, Ray};

/// A bounding volume hierarchy over a set of primitives given by their bounding boxes.
///
/// The BVH only knows boxes: queries take a closure that intersects the ray with a primitive,
/// identified by its index in the slice given to [`Bvh::build`]. `Bvh::default()` is the empty
/// hierarchy, which no ray hits.
///
/// The builder makes a binary tree down to single primitives; queries traverse that tree
/// collapsed into 8-wide nodes, whose eight child boxes are tested at once, with the leaves
/// the collapse chose.
#[derive(Debug, Clone, Default)]
pub struct Bvh {
    /// Bounds of all primitives ([`Aabb::EMPTY`], the default, when there are none).
    bounds: Aabb,
    /// The binary tree collapsed into 8-wide nodes, root first.
    wide: Vec<WideNode>,
    /// Primitive indices in leaf order ([`HOLE`](super::wide::HOLE) between aligned leaves).
    indices: Vec<u32>,
    /// Number of primitives.
    len: usize,
    /// Levels of wide nodes.
    depth: usize,
}

impl Bvh {
    /// Builds the hierarchy over primitives with the given bounds (binned SAH, deterministic).
    ///
    /// Flat (zero-thickness) boxes, many primitives with the same centroid and empty boxes
    /// (primitives that no ray can hit) are all fine.
    ///
    /// # Panics
    ///
    /// If there are more than 2²⁸ (268 million) primitives.
    pub fn build(bounds: &[Aabb]) -> Bvh {
        Self::build_with_leaf_alignment(bounds, 1)
    }

    /// [`build`](Self::build) for primitives tested `alignment` at a time: the builder's and the
    /// collapse's SAH count primitives in blocks of `alignment`, and every leaf's first slot is
    /// a multiple of `alignment` (the slots between leaves are [`HOLE`](super::wide::HOLE)s).
    pub(crate) fn build_with_leaf_alignment(bounds: &[Aabb], alignment: usize) -> Bvh {
        let n = bounds.len();
        assert!(
            n <= MAX_PRIMITIVES,
            "a BVH holds at most {MAX_PRIMITIVES} primitives, got {n}"
        );
        if n == 0 {
            return Bvh::default();
        }
        let BinaryTree { nodes, order } = sah::build(bounds, alignment);
        let WideTree {
            nodes: wide,
            indices,
            depth,
        } = collapse(&nodes, &order, alignment);
        assert!(
            indices.len() <= MAX_PRIMITIVES,
            "a BVH holds at most {MAX_PRIMITIVES} slots, got {}",
            indices.len()
        );
        Bvh {
            bounds: Aabb::new(nodes[0].min, nodes[0].max),
            wide,
            indices,
            len: n,
            depth,
        }
    }

    /// Number of primitives.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the hierarchy holds no primitives.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Bounds of all primitives ([`Aabb::EMPTY`] for an empty hierarchy).
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Number of 8-wide nodes.
    pub fn node_count(&self) -> usize {
        self.wide.len()
    }

    /// Number of levels of 8-wide nodes: 0 when empty, 1 for the root alone.
    pub fn depth(&self) -> usize {
        self.depth
    }

    /// Finds the closest primitive along `ray`, returning its index and ray parameter `t`.
    ///
    /// `intersect(prim, ray)` must return `Some(t)` exactly when the primitive is hit at some
    /// `t` with `ray.tmin ≤ t ≤ ray.tmax` of the ray it is passed, and `None` otherwise. It is
    /// passed the query ray with `tmax` shrunk to the closest hit found so far; the nodes are
    /// visited front to back, nearer child first, and skipped once they start beyond `tmax`.
    ///
    /// Because `tmax` only shrinks, **the last call that returned `Some` is the closest hit**:
    /// a closure may record extra data (barycentrics, which mesh) each time it reports a hit,
    /// overwriting the previous record, and the final record belongs to the returned hit.
    ///
    /// The closure's answers are trusted: a `t` outside the ray's interval is taken as is (and
    /// becomes the new `tmax`), so a test that ignores `tmin`/`tmax` changes which hit wins.
    #[inline]
    pub fn closest_hit<F: FnMut(u32, &Ray) -> Option<f32>>(
        &self,
        ray: &Ray,
        intersect: F,
    ) -> Option<(u32, f32)> {
        self.closest_hit_with(ray, intersect, &mut ())
    }

    /// [`closest_hit`](Self::closest_hit), adding the work done to `stats`.
    pub fn closest_hit_counted<F: FnMut(u32, &Ray) -> Option<f32>>(
        &self,
        ray: &Ray,
        intersect: F,
        stats: &mut TraversalStats,
    ) -> Option<(u32, f32)> {
        self.closest_hit_with(ray, intersect, stats)
    }

    /// [`any_hit`](Self::any_hit), adding the work done to `stats`.
    pub fn any_hit_counted<F: FnMut(u32, &Ray) -> bool>(
        &self,
        ray: &Ray,
        mut intersect: F,
        stats: &mut TraversalStats,
    ) -> bool {
        self.any_hit_in_leaf_order(ray, |k, r| intersect(self.indices[k as usize], r), stats)
    }

    #[inline(always)]
    fn closest_hit_with<F: FnMut(u32, &Ray) -> Option<f32>>(
        &self,
        ray: &Ray,
        mut intersect: F,
        stats: &mut impl Counter,
    ) -> Option<(u32, f32)> {
        self.closest_hit_in_leaf_order(ray, |k, r| intersect(self.indices[k as usize], r), stats)
            .map(|(k, t)| (self.indices[k as usize], t))
    }

    /// The primitive indices in leaf order: the primitive in leaf slot `k` is `leaf_order()[k]`
    /// ([`HOLE`](super::wide::HOLE) for a slot between aligned leaves).
    pub(crate) fn leaf_order(&self) -> &[u32] {
        &self.indices
    }

    /// [`closest_hit`](Self::closest_hit) with primitives named by their leaf slot (see
    /// [`leaf_order`](Self::leaf_order)) instead of their index, both in the calls of
    /// `intersect` and in the result.
    #[inline(always)]
    pub(crate) fn closest_hit_in_leaf_order<F: FnMut(u32, &Ray) -> Option<f32>>(
        &self,
        ray: &Ray,
        mut intersect: F,
        stats: &mut impl Counter,
    ) -> Option<(u32, f32)> {
        let mut closest = None;
        self.traverse::<true>(
            ray,
            |slot, ray| {
                if let Some(t) = intersect(slot, ray) {
                    ray.tmax = t;
                    closest = Some((slot, t));
                }
                false
            },
            stats,
        );
        closest
    }

    /// [`any_hit`](Self::any_hit) with primitives named by their leaf slot.
    #[inline(always)]
    pub(crate) fn any_hit_in_leaf_order<F: FnMut(u32, &Ray) -> bool>(
        &self,
        ray: &Ray,
        mut intersect: F,
        stats: &mut impl Counter,
    ) -> bool {
        self.traverse::<false>(ray, |slot, ray| intersect(slot, ray), stats)
    }

    /// Whether any primitive intersects `ray`; stops at the first one `intersect` reports hit.
    ///
    /// `intersect(prim, ray)` returns whether the primitive is hit with `ray.tmin ≤ t ≤
    /// ray.tmax` (the ray is always the query ray itself); useful for shadow rays.
    #[inline]
    pub fn any_hit<F: FnMut(u32, &Ray) -> bool>(&self, ray: &Ray, mut intersect: F) -> bool {
        self.any_hit_in_leaf_order(ray, |k, r| intersect(self.indices[k as usize], r), &mut ())
    }

    /// [`traverse_leaves`](Self::traverse_leaves) calling `leaf_prim(slot, ray)` on the leaf
    /// slot of every primitive in a reached leaf; `leaf_prim` may shrink `ray.tmax` and stops
    /// the traversal by returning `true`. Returns whether it was stopped.
    #[inline(always)]
    fn traverse<const NEAREST_FIRST: bool>(
        &self,
        ray: &Ray,
        mut leaf_prim: impl FnMut(u32, &mut Ray) -> bool,
        stats: &mut impl Counter,
    ) -> bool {
        self.traverse_leaves::<NEAREST_FIRST>(
            ray,
            |first, count, ray| (first..first + count).any(|slot| leaf_prim(slot as u32, ray)),
            stats,
        )
    }

    /// Traversal calling `leaf(first, count, ray)` on every reached leaf, which holds the slots
    /// `first..first + count`; `leaf` may shrink `ray.tmax` and stops the traversal by returning
    /// `true`. Returns whether it was stopped.
    ///
    /// `NEAREST_FIRST` visits the children a node's slab test hits front to back, so that a
    /// shrinking `tmax` (a closest-hit search) skips the nodes behind the closest hit; without
    /// it, for a search that stops at the first hit (any-hit, whose `tmax` stays put and so
    /// reaches the same leaves in any order), the nearer of two children hit goes first and
    /// three or more are visited in lane order, unsorted, as Embree's occlusion queries visit
    /// them: sorting them cost shadow-like rays more than it saved (docs/performance.md).
    ///
    /// Runs the AVX slab test where the CPU has AVX and the portable one elsewhere; both give
    /// the same answers, so the visit order (and which of two hits at the same `t` wins) does
    /// not depend on the CPU.
    #[inline(always)]
    pub(crate) fn traverse_leaves<const NEAREST_FIRST: bool>(
        &self,
        ray: &Ray,
        leaf: impl FnMut(usize, usize, &mut Ray) -> bool,
        stats: &mut impl Counter,
    ) -> bool {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = Avx::detect() {
            // SAFETY: an `Avx` value exists only where the CPU has AVX.
            return unsafe { traverse_avx::<NEAREST_FIRST>(self, avx, ray, leaf, stats) };
        }
        self.traverse_with::<NEAREST_FIRST>(Portable, ray, leaf, stats)
    }

    /// [`traverse_leaves`](Self::traverse_leaves) with the slab test `slab_test`.
    ///
    /// Runs on the 8-wide nodes: each visit tests the boxes of up to eight children at once,
    /// continues with the nearest child hit and pushes the others, farthest first, with their
    /// entry distances, so that a popped node starting beyond the closest hit is skipped (in
    /// lane order and without that check unless `NEAREST_FIRST`).
    #[inline(always)]
    fn traverse_with<const NEAREST_FIRST: bool>(
        &self,
        slab_test: impl SlabTest,
        ray: &Ray,
        mut leaf: impl FnMut(usize, usize, &mut Ray) -> bool,
        stats: &mut impl Counter,
    ) -> bool {
        if self.wide.is_empty() {
            return false;
        }
        let slabs = Slabs::new(ray);
        // The closest hit so far shrinks this copy's `tmax`. The copy is made here, after the
        // set-up has read the caller's ray: a copy made just before and read back at once has its
        // direction loaded across two of the copy's stores, which the CPU cannot forward to the
        // load: a stall that cost bunny camera rays a fifth of their time (docs/performance.md).
        let ray = &mut ray.clone();
        let mut stack = Stack::new();
        let mut current = 0u32;
        loop {
            if current & LEAF != 0 {
                let (first, count) = leaf_range(current);
                stats.leaf(count);
                if leaf(first, count, ray) {
                    return true;
                }
            } else {
                stats.node();
                let node = &self.wide[current as usize];
                let (entry, mask) = slab_test.entries(&slabs, node, ray.tmin, ray.tmax);
                // `& (WIDTH - 1)` tells the compiler the lane is in bounds (the mask has
                // `WIDTH` bits).
                let lane = |mask: u32| mask.trailing_zeros() as usize & (WIDTH - 1);
                if mask != 0 {
                    // Most visits hit one or two children: those go without the sort below,
                    // in the order it would give them (ties keep the lower lane first, which
                    // decides which of two triangles at the same `t` a closest-hit reports).
                    let (first, rest) = (lane(mask), mask & (mask - 1));
                    if rest == 0 {
                        current = node.children[first];
                        continue;
                    }
                    // Two children hit: the nearer first, in both orders (for an any-hit
                    // search, the nearer is the likelier to hold a hit, and the comparison
                    // costs next to nothing).
                    let (second, rest_of_rest) = (lane(rest), rest & (rest - 1));
                    if rest_of_rest == 0 {
                        let a = (node.children[first], entry[first]);
                        let b = (node.children[second], entry[second]);
                        let (near, far) = if a.1 > b.1 { (b, a) } else { (a, b) };
                        stack.push(far);
                        current = near.0;
                        continue;
                    }
                    if !NEAREST_FIRST {
                        // Three or more: the first lane now, the others in lane order.
                        let mut rest = rest;
                        while rest != 0 {
                            let lane = lane(rest);
                            rest &= rest - 1;
                            stack.push((node.children[lane], entry[lane]));
                        }
                        current = node.children[first];
                        continue;
                    }
                    // Three or more children hit, nearest first (insertion sort).
                    let mut hits = [(0u32, 0f32); WIDTH];
                    let mut n = 0;
                    let mut mask = mask;
                    while mask != 0 {
                        let lane = lane(mask);
                        mask &= mask - 1;
                        let hit = (node.children[lane], entry[lane]);
                        let mut k = n;
                        while k > 0 && hits[k - 1].1 > hit.1 {
                            hits[k] = hits[k - 1];
                            k -= 1;
                        }
                        hits[k] = hit;
                        n += 1;
                    }
                    for &far in hits[1..n].iter().rev() {
                        stack.push(far);
                    }
                    current = hits[0].0;
                    continue;
                }
            }
            // Pop the next node that still starts before the closest hit.
            loop {
                let Some((node, t_entry)) = stack.pop() else {
                    return false;
                };
                if !NEAREST_FIRST || t_entry <= ray.tmax * EXIT_SLACK {
                    current = node;
                    break;
                }
            }
        }
    }
}

/// [`Bvh::traverse_with`] the AVX slab test, compiled for AVX (so the whole loop, with the
/// caller's primitive test, uses the 8-lane registers).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn traverse_avx<const NEAREST_FIRST: bool>(
    bvh: &Bvh,
    avx: Avx,
    ray: &Ray,
    leaf: impl FnMut(usize, usize, &mut Ray) -> bool,
    stats: &mut impl Counter,
) -> bool {
    bvh.traverse_with::<NEAREST_FIRST>(avx, ray, leaf, stats)
}

/// Entries of the traversal stack kept in place; deeper ones spill to the heap.
const STACK_INLINE: usize = 64;

/// The traversal stack of (node reference, entry distance) pairs.
///
/// Each wide node pushes at most seven children, so the stack can grow to seven times the
/// depth. Typical rays need far fewer entries than that: the first [`STACK_INLINE`] live in an
/// array (left uninitialised, so setting it up costs nothing per ray), the rest, for rare rays
/// in deep trees, in a vector.
struct Stack {
    /// `inline[..len.min(STACK_INLINE)]` are initialised.
    inline: [MaybeUninit<(u32, f32)>; STACK_INLINE],
    len: usize,
    spill: Vec<(u32, f32)>,
}

impl Stack {
    #[inline(always)]
    fn new() -> Self {
        Stack {
            inline: [const { MaybeUninit::uninit() }; STACK_INLINE],
            len: 0,
            spill: Vec::new(),
        }
    }

    #[inline(always)]
    fn push(&mut self, entry: (u32, f32)) {
        if self.len < STACK_INLINE {
            self.inline[self.len].write(entry);
        } else {
            self.spill.push(entry);
        }
        self.len += 1;
    }

    #[inline(always)]
    fn pop(&mut self) -> Option<(u32, f32)> {
        self.len = self.len.checked_sub(1)?;
        if self.len < STACK_INLINE {
            // SAFETY: `push` wrote every inline entry below the old length, and `len` only
            // shrinks by `pop`, so `inline[len]` was written and not yet popped.
            Some(unsafe { self.inline[self.len].assume_init() })
        } else {
            self.spill.pop()
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::super::sah::MAX_DEPTH;
    use super::super::wide::{HOLE, MAX_LEAF};
    use super::*;
    use crate::test_rng::Rng;

    /// Möller–Trumbore in `f64`, test-only: accurate enough that its hits lie in the boxes.
    fn hit_triangle(ray: &Ray, tri: [Vec3; 3]) -> Option<f32> {
        let [a, b, c] = tri.map(|v| v.as_dvec3());
        let (o, d) = (ray.origin.as_dvec3(), ray.direction.as_dvec3());
        let (e1, e2) = (b - a, c - a);
        let p = d.cross(e2);
        let det = e1.dot(p);
        if det == 0.0 {
            return None;
        }
        let s = o - a;
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let v = d.dot(q) / det;
        let t = (e2.dot(q) / det) as f32;
        (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && ray.accepts(t)).then_some(t)
    }

    /// Textbook sphere test in `f64`, test-only.
    fn hit_sphere(ray: &Ray, (center, radius): (Vec3, f32)) -> Option<f32> {
        let (o, d) = (ray.origin.as_dvec3(), ray.direction.as_dvec3());
        let (f, r) = (o - center.as_dvec3(), radius as f64);
        let (a, b, c) = (d.dot(d), f.dot(d), f.dot(f) - r * r);
        let disc = b * b - a * c;
        if disc < 0.0 {
            return None;
        }
        let s = disc.sqrt();
        [(-b - s) / a, (-b + s) / a]
            .into_iter()
            .map(|t| t as f32)
            .find(|&t| ray.accepts(t))
    }

    fn triangle_bounds(tris: &[[Vec3; 3]]) -> Vec<Aabb> {
        tris.iter().map(|t| Aabb::from_points(*t)).collect()
    }

    fn sphere_bounds(spheres: &[(Vec3, f32)]) -> Vec<Aabb> {
        spheres
            .iter()
            .map(|&(c, r)| Aabb::new(c - r, c + r))
            .collect()
    }

    fn random_triangles(rng: &mut Rng, n: usize) -> Vec<[Vec3; 3]> {
        (0..n)
            .map(|i| {
                let size = if i % 50 == 0 { 1.0 } else { 0.08 };
                let c = rng.vec();
                [
                    c + size * rng.vec(),
                    c + size * rng.vec(),
                    c + size * rng.vec(),
                ]
            })
            .collect()
    }

    /// Rays of many kinds: from outside and inside the scene bounds, random and axis-aligned
    /// directions, directions with one or two zero components, origins exactly on coordinates
    /// of primitive bounds (so slabs see `0·∞`), and limited `[tmin, tmax]`.
    fn random_ray(rng: &mut Rng, boxes: &[Aabb]) -> Ray {
        let mut origin = match rng.below(3) {
            0 => rng.vec() * 3.0,
            1 => rng.vec() * 0.9,
            _ => {
                let b = boxes[rng.below(boxes.len())];
                if rng.next() < 0.5 { b.min } else { b.max }
            }
        };
        let mut dir = match rng.below(4) {
            0 => [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z][rng.below(6)],
            1 => {
                // One or two zero components.
                let mut d = rng.vec();
                d[rng.below(3)] = if rng.next() < 0.5 { 0.0 } else { -0.0 };
                if rng.next() < 0.3 {
                    d[rng.below(3)] = 0.0;
                }
                d
            }
            _ => rng.vec(),
        };
        if dir.length_squared() < 1e-6 {
            dir = Vec3::new(0.3, -0.5, 0.8);
        }
        if rng.below(2) == 0 && origin.x.abs() < 3.0 {
            // Aim at a primitive from here, sometimes.
            let target = boxes[rng.below(boxes.len())].centroid();
            if (target - origin).length_squared() > 1e-6 {
                dir = target - origin;
                origin[rng.below(3)] += 0.0;
            }
        }
        let dir = dir.normalize();
        match rng.below(4) {
            0 => Ray::new(origin, dir, 0.1 * rng.next(), 0.5 + 2.0 * rng.next()),
            _ => Ray::unbounded(origin, dir, 0.0),
        }
    }

    fn brute_closest(
        n: usize,
        ray: &Ray,
        hit: impl Fn(usize, &Ray) -> Option<f32>,
    ) -> Option<(u32, f32)> {
        (0..n)
            .filter_map(|i| hit(i, ray).map(|t| (i as u32, t)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// Checks `closest_hit` and `any_hit` against brute force for `rays` random rays.
    fn check_against_brute_force(
        n: usize,
        boxes: &[Aabb],
        rays: usize,
        seed: u64,
        hit: impl Fn(usize, &Ray) -> Option<f32>,
    ) {
        let bvh = Bvh::build(boxes);
        assert_eq!(bvh.len(), n);
        assert!(bvh.depth() <= MAX_DEPTH);
        let mut rng = Rng::new(seed);
        let mut hits = 0;
        for _ in 0..rays {
            let ray = random_ray(&mut rng, boxes);
            let expected = brute_closest(n, &ray, &hit);
            let mut last = None;
            let got = bvh.closest_hit(&ray, |prim, r| {
                assert!(r.tmin == ray.tmin && r.tmax <= ray.tmax && r.origin == ray.origin);
                let t = hit(prim as usize, r);
                if t.is_some() {
                    last = Some(prim);
                }
                t
            });
            match (expected, got) {
                (None, None) => {}
                (Some((_, te)), Some((prim, t))) => {
                    hits += 1;
                    // Equal t, or on a near-tie (within rounding, such as at an edge shared by
                    // two triangles) another primitive.
                    assert!(
                        te <= t && t <= te + 1e-5 * (1.0 + te),
                        "{te} vs {t} for {ray:?}"
                    );
                    assert_eq!(hit(prim as usize, &ray), Some(t));
                    assert_eq!(last, Some(prim), "the last reported hit is the closest");
                }
                _ => panic!("brute force {expected:?}, BVH {got:?} for {ray:?}"),
            }
            let any = bvh.any_hit(&ray, |prim, r| {
                assert_eq!(r, &ray);
                hit(prim as usize, r).is_some()
            });
            assert_eq!(any, expected.is_some(), "{ray:?}");
        }
        assert!(
            hits > rays / 10,
            "only {hits} of {rays} rays hit: the test is too weak"
        );
    }

    #[test]
    fn triangle_soup_matches_brute_force() {
        let mut rng = Rng::new(1);
        let tris = random_triangles(&mut rng, 3000);
        let boxes = triangle_bounds(&tris);
        check_against_brute_force(tris.len(), &boxes, 5000, 2, |i, r| hit_triangle(r, tris[i]));
    }

    #[test]
    fn sphere_set_matches_brute_force() {
        let mut rng = Rng::new(3);
        let spheres: Vec<(Vec3, f32)> = (0..2000)
            .map(|i| {
                (
                    rng.vec(),
                    if i % 100 == 0 {
                        0.5
                    } else {
                        0.01 + 0.05 * rng.next()
                    },
                )
            })
            .collect();
        let boxes = sphere_bounds(&spheres);
        check_against_brute_force(spheres.len(), &boxes, 5000, 4, |i, r| {
            hit_sphere(r, spheres[i])
        });
    }

    #[test]
    fn axis_aligned_quads_with_flat_boxes_match_brute_force() {
        // A grid of axis-aligned quads (flat bounds), like the walls of a box scene, hit by rays
        // that run along and start on their planes.
        let mut tris = Vec::new();
        for i in 0..12 {
            for j in 0..12 {
                let (u, v) = (i as f32 / 6.0 - 1.0, j as f32 / 6.0 - 1.0);
                let s = 1.0 / 6.0;
                for axis in 0..3 {
                    let p = |a: f32, b: f32| {
                        let mut q = Vec3::splat(if axis == 0 { -0.5 } else { 0.25 * axis as f32 });
                        q[(axis + 1) % 3] = a;
                        q[(axis + 2) % 3] = b;
                        q
                    };
                    tris.push([p(u, v), p(u + s, v), p(u + s, v + s)]);
                    tris.push([p(u, v), p(u + s, v + s), p(u, v + s)]);
                }
            }
        }
        let boxes = triangle_bounds(&tris);
        check_against_brute_force(tris.len(), &boxes, 5000, 5, |i, r| hit_triangle(r, tris[i]));
    }

    #[test]
    fn empty_bvh_hits_nothing() {
        for bvh in [Bvh::default(), Bvh::build(&[])] {
            assert!(bvh.is_empty());
            assert_eq!((bvh.len(), bvh.node_count(), bvh.depth()), (0, 0, 0));
            assert!(bvh.bounds().is_empty());
            let ray = Ray::unbounded(Vec3::ZERO, Vec3::X, 0.0);
            assert_eq!(bvh.closest_hit(&ray, |_, _| panic!("no primitives")), None);
            assert!(!bvh.any_hit(&ray, |_, _| panic!("no primitives")));
        }
    }

    #[test]
    fn one_primitive() {
        let sphere = (Vec3::new(0.0, 0.0, -3.0), 1.0);
        let bvh = Bvh::build(&sphere_bounds(&[sphere]));
        assert_eq!((bvh.len(), bvh.node_count(), bvh.depth()), (1, 1, 1));
        assert_eq!(
            bvh.bounds(),
            Aabb::new(Vec3::new(-1.0, -1.0, -4.0), Vec3::new(1.0, 1.0, -2.0))
        );
        let hit = |_: u32, r: &Ray| hit_sphere(r, sphere);
        let ray = Ray::unbounded(Vec3::ZERO, -Vec3::Z, 0.0);
        assert_eq!(bvh.closest_hit(&ray, hit), Some((0, 2.0)));
        assert!(bvh.any_hit(&ray, |p, r| hit(p, r).is_some()));
        let away = Ray::unbounded(Vec3::ZERO, Vec3::Z, 0.0);
        assert_eq!(bvh.closest_hit(&away, hit), None);
        let short = Ray::new(Vec3::ZERO, -Vec3::Z, 0.0, 1.5);
        assert!(!bvh.any_hit(&short, |p, r| hit(p, r).is_some()));
    }

    #[test]
    fn identical_centroids_fall_back_to_median_splits() {
        // Concentric spheres and identical triangles: the SAH has nothing to bin.
        let spheres: Vec<(Vec3, f32)> = (0..1000)
            .map(|i| (Vec3::ZERO, 0.01 + 0.001 * i as f32))
            .collect();
        let boxes = sphere_bounds(&spheres);
        let bvh = Bvh::build(&boxes);
        assert!(bvh.depth() <= 10, "depth {}", bvh.depth());
        assert!(leaf_sizes(&bvh).iter().all(|&n| n <= MAX_LEAF));
        check_against_brute_force(spheres.len(), &boxes, 1000, 6, |i, r| {
            hit_sphere(r, spheres[i])
        });

        let tri = [
            Vec3::new(-1.0, -1.0, 0.5),
            Vec3::new(1.0, -1.0, 0.5),
            Vec3::new(0.0, 1.0, 0.5),
        ];
        let bvh = Bvh::build(&triangle_bounds(&vec![tri; 100]));
        assert!(leaf_sizes(&bvh).iter().all(|&n| n <= MAX_LEAF));
        let ray = Ray::unbounded(Vec3::ZERO, Vec3::Z, 0.0);
        let (_, t) = bvh.closest_hit(&ray, |_, r| hit_triangle(r, tri)).unwrap();
        assert_eq!(t, 0.5);
        let mut calls = 0;
        assert!(bvh.any_hit(&ray, |_, r| {
            calls += 1;
            hit_triangle(r, tri).is_some()
        }));
        assert_eq!(calls, 1, "any_hit stops at the first hit");
    }

    #[test]
    fn depth_stays_bounded_on_pathological_input() {
        // Geometrically growing boxes make SAH splits peel off one primitive at a time.
        let boxes: Vec<Aabb> = (0..20_000)
            .map(|i| {
                let x = 1.001f32.powi(i) - 1.0;
                Aabb::new(Vec3::new(x, 0.0, 0.0), Vec3::new(x * 1.5 + 1e-3, 1.0, 1.0))
            })
            .chain((0..100).map(|_| Aabb::EMPTY))
            .collect();
        let bvh = Bvh::build(&boxes);
        assert!(bvh.depth() <= MAX_DEPTH, "depth {}", bvh.depth());
        let mut rng = Rng::new(8);
        for _ in 0..200 {
            let ray = Ray::unbounded(Vec3::new(-1.0, rng.next(), rng.next()), Vec3::X, 0.0);
            assert!(bvh.any_hit(&ray, |i, _| i < 20_000));
        }
    }

    #[test]
    fn build_is_deterministic_and_well_formed() {
        for alignment in [1, 4] {
            check_well_formed(alignment);
        }
    }

    #[test]
    fn splits_counted_in_blocks_fill_the_blocks() {
        // The leaves of a tree whose splits count triangles in blocks of four leave fewer
        // empty lanes in their blocks than those of one that counts triangles one by one.
        let mut rng = Rng::new(12);
        let boxes = triangle_bounds(&random_triangles(&mut rng, 20_000));
        let holes = |block| {
            let BinaryTree { nodes, order } = sah::build(&boxes, block);
            let indices = collapse(&nodes, &order, 4).indices;
            indices.iter().filter(|&&i| i == HOLE).count()
        };
        let (by_block, by_primitive) = (holes(4), holes(1));
        assert!(
            10 * by_block < 9 * by_primitive,
            "{by_block} vs {by_primitive} holes"
        );
    }

    /// The primitive counts of the leaves of `bvh`'s wide tree.
    fn leaf_sizes(bvh: &Bvh) -> Vec<usize> {
        bvh.wide
            .iter()
            .flat_map(|node| {
                node.children
                    .iter()
                    .zip(node.planes[0].iter().zip(node.planes[3]))
            })
            .filter(|&(&child, (&min, max))| child & LEAF != 0 && min <= max)
            .map(|(&child, _)| leaf_range(child).1)
            .collect()
    }

    /// A build over 5000 random triangles with leaves aligned to `alignment` slots.
    fn check_well_formed(alignment: usize) {
        let mut rng = Rng::new(9);
        let tris = random_triangles(&mut rng, 5000);
        let boxes = triangle_bounds(&tris);
        let a = Bvh::build_with_leaf_alignment(&boxes, alignment);
        let b = Bvh::build_with_leaf_alignment(&boxes, alignment);
        assert_eq!(format!("{a:?}"), format!("{b:?}"));
        assert_eq!(a.len(), 5000);
        // Every primitive appears exactly once.
        let mut seen: Vec<u32> = a.indices.iter().copied().filter(|&p| p != HOLE).collect();
        seen.sort_unstable();
        assert!(seen.iter().copied().eq(0..5000));
        let contains = |outer: &Aabb, inner: Aabb| {
            outer.min.cmple(inner.min).all() && outer.max.cmpge(inner.max).all()
        };
        assert_eq!(
            a.bounds(),
            boxes.iter().fold(Aabb::EMPTY, |acc, b| acc.union(*b))
        );
        assert!(a.depth() < 20, "depth {}", a.depth());
        // The wide tree: every primitive in exactly one leaf, every child box inside its node's
        // binary counterpart's bounds (the root's: all primitives).
        let mut seen = Vec::new();
        let mut stack = vec![(0u32, a.bounds())];
        while let Some((child, bounds)) = stack.pop() {
            if child & LEAF != 0 {
                // Leaves start at aligned slots and hold at most `MAX_LEAF` primitives.
                let (first, count) = leaf_range(child);
                assert!(first.is_multiple_of(alignment) && count <= MAX_LEAF);
                for &p in &a.indices[first..first + count] {
                    assert!(contains(&bounds, boxes[p as usize]));
                    seen.push(p);
                }
                continue;
            }
            let node = &a.wide[child as usize];
            for lane in 0..WIDTH {
                let (min, max) = node.lane_box(lane);
                if min.x <= max.x {
                    assert!(bounds.min.cmple(min).all() && bounds.max.cmpge(max).all());
                    stack.push((node.children[lane], Aabb::new(min, max)));
                }
            }
        }
        seen.sort_unstable();
        assert!(seen.iter().copied().eq(0..5000));
        assert_eq!(std::mem::size_of::<WideNode>(), 224);
    }
}
