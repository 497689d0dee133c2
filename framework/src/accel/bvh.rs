//! A bounding volume hierarchy over primitive bounding boxes: a binary tree built with the
//! binned surface area heuristic, collapsed into 8-wide nodes that are traversed front to back
//! with a small stack.

use std::mem::MaybeUninit;

use glam::Vec3;

#[cfg(target_arch = "x86_64")]
use super::slabs::Avx;
use super::slabs::{EXIT_SLACK, Portable, SlabTest, Slabs};
use super::stats::{Counter, TraversalStats};
use super::wide::{LEAF, MAX_PRIMITIVES, WIDTH, WideNode, collapse, leaf_range};
use crate::math::{Aabb, Ray};

/// Number of SAH bins per axis.
const BINS: usize = 16;
/// Nodes with at most this many primitives always become leaves.
const MIN_LEAF: usize = 1;
/// Nodes with more primitives than this are split even when the SAH prefers a leaf.
const MAX_LEAF: usize = 8;
/// SAH cost of traversing an interior node (testing its two children): the unit of
/// [`leaf_cost`].
const TRAVERSAL_COST: f32 = 1.0;
/// Below this depth the builder switches from the SAH to balanced median splits, which bounds
/// the depth by `SAH_MAX_DEPTH + ⌈log₂ n⌉ ≤ 24 + 32 < MAX_DEPTH`.
const SAH_MAX_DEPTH: usize = 24;
/// Largest depth of the tree (the builder checks `depth() ≤ MAX_DEPTH`).
const MAX_DEPTH: usize = 64;
/// One node of the binary tree the builder makes: 32 bytes.
///
/// Nodes are stored depth first: an interior node's first child directly follows it, and
/// `index` holds its second child. A leaf (`count > 0`) owns `indices[index..index + count]`.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub(crate) struct Node {
    pub min: Vec3,
    pub index: u32,
    pub max: Vec3,
    pub count: u32,
}

/// A bounding volume hierarchy over a set of primitives given by their bounding boxes.
///
/// The BVH only knows boxes: queries take a closure that intersects the ray with a primitive,
/// identified by its index in the slice given to [`Bvh::build`]. `Bvh::default()` is the empty
/// hierarchy, which no ray hits.
///
/// The builder makes a binary tree (kept for [`bounds`](Self::bounds),
/// [`node_count`](Self::node_count) and [`depth`](Self::depth)); queries traverse the same tree
/// collapsed into 8-wide nodes, whose eight child boxes are tested at once.
#[derive(Debug, Clone, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// The binary tree collapsed into 8-wide nodes, root first.
    wide: Vec<WideNode>,
    /// Primitive indices in leaf order ([`HOLE`] between aligned leaves).
    indices: Vec<u32>,
    /// Number of primitives.
    len: usize,
    depth: usize,
}

/// A slot of [`Bvh::leaf_order`] that belongs to no leaf: padding before a leaf whose first
/// slot is aligned (see `Bvh::build_with_leaf_alignment`).
pub(crate) const HOLE: u32 = u32::MAX;

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

    /// [`build`](Self::build) for primitives tested `alignment` at a time: the SAH counts a
    /// leaf's cost in blocks of `alignment`, and every leaf's first slot is a multiple of
    /// `alignment` (the slots between leaves are [`HOLE`]s).
    pub(crate) fn build_with_leaf_alignment(bounds: &[Aabb], alignment: usize) -> Bvh {
        let n = bounds.len();
        assert!(
            n <= MAX_PRIMITIVES,
            "a BVH holds at most {MAX_PRIMITIVES} primitives, got {n}"
        );
        if n == 0 {
            return Bvh::default();
        }
        let prims = bounds
            .iter()
            .zip(0..)
            .map(|(&bounds, index)| {
                let c = bounds.centroid();
                BuildPrim {
                    bounds,
                    // Empty or unbounded boxes have no meaningful centroid; any point will do.
                    centroid: Vec3::select(c.is_finite_mask(), c, Vec3::ZERO),
                    index,
                }
            })
            .collect();
        let mut builder = Builder {
            block: alignment,
            prims,
            nodes: Vec::with_capacity(2 * n),
            depth: 0,
        };
        builder.build_node(0, n, 1);
        assert!(
            builder.depth <= MAX_DEPTH,
            "BVH depth {} exceeds {MAX_DEPTH}",
            builder.depth
        );
        let Builder {
            block: _,
            prims,
            mut nodes,
            depth,
        } = builder;
        // Lay the leaves out in slot order again, each starting at a multiple of `alignment`.
        let mut indices = Vec::with_capacity(n);
        for leaf in nodes.iter_mut().filter(|node| node.count > 0) {
            indices.resize(indices.len().next_multiple_of(alignment), HOLE);
            let first = leaf.index as usize;
            leaf.index = indices.len() as u32;
            indices.extend(
                prims[first..first + leaf.count as usize]
                    .iter()
                    .map(|p| p.index),
            );
        }
        assert!(
            indices.len() <= MAX_PRIMITIVES,
            "a BVH holds at most {MAX_PRIMITIVES} slots, got {}",
            indices.len()
        );
        Bvh {
            wide: collapse(&nodes),
            nodes,
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
        self.nodes
            .first()
            .map_or(Aabb::EMPTY, |n| Aabb::new(n.min, n.max))
    }

    /// Number of nodes (interior nodes and leaves).
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Number of levels: 0 when empty, 1 for a single leaf.
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
    /// ([`HOLE`] for a slot between aligned leaves).
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
        let mut ray = *ray;
        let mut closest = None;
        self.traverse(
            &mut ray,
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
        let mut ray = *ray;
        self.traverse(&mut ray, |slot, ray| intersect(slot, ray), stats)
    }

    /// Whether any primitive intersects `ray`; stops at the first one `intersect` reports hit.
    ///
    /// `intersect(prim, ray)` returns whether the primitive is hit with `ray.tmin ≤ t ≤
    /// ray.tmax` (the ray is always the query ray itself); useful for shadow rays.
    #[inline]
    pub fn any_hit<F: FnMut(u32, &Ray) -> bool>(&self, ray: &Ray, mut intersect: F) -> bool {
        self.any_hit_in_leaf_order(ray, |k, r| intersect(self.indices[k as usize], r), &mut ())
    }

    /// Front-to-back traversal calling `leaf_prim(slot, ray)` on the leaf slot of every
    /// primitive in a reached leaf; `leaf_prim` may shrink `ray.tmax` and stops the traversal
    /// by returning `true`. Returns whether it was stopped.
    #[inline(always)]
    fn traverse(
        &self,
        ray: &mut Ray,
        mut leaf_prim: impl FnMut(u32, &mut Ray) -> bool,
        stats: &mut impl Counter,
    ) -> bool {
        self.traverse_leaves(
            ray,
            |first, count, ray| (first..first + count).any(|slot| leaf_prim(slot as u32, ray)),
            stats,
        )
    }

    /// Front-to-back traversal calling `leaf(first, count, ray)` on every reached leaf, which
    /// holds the slots `first..first + count`; `leaf` may shrink `ray.tmax` and stops the
    /// traversal by returning `true`. Returns whether it was stopped.
    ///
    /// Runs the AVX slab test where the CPU has AVX and the portable one elsewhere; both give
    /// the same answers, so the visit order (and which of two hits at the same `t` wins) does
    /// not depend on the CPU.
    #[inline(always)]
    pub(crate) fn traverse_leaves(
        &self,
        ray: &mut Ray,
        leaf: impl FnMut(usize, usize, &mut Ray) -> bool,
        stats: &mut impl Counter,
    ) -> bool {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx) = Avx::detect() {
            // SAFETY: an `Avx` value exists only where the CPU has AVX.
            return unsafe { traverse_avx(self, avx, ray, leaf, stats) };
        }
        self.traverse_with(Portable, ray, leaf, stats)
    }

    /// [`traverse_leaves`](Self::traverse_leaves) with the slab test `slab_test`.
    ///
    /// Runs on the 8-wide nodes: each visit tests the boxes of up to eight children at once,
    /// continues with the nearest child hit and pushes the others, farthest first, with their
    /// entry distances, so that a popped node starting beyond the closest hit is skipped.
    #[inline(always)]
    fn traverse_with(
        &self,
        slab_test: impl SlabTest,
        ray: &mut Ray,
        mut leaf: impl FnMut(usize, usize, &mut Ray) -> bool,
        stats: &mut impl Counter,
    ) -> bool {
        if self.wide.is_empty() {
            return false;
        }
        let slabs = Slabs::new(ray);
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
                    let (second, rest) = (lane(rest), rest & (rest - 1));
                    if rest == 0 {
                        let a = (node.children[first], entry[first]);
                        let b = (node.children[second], entry[second]);
                        let (near, far) = if a.1 > b.1 { (b, a) } else { (a, b) };
                        stack.push(far);
                        current = near.0;
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
                if t_entry <= ray.tmax * EXIT_SLACK {
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
fn traverse_avx(
    bvh: &Bvh,
    avx: Avx,
    ray: &mut Ray,
    leaf: impl FnMut(usize, usize, &mut Ray) -> bool,
    stats: &mut impl Counter,
) -> bool {
    bvh.traverse_with(avx, ray, leaf, stats)
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

/// A primitive during the build; the builder reorders these in place.
#[derive(Clone, Copy)]
struct BuildPrim {
    bounds: Aabb,
    centroid: Vec3,
    index: u32,
}

/// Build state: the primitives (reordered into leaf order as the tree is built) and the nodes.
struct Builder {
    /// Primitives tested together in a leaf (the SAH's unit of intersection cost).
    block: usize,
    prims: Vec<BuildPrim>,
    nodes: Vec<Node>,
    depth: usize,
}

/// One SAH bin: the bounds and number of the primitives whose centroid falls in it.
#[derive(Clone, Copy)]
struct Bin {
    bounds: Aabb,
    count: usize,
}

impl Bin {
    const EMPTY: Bin = Bin {
        bounds: Aabb::EMPTY,
        count: 0,
    };
}

/// How to split a node's primitive range.
enum Split {
    /// Primitives whose centroid's bin along `axis` is below `bin` go left.
    Sah { axis: usize, bin: usize },
    /// Object median: the first half of the range (ordered along `axis`) goes left.
    Median { axis: usize },
}

impl Builder {
    /// Builds the subtree over `prims[start..end]` at `depth` (root = 1) and returns the index
    /// of its root node.
    fn build_node(&mut self, start: usize, end: usize, depth: usize) -> usize {
        self.depth = self.depth.max(depth);
        let prims = &mut self.prims[start..end];
        let (bounds, centroids) = prims.iter().fold((Aabb::EMPTY, Aabb::EMPTY), |(b, c), p| {
            (b.union(p.bounds), c.grow(p.centroid))
        });
        let node_index = self.nodes.len();
        self.nodes.push(Node {
            min: bounds.min,
            index: start as u32,
            max: bounds.max,
            count: prims.len() as u32,
        });
        let mid = match choose_split(prims, depth, &bounds, &centroids, self.block) {
            None => return node_index,
            Some(Split::Sah { axis, bin }) => {
                let binning = Binning::new(&centroids, axis);
                partition(prims, |p| binning.bin(p.centroid) < bin)
            }
            Some(Split::Median { axis }) => {
                let mid = prims.len() / 2;
                // Ties broken by primitive index: a total order, so the split is deterministic.
                let key = |p: &BuildPrim| (p.centroid[axis], p.index);
                prims.select_nth_unstable_by(mid, |a, b| key(a).partial_cmp(&key(b)).unwrap());
                mid
            }
        };
        debug_assert!(0 < mid && mid < end - start);
        self.build_node(start, start + mid, depth + 1);
        let right = self.build_node(start + mid, end, depth + 1);
        self.nodes[node_index].index = right as u32;
        self.nodes[node_index].count = 0;
        node_index
    }
}

/// The split for `prims` (with the given bounds and centroid bounds), or `None` for a leaf.
///
/// Leaf costs come from [`leaf_cost`].
fn choose_split(
    prims: &[BuildPrim],
    depth: usize,
    bounds: &Aabb,
    centroids: &Aabb,
    block: usize,
) -> Option<Split> {
    let count = prims.len();
    let cost_units = |n: usize| leaf_cost(n, block);
    if count <= MIN_LEAF {
        return None;
    }
    let extent = centroids.diagonal();
    let axis = centroids.longest_axis();
    if depth >= SAH_MAX_DEPTH || extent.max_element() <= 0.0 {
        // Deep in a degenerate tree, or all centroids identical: nothing for the SAH to
        // separate, so halve the range if it is too big for a leaf.
        return (count > MAX_LEAF).then_some(Split::Median { axis });
    }
    // Binned SAH over all three axes in one pass; costs are scaled by the parent's area.
    let binnings = [0, 1, 2].map(|axis| Binning::new(centroids, axis));
    let mut bins = [[Bin::EMPTY; BINS]; 3];
    for p in prims {
        for (axis, binning) in binnings.iter().enumerate() {
            let bin = &mut bins[axis][binning.bin(p.centroid)];
            bin.bounds = bin.bounds.union(p.bounds);
            bin.count += 1;
        }
    }
    let mut best: Option<(f32, usize, usize)> = None;
    for (axis, bins) in bins.iter().enumerate() {
        if extent[axis] <= 0.0 {
            continue;
        }
        // right_cost[k]: area × count of bins k.. (the right side of a split before bin k).
        let mut right_cost = [0.0f32; BINS];
        let (mut acc, mut n) = (Aabb::EMPTY, 0);
        for k in (1..BINS).rev() {
            acc = acc.union(bins[k].bounds);
            n += bins[k].count;
            right_cost[k] = acc.surface_area() * cost_units(n);
        }
        let (mut acc, mut n) = (Aabb::EMPTY, 0);
        for k in 1..BINS {
            acc = acc.union(bins[k - 1].bounds);
            n += bins[k - 1].count;
            if n == 0 || n == count {
                continue;
            }
            let cost = acc.surface_area() * cost_units(n) + right_cost[k];
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, k));
            }
        }
    }
    let area = bounds.surface_area();
    match best {
        Some((cost, axis, bin)) => {
            let worth_it = TRAVERSAL_COST * area + cost < area * cost_units(count);
            (count > MAX_LEAF || worth_it).then_some(Split::Sah { axis, bin })
        }
        // All centroids in one bin on every axis (tiny extents): split by the median.
        None => (count > MAX_LEAF).then_some(Split::Median { axis }),
    }
}

/// SAH cost of intersecting a leaf of `n` primitives that are tested `block` at a time, in
/// units of one node visit ([`TRAVERSAL_COST`]).
///
/// One at a time, a test costs one unit, so the leaf costs `n`. In blocks (four triangles in
/// SIMD lanes), a block costs two units plus half a unit per primitive for what still grows
/// with them (reading the block, accepting hits lane by lane): `2·(⌈n/4⌉ + n/4)`. Of the
/// models measured on the Cornell box and the bunny (docs/performance.md), counting blocks
/// alone made leaves too big for the Cornell box's walls, counting primitives alone too small
/// for the bunny, and a block at one node visit made the tree too shallow.
fn leaf_cost(n: usize, block: usize) -> f32 {
    if block == 1 {
        n as f32
    } else {
        2.0 * (n.div_ceil(block) as f32 + n as f32 / block as f32)
    }
}

/// Maps centroids to SAH bins along one axis of the centroid bounds.
struct Binning {
    axis: usize,
    min: f32,
    scale: f32,
}

impl Binning {
    fn new(centroids: &Aabb, axis: usize) -> Self {
        Self {
            axis,
            min: centroids.min[axis],
            scale: BINS as f32 / centroids.diagonal()[axis],
        }
    }

    #[inline]
    fn bin(&self, c: Vec3) -> usize {
        // `as` saturates (and maps NaN, from a zero extent, to 0): only the top needs clamping.
        (((c[self.axis] - self.min) * self.scale) as usize).min(BINS - 1)
    }
}

/// Moves the items satisfying `left` to the front and returns how many there are.
fn partition<T>(items: &mut [T], left: impl Fn(&T) -> bool) -> usize {
    let mut mid = 0;
    for i in 0..items.len() {
        if left(&items[i]) {
            items.swap(i, mid);
            mid += 1;
        }
    }
    mid
}

#[cfg(test)]
mod tests {
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
    fn slab_test_handles_zero_direction_components() {
        let node = Node {
            min: Vec3::ZERO,
            index: 0,
            max: Vec3::ONE,
            count: 1,
        };
        let flat = Node {
            max: Vec3::new(1.0, 1.0, 0.0),
            ..node
        };
        // The box in lane 2 of a wide node, the other lanes empty.
        let entry = |o: Vec3, d: Vec3, n: &Node| {
            let mut wide = collapse(&[*n])[0];
            wide.set_lane(2, n.min, n.max, 0);
            wide.set_lane(0, Vec3::INFINITY, Vec3::NEG_INFINITY, 0);
            let slabs = Slabs::new(&Ray::unbounded(o, d, 0.0));
            let (t, mask) = Portable.entries(&slabs, &wide, 0.0, f32::INFINITY);
            #[cfg(target_arch = "x86_64")]
            if let Some(avx) = Avx::detect() {
                let (t_avx, mask_avx) = avx.entries(&slabs, &wide, 0.0, f32::INFINITY);
                assert_eq!(mask_avx, mask);
                assert_eq!(t_avx.map(f32::to_bits), t.map(f32::to_bits));
            }
            assert_eq!(mask & !0b100, 0, "empty lanes are never entered");
            (mask != 0).then_some(t[2])
        };
        for d in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(0.0, 0.6, 0.8),
            Vec3::new(-0.0, -0.6, -0.8),
        ] {
            // On the min and max faces of a slab the ray runs parallel to: inside.
            for o in [
                Vec3::new(0.0, 0.5, 0.5),
                Vec3::new(1.0, 0.5, 0.5),
                Vec3::new(0.0, 0.0, 0.5),
            ] {
                assert_eq!(entry(o, d, &node), Some(0.0), "{o} {d}");
            }
            // Just outside: miss.
            assert_eq!(entry(Vec3::new(-1e-6, 0.5, 0.5), d, &node), None);
            assert_eq!(entry(Vec3::new(1.0 + 1e-6, 0.5, 0.5), d, &node), None);
        }
        // A flat box, approached from outside within its plane and across it.
        assert_eq!(entry(Vec3::new(-1.0, 0.5, 0.0), Vec3::X, &flat), Some(1.0));
        assert_eq!(entry(Vec3::new(0.5, 0.5, 2.0), -Vec3::Z, &flat), Some(2.0));
        assert_eq!(entry(Vec3::new(-1.0, 0.5, 1e-6), Vec3::X, &flat), None);
        // From outside along an axis.
        assert_eq!(entry(Vec3::new(0.5, 0.5, -2.0), Vec3::Z, &node), Some(2.0));
        assert_eq!(entry(Vec3::new(0.5, 0.5, 3.0), -Vec3::Z, &node), Some(2.0));
        assert_eq!(entry(Vec3::new(0.5, 0.5, 3.0), Vec3::Z, &node), None);
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
        assert!(bvh.nodes.iter().all(|n| n.count as usize <= MAX_LEAF));
        check_against_brute_force(spheres.len(), &boxes, 1000, 6, |i, r| {
            hit_sphere(r, spheres[i])
        });

        let tri = [
            Vec3::new(-1.0, -1.0, 0.5),
            Vec3::new(1.0, -1.0, 0.5),
            Vec3::new(0.0, 1.0, 0.5),
        ];
        let bvh = Bvh::build(&triangle_bounds(&vec![tri; 100]));
        assert!(bvh.nodes.iter().all(|n| n.count as usize <= MAX_LEAF));
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

    /// A build over 5000 random triangles with leaves aligned to `alignment` slots.
    fn check_well_formed(alignment: usize) {
        let mut rng = Rng::new(9);
        let tris = random_triangles(&mut rng, 5000);
        let boxes = triangle_bounds(&tris);
        let a = Bvh::build_with_leaf_alignment(&boxes, alignment);
        let b = Bvh::build_with_leaf_alignment(&boxes, alignment);
        assert_eq!(format!("{a:?}"), format!("{b:?}"));
        assert_eq!(a.len(), 5000);
        // Every primitive appears exactly once, node bounds contain their contents, leaves
        // start at aligned slots.
        let mut seen: Vec<u32> = a.indices.iter().copied().filter(|&p| p != HOLE).collect();
        seen.sort_unstable();
        assert!(seen.iter().copied().eq(0..5000));
        assert!(
            a.nodes
                .iter()
                .all(|n| n.count == 0 || (n.index as usize).is_multiple_of(alignment))
        );
        let contains = |outer: &Node, inner: Aabb| {
            outer.min.cmple(inner.min).all() && outer.max.cmpge(inner.max).all()
        };
        for (i, n) in a.nodes.iter().enumerate() {
            if n.count > 0 {
                assert!(n.count as usize <= MAX_LEAF);
                let prims = &a.indices[n.index as usize..(n.index + n.count) as usize];
                assert!(prims.iter().all(|&p| contains(n, boxes[p as usize])));
            } else {
                let right = n.index as usize;
                assert!(right > i + 1 && right < a.nodes.len());
                assert!(contains(
                    n,
                    Aabb::new(a.nodes[i + 1].min, a.nodes[i + 1].max)
                ));
                assert!(contains(
                    n,
                    Aabb::new(a.nodes[right].min, a.nodes[right].max)
                ));
            }
        }
        assert_eq!(
            a.bounds(),
            boxes.iter().fold(Aabb::EMPTY, |acc, b| acc.union(*b))
        );
        assert!(a.depth() < 40, "depth {}", a.depth());
        assert_eq!(std::mem::size_of::<Node>(), 32);
        // The wide tree: every primitive in exactly one leaf, every child box inside its node's
        // binary counterpart's bounds (the root's: all primitives).
        let mut seen = Vec::new();
        let mut stack = vec![(0u32, a.bounds())];
        while let Some((child, bounds)) = stack.pop() {
            if child & LEAF != 0 {
                let (first, count) = leaf_range(child);
                for &p in &a.indices[first..first + count] {
                    assert!(contains(
                        &Node {
                            min: bounds.min,
                            max: bounds.max,
                            index: 0,
                            count: 0
                        },
                        boxes[p as usize]
                    ));
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
