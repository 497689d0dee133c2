//! The binned surface area heuristic builder (Wald 2007, "On fast Construction of SAH-based
//! Bounding Volume Hierarchies"): a binary tree over primitive bounding boxes, stored depth
//! first, down to one primitive per leaf. The collapse into wide nodes (`wide.rs`) decides
//! which subtrees become leaves.
//!
//! For primitives tested a block at a time (four triangles in SIMD lanes), the SAH counts each
//! side of a split in blocks, `⌈n / block⌉`, as Embree's builders do: splits then tend to leave
//! subtrees of whole blocks, so that the leaves the collapse makes of them fill their blocks.

use glam::{Vec3, Vec3A};

use crate::math::Aabb;

/// Number of SAH bins per axis.
const BINS: usize = 16;
/// Nodes of at most this many primitives are split by a full sweep instead of binning.
const SMALL_NODE: usize = 12;
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

/// The binary tree the builder makes, with the primitive indices in build order.
pub(crate) struct BinaryTree {
    /// The nodes, depth first; the root is `nodes[0]`.
    pub nodes: Vec<Node>,
    /// Primitive indices in build order: a leaf owns `order[index..index + count]`, and every
    /// subtree a contiguous range.
    pub order: Vec<u32>,
}

/// Builds the binary tree over at least one primitive with the given bounds (binned SAH,
/// deterministic), down to one primitive per leaf, for primitives tested `block` at a time, a
/// power of two (see the module's documentation; 1 counts primitives one by one).
///
/// Flat (zero-thickness) boxes, many primitives with the same centroid and empty boxes
/// (primitives that no ray can hit) are all fine.
pub(crate) fn build(bounds: &[Aabb], block: usize) -> BinaryTree {
    let n = bounds.len();
    debug_assert!(n > 0 && n <= u32::MAX as usize);
    assert!(block.is_power_of_two(), "block of {block} primitives");
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
        prims,
        nodes: Vec::with_capacity(2 * n),
        depth: 0,
        block_shift: block.trailing_zeros(),
    };
    builder.build_node(0, n, 1);
    assert!(
        builder.depth <= MAX_DEPTH,
        "BVH depth {} exceeds {MAX_DEPTH}",
        builder.depth
    );
    BinaryTree {
        order: builder.prims.iter().map(|p| p.index).collect(),
        nodes: builder.nodes,
    }
}

/// A primitive during the build; the builder reorders these in place.
#[derive(Clone, Copy, Debug)]
struct BuildPrim {
    bounds: Aabb,
    centroid: Vec3,
    index: u32,
}

/// Build state: the primitives (reordered into leaf order as the tree is built) and the nodes.
struct Builder {
    prims: Vec<BuildPrim>,
    nodes: Vec<Node>,
    depth: usize,
    /// Primitives per block, the SAH's unit of count, as a power of two: `1 << block_shift`.
    block_shift: u32,
}

/// The SAH weight of `n` primitives tested `1 << block_shift` at a time: the number of blocks
/// (by a shift: a division by a number known only at run time would slow the sweeps down).
#[inline(always)]
fn blocks(n: usize, block_shift: u32) -> f32 {
    ((n + (1 << block_shift) - 1) >> block_shift) as f32
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

impl BuildPrim {
    /// The primitive's place in the order along `axis` of ordered splits: by centroid, ties
    /// broken by primitive index (a total order, so the split is deterministic). One integer,
    /// so that sorting compares integers: the centroid's bits mapped so that their order as
    /// integers is the numbers' (`-0.0` made `0.0` first, which compares equal to it), then
    /// the index.
    #[inline(always)]
    fn order_key(&self, axis: usize) -> u64 {
        let bits = (self.centroid[axis] + 0.0).to_bits();
        let ordered = if bits >> 31 != 0 {
            !bits
        } else {
            bits | 1 << 31
        };
        (ordered as u64) << 32 | self.index as u64
    }
}

/// How to split a node's primitive range.
enum Split {
    /// Primitives whose centroid's bin along `axis` is below `bin` go left.
    Sah { axis: usize, bin: usize },
    /// The first `mid` primitives of the range ordered along `axis` (by centroid, then index)
    /// go left: the object median, or the best of a full sweep.
    Ordered { axis: usize, mid: usize },
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
        let mid = match choose_split(prims, depth, &centroids, self.block_shift) {
            None => return node_index,
            Some(Split::Sah { axis, bin }) => {
                let binning = Binning::new(&centroids, axis);
                partition(prims, |p| binning.bin(p.centroid) < bin)
            }
            Some(Split::Ordered { axis, mid }) => {
                prims.select_nth_unstable_by_key(mid, |p| p.order_key(axis));
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

/// The split for `prims` (with the given centroid bounds), or `None` for a leaf:
/// every node of more than one primitive is split, at the plane of least SAH cost (each side's
/// surface area times its number of blocks of `1 << block_shift` primitives).
fn choose_split(
    prims: &[BuildPrim],
    depth: usize,
    centroids: &Aabb,
    block_shift: u32,
) -> Option<Split> {
    let count = prims.len();
    if count <= 1 {
        return None;
    }
    let extent = centroids.diagonal();
    let axis = centroids.longest_axis();
    if depth >= SAH_MAX_DEPTH || extent.max_element() <= 0.0 {
        // Deep in a degenerate tree, or all centroids identical: nothing for the SAH to
        // separate, so halve the range.
        return Some(Split::Ordered {
            axis,
            mid: count / 2,
        });
    }
    if count <= SMALL_NODE {
        return Some(sweep_small(prims, block_shift));
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
        // right_cost[k]: area × blocks of bins k.. (the right side of a split before bin k).
        let mut right_cost = [0.0f32; BINS];
        let mut acc = Bin::EMPTY;
        for k in (1..BINS).rev() {
            acc.add(&bins[k]);
            right_cost[k] = acc.surface_area() * blocks(acc.count, block_shift);
        }
        let mut acc = Bin::EMPTY;
        for k in 1..BINS {
            acc.add(&bins[k - 1]);
            let n = acc.count;
            if n == 0 || n == count {
                continue;
            }
            let cost = acc.surface_area() * blocks(n, block_shift) + right_cost[k];
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, k));
            }
        }
    }
    Some(match best {
        Some((_, axis, bin)) => Split::Sah { axis, bin },
        // All centroids in one bin on every axis (tiny extents): split by the median.
        None => Split::Ordered {
            axis,
            mid: count / 2,
        },
    })
}

/// The split of a small node (at most [`SMALL_NODE`] primitives) of least SAH cost over every
/// position along every axis with the primitives ordered by centroid: exact where binning is
/// coarse, and cheaper than binning for so few.
fn sweep_small(prims: &[BuildPrim], block_shift: u32) -> Split {
    let n = prims.len();
    debug_assert!((2..=SMALL_NODE).contains(&n));
    let mut best = (f32::INFINITY, 0, n / 2);
    let mut order = [0u8; SMALL_NODE];
    let mut keys = [0u64; SMALL_NODE];
    for axis in 0..3 {
        let order = &mut order[..n];
        for (i, (o, k)) in order.iter_mut().zip(&mut keys).enumerate() {
            *o = i as u8;
            *k = prims[i].order_key(axis);
        }
        order.sort_unstable_by_key(|&i| keys[i as usize]);
        // right[k]: the bounds of order[k..].
        let mut right = [Bin::EMPTY; SMALL_NODE];
        let mut acc = Bin::EMPTY;
        for k in (1..n).rev() {
            let b = &prims[order[k] as usize].bounds;
            acc.grow(b.min.into(), b.max.into());
            right[k] = acc;
        }
        let mut left = Bin::EMPTY;
        for k in 1..n {
            let b = &prims[order[k - 1] as usize].bounds;
            left.grow(b.min.into(), b.max.into());
            let cost = left.surface_area() * blocks(k, block_shift)
                + right[k].surface_area() * blocks(n - k, block_shift);
            if cost < best.0 {
                best = (cost, axis, k);
            }
        }
    }
    Split::Ordered {
        axis: best.1,
        mid: best.2,
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

    #[test]
    fn order_key_orders_by_centroid_then_index() {
        let mut rng = Rng::new(8);
        let prim = |rng: &mut Rng| {
            // Centroids at every scale, both zeros and ±1 among them, few indices so that
            // ties happen.
            let centroid = rng.coords() * [1e-4, 1.0, 1e3][rng.below(3)];
            BuildPrim {
                bounds: Aabb::new(centroid, centroid),
                centroid,
                index: rng.below(4) as u32,
            }
        };
        for _ in 0..20_000 {
            let (a, b) = (prim(&mut rng), prim(&mut rng));
            for axis in 0..3 {
                let by_tuple =
                    (a.centroid[axis], a.index).partial_cmp(&(b.centroid[axis], b.index));
                let by_key = a.order_key(axis).cmp(&b.order_key(axis));
                assert_eq!(Some(by_key), by_tuple, "{a:?} {b:?} axis {axis}");
            }
        }
    }

    #[test]
    fn binary_tree_is_well_formed_down_to_single_primitives() {
        // Counting primitives one by one and in blocks of four.
        for block in [1, 4] {
            check_binary_tree(block);
        }
    }

    fn check_binary_tree(block: usize) {
        let mut rng = Rng::new(5);
        // Random boxes of every size, some flat, with repeated centroids among them.
        let bounds: Vec<Aabb> = (0..3000)
            .map(|i| {
                let c = if i % 7 == 0 {
                    Vec3::ZERO
                } else {
                    rng.vec() * 10.0
                };
                let mut h = rng.vec().abs() * 0.1;
                if i % 5 == 0 {
                    h.z = 0.0;
                }
                Aabb::new(c - h, c + h)
            })
            .collect();
        let tree = build(&bounds, block);
        let nodes = &tree.nodes;
        // `order` is a permutation of the primitives.
        let mut seen = tree.order.clone();
        seen.sort_unstable();
        assert!(seen.iter().copied().eq(0..bounds.len() as u32));
        let contains = |outer: &Node, inner: Aabb| {
            outer.min.cmple(inner.min).all() && outer.max.cmpge(inner.max).all()
        };
        // Each subtree owns a contiguous range of `order`, in depth-first order.
        let mut next = 0;
        for (i, n) in nodes.iter().enumerate() {
            if n.count > 0 {
                assert_eq!((n.count, n.index), (1, next), "node {i}");
                assert!(contains(n, bounds[tree.order[next as usize] as usize]));
                next += 1;
            } else {
                let right = n.index as usize;
                assert!(right > i + 1 && right < nodes.len());
                for c in [i + 1, right] {
                    assert!(contains(n, Aabb::new(nodes[c].min, nodes[c].max)));
                }
            }
        }
        assert_eq!(next as usize, bounds.len());
        assert_eq!(nodes.len(), 2 * bounds.len() - 1);
        assert_eq!(std::mem::size_of::<Node>(), 32);
    }
}
