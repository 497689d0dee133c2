//! The binned surface area heuristic builder (Wald 2007, "On fast Construction of SAH-based
//! Bounding Volume Hierarchies"): a binary tree over primitive bounding boxes, stored depth
//! first, with its leaves laid out in slot order.

use glam::{Vec3, Vec3A};

use crate::math::Aabb;

/// Number of SAH bins per axis.
const BINS: usize = 16;
/// Nodes with at most this many primitives always become leaves.
const MIN_LEAF: usize = 1;
/// Nodes with more primitives than this are split even when the SAH prefers a leaf.
pub(crate) const MAX_LEAF: usize = 8;
/// SAH cost of traversing an interior node (testing its two children): the unit of
/// [`leaf_cost`].
const TRAVERSAL_COST: f32 = 1.0;
/// Below this depth the builder switches from the SAH to balanced median splits, which bounds
/// the depth by `SAH_MAX_DEPTH + ⌈log₂ n⌉ ≤ 24 + 32 < MAX_DEPTH`.
const SAH_MAX_DEPTH: usize = 24;
/// Largest depth of the tree (the builder checks `depth() ≤ MAX_DEPTH`).
pub(crate) const MAX_DEPTH: usize = 64;
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

/// A slot of the leaf order that belongs to no leaf: padding before a leaf whose first slot is
/// aligned (see [`build`]).
pub(crate) const HOLE: u32 = u32::MAX;

/// The binary tree the builder makes, with the primitive indices in leaf order.
pub(crate) struct BinaryTree {
    /// The nodes, depth first; the root is `nodes[0]`.
    pub nodes: Vec<Node>,
    /// Primitive indices in leaf order ([`HOLE`] between aligned leaves).
    pub indices: Vec<u32>,
    /// Number of levels: 1 for a single leaf.
    pub depth: usize,
}

/// Builds the binary tree over at least one primitive with the given bounds (binned SAH,
/// deterministic), for primitives tested `alignment` at a time: the SAH counts a leaf's cost in
/// blocks of `alignment`, and every leaf's first slot is a multiple of `alignment` (the slots
/// between leaves are [`HOLE`]s).
///
/// Flat (zero-thickness) boxes, many primitives with the same centroid and empty boxes
/// (primitives that no ray can hit) are all fine.
pub(crate) fn build(bounds: &[Aabb], alignment: usize) -> BinaryTree {
    let n = bounds.len();
    debug_assert!(n > 0 && n <= u32::MAX as usize);
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
    BinaryTree {
        nodes,
        indices,
        depth,
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

/// One SAH bin: the bounds (corners in SIMD registers) and number of the primitives whose
/// centroid falls in it.
#[derive(Clone, Copy)]
struct Bin {
    min: Vec3A,
    max: Vec3A,
    count: usize,
}

impl Bin {
    const EMPTY: Bin = Bin {
        min: Vec3A::INFINITY,
        max: Vec3A::NEG_INFINITY,
        count: 0,
    };

    /// Grows the bounds to hold the box `lo..hi` (operands in the order that leaves a NaN
    /// corner out, as `f32::min` does); the count is the caller's.
    #[inline(always)]
    fn grow(&mut self, lo: Vec3A, hi: Vec3A) {
        self.min = lo.min(self.min);
        self.max = hi.max(self.max);
    }

    /// Grows this bin by `other`'s primitives.
    #[inline(always)]
    fn add(&mut self, other: &Bin) {
        self.grow(other.min, other.max);
        self.count += other.count;
    }

    /// The bounds as an [`Aabb`].
    fn aabb(&self) -> Aabb {
        Aabb::new(self.min.into(), self.max.into())
    }

    /// [`Aabb::surface_area`] of the bin's bounds, with the same operations.
    #[inline(always)]
    fn surface_area(&self) -> f32 {
        if self.min.cmpgt(self.max).any() {
            return 0.0;
        }
        let d = self.max - self.min;
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }
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
        // The bounds of the boxes and of the centroids, in SIMD registers.
        let (mut bounds, mut centroids) = (Bin::EMPTY, Bin::EMPTY);
        for p in prims.iter() {
            let c = Vec3A::from(p.centroid);
            bounds.grow(p.bounds.min.into(), p.bounds.max.into());
            centroids.grow(c, c);
        }
        let (bounds, centroids) = (bounds.aabb(), centroids.aabb());
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
    // Binned SAH over all three axes in one pass; costs are scaled by the parent's area. The
    // three bins of a primitive are found at once, and its box grows each in two SIMD
    // operations (the values of `Binning::bin` and `Aabb::union`, which `partition` and the
    // sweep below use).
    let binnings = [0, 1, 2].map(|axis| Binning::new(centroids, axis));
    let (origin, scale) = (
        Vec3A::from(centroids.min),
        Vec3A::from_array(binnings.map(|b| b.scale)),
    );
    let mut bins = [[Bin::EMPTY; BINS]; 3];
    for p in prims {
        let (lo, hi) = (Vec3A::from(p.bounds.min), Vec3A::from(p.bounds.max));
        let at = ((Vec3A::from(p.centroid) - origin) * scale).as_uvec3();
        for (axis, bins) in bins.iter_mut().enumerate() {
            if extent[axis] <= 0.0 {
                continue;
            }
            let bin = &mut bins[(at[axis] as usize).min(BINS - 1)];
            bin.grow(lo, hi);
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
        let mut acc = Bin::EMPTY;
        for k in (1..BINS).rev() {
            acc.add(&bins[k]);
            right_cost[k] = acc.surface_area() * cost_units(acc.count);
        }
        let mut acc = Bin::EMPTY;
        for k in 1..BINS {
            acc.add(&bins[k - 1]);
            let n = acc.count;
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
