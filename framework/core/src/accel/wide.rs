//! The 8-wide form of the BVH that queries traverse: each node holds the boxes of up to eight
//! children side by side (one array of eight per coordinate), so one slab test in SIMD
//! registers decides all eight (see `slabs.rs`); and the SAH-optimal collapse of the builder's
//! binary tree into that form, which also decides the leaves.

use glam::Vec3;

use super::sah::Node;
use crate::math::Aabb;

/// Children per wide node.
pub(crate) const WIDTH: usize = 8;
/// Marks a child reference as a leaf: `LEAF | (count − 1) << COUNT_SHIFT | first`, owning
/// `indices[first..first + count]`. Without it, a reference is the index of a wide node.
pub(crate) const LEAF: u32 = 1 << 31;
/// Position of a leaf's primitive count (minus one, 3 bits: leaves hold at most 8).
const COUNT_SHIFT: u32 = 28;
/// Largest leaf the collapse makes: the primitive counts that fit a leaf reference.
pub(crate) const MAX_LEAF: usize = 8;
/// Largest number of primitives whose indices fit a leaf reference.
pub(crate) const MAX_PRIMITIVES: usize = 1 << COUNT_SHIFT;
/// A slot of the leaf order that belongs to no leaf: padding before a leaf whose first slot is
/// aligned (see [`collapse`]).
pub(crate) const HOLE: u32 = u32::MAX;
/// SAH cost of visiting a wide node (testing its eight boxes at once): the unit of
/// [`leaf_cost`].
const NODE_COST: f32 = 1.0;
/// SAH cost of each primitive of a leaf beyond its blocks' (accepting hits lane by lane), in
/// node visits.
const PRIMITIVE_COST: f32 = 0.1;

/// SAH cost of intersecting a leaf of `n` primitives that are tested `block` at a time, in
/// node visits: one per block, and [`PRIMITIVE_COST`] per primitive. Of the models measured
/// on the Cornell box, the bunny and the eight bunnies (docs/performance.md), blocks alone made
/// leaves too big for the Cornell box's large walls, and a larger cost per primitive made
/// leaves too small for the bunny.
fn leaf_cost(n: usize, block: usize) -> f32 {
    n.div_ceil(block) as f32 + PRIMITIVE_COST * n as f32
}

/// A node of the 8-wide hierarchy: 224 bytes, aligned for 8-lane loads.
///
/// Lane `i` holds child `i`: its box (`planes[axis][i]` the minimum along `axis`,
/// `planes[3 + axis][i]` the maximum) and its reference `children[i]`. Unused lanes have the
/// empty box (`+∞` minima, `−∞` maxima), which no ray enters.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub(crate) struct WideNode {
    /// The children's box planes: minima along x, y, z, then maxima along x, y, z.
    pub planes: [[f32; WIDTH]; 6],
    pub children: [u32; WIDTH],
}

impl WideNode {
    pub(crate) const EMPTY: WideNode = WideNode {
        planes: [
            [f32::INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
        ],
        children: [0; WIDTH],
    };

    pub(crate) fn set_lane(&mut self, lane: usize, min: Vec3, max: Vec3, child: u32) {
        for axis in 0..3 {
            self.planes[axis][lane] = min[axis];
            self.planes[3 + axis][lane] = max[axis];
        }
        self.children[lane] = child;
    }

    /// The box of lane `lane`: (minimum, maximum).
    #[cfg(test)]
    pub(crate) fn lane_box(&self, lane: usize) -> (Vec3, Vec3) {
        let plane = |k: usize| Vec3::from_array([0, 1, 2].map(|axis| self.planes[k + axis][lane]));
        (plane(0), plane(3))
    }
}

/// The primitive range `(first, count)` of a leaf reference.
#[inline(always)]
pub(crate) fn leaf_range(child: u32) -> (usize, usize) {
    let first = (child & (MAX_PRIMITIVES as u32 - 1)) as usize;
    let count = ((child & !LEAF) >> COUNT_SHIFT) as usize + 1;
    (first, count)
}

/// The surface area of a binary node's box, 0 for an empty or a NaN one (the SAH's weight).
fn area(node: &Node) -> f32 {
    let a = Aabb::new(node.min, node.max).surface_area();
    if a.is_nan() { 0.0 } else { a }
}

/// The collapse's choices for one binary node.
#[derive(Clone, Copy)]
struct Plan {
    /// `cost[i - 1]`: the least SAH cost of the subtree as at most `i` lanes of its parent.
    cost: [f32; WIDTH],
    /// `split[i - 1]`: how those lanes divide between the left and the right child, `(k, j)`;
    /// `(0, 0)` for the subtree as one lane.
    split: [(u8, u8); WIDTH],
    /// As one lane: a leaf (all the subtree's primitives) rather than a wide node.
    leaf: bool,
    /// As a wide node: the lanes the left child takes of the eight (the right one the rest).
    node_split: u8,
    /// Primitives in the subtree, and the first one's position in build order.
    count: u32,
    first: u32,
}

/// Collapses a binary hierarchy (depth first, as the builder lays it out, with leaves indexing
/// `order`) into 8-wide nodes, depth first with the root at `result[0]`, and lays out the
/// leaves' primitive indices, each leaf starting at a multiple of `block` slots ([`HOLE`]s
/// between).
///
/// The collapse minimises the SAH cost of the wide tree over all ways of choosing which binary
/// subtrees become the lanes of a wide node and which become leaves (Ylitie, Karras and Laine
/// 2017, "Efficient Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", §4.1):
/// a subtree of at most eight primitives may become one leaf.
pub(crate) fn collapse(binary: &[Node], order: &[u32], block: usize) -> WideTree {
    let mut plans = vec![
        Plan {
            cost: [0.0; WIDTH],
            split: [(0, 0); WIDTH],
            leaf: true,
            node_split: 0,
            count: 0,
            first: 0
        };
        binary.len()
    ];
    // Children follow their parent, so a reverse sweep sees them first.
    for b in (0..binary.len()).rev() {
        let node = &binary[b];
        let area = area(node);
        if node.count > 0 {
            let cost = area * leaf_cost(node.count as usize, block);
            plans[b] = Plan {
                cost: [cost; WIDTH],
                split: [(0, 0); WIDTH],
                leaf: true,
                node_split: 0,
                count: node.count,
                first: node.index,
            };
            continue;
        }
        let (l, r) = (&plans[b + 1], &plans[node.index as usize]);
        // distribute[j - 1]: the best division of at most `j` lanes between the children.
        let mut distribute = [(f32::INFINITY, (0u8, 0u8)); WIDTH];
        for j in 2..=WIDTH {
            let mut best = (l.cost[0] + r.cost[j - 2], (1u8, (j - 1) as u8));
            for k in 2..j {
                let c = l.cost[k - 1] + r.cost[j - k - 1];
                if c < best.0 {
                    best = (c, (k as u8, (j - k) as u8));
                }
            }
            distribute[j - 1] = best;
        }
        let count = l.count + r.count;
        let as_node = area * NODE_COST + distribute[WIDTH - 1].0;
        let as_leaf = if count as usize <= MAX_LEAF {
            area * leaf_cost(count as usize, block)
        } else {
            f32::INFINITY
        };
        let leaf = as_leaf <= as_node;
        let one = if leaf { as_leaf } else { as_node };
        let mut plan = Plan {
            cost: [one; WIDTH],
            split: [(0, 0); WIDTH],
            leaf,
            node_split: distribute[WIDTH - 1].1.0,
            count,
            first: l.first,
        };
        for i in 2..=WIDTH {
            if distribute[i - 1].0 < one {
                plan.cost[i - 1] = distribute[i - 1].0;
                plan.split[i - 1] = distribute[i - 1].1;
            }
        }
        plans[b] = plan;
    }
    let mut wide = Vec::with_capacity(binary.len() / 8 + 1);
    let mut leaves = Vec::new();
    let mut depth = 0;
    if binary.is_empty() {
        return WideTree {
            nodes: wide,
            indices: Vec::new(),
            depth,
        };
    }
    if plans[0].leaf {
        // A single leaf: one wide node with one lane.
        let root = &binary[0];
        wide.push(WideNode::EMPTY);
        wide[0].set_lane(0, root.min, root.max, 0);
        leaves.push((plans[0].first, plans[0].count, 0u32, 0u8));
        depth = 1;
    } else {
        let mut emit = Emit {
            binary,
            plans: &plans,
            wide: &mut wide,
            leaves: &mut leaves,
            depth: &mut depth,
        };
        emit.node(0, 1);
    }
    // Leaves in build order (the order the depth-first emission met them), each at an aligned
    // slot.
    debug_assert!(leaves.is_sorted_by_key(|&(first, ..)| first));
    let mut indices = Vec::with_capacity(order.len() + order.len() / 2);
    for (first, count, node, lane) in leaves {
        indices.resize(indices.len().next_multiple_of(block), HOLE);
        let slot = indices.len() as u32;
        indices.extend_from_slice(&order[first as usize..(first + count) as usize]);
        debug_assert!((1..=MAX_LEAF as u32).contains(&count) && (slot as usize) < MAX_PRIMITIVES);
        wide[node as usize].children[lane as usize] = LEAF | (count - 1) << COUNT_SHIFT | slot;
    }
    WideTree {
        nodes: wide,
        indices,
        depth,
    }
}

/// The result of [`collapse`].
pub(crate) struct WideTree {
    /// The wide nodes, depth first; the root is `nodes[0]`.
    pub nodes: Vec<WideNode>,
    /// Primitive indices in leaf order ([`HOLE`]s between aligned leaves).
    pub indices: Vec<u32>,
    /// Levels of wide nodes: 1 for the root alone.
    pub depth: usize,
}

/// The binary subtrees that make the lanes of `b` as at most `i` lanes, in tree order.
fn lanes(binary: &[Node], plans: &[Plan], b: usize, i: usize, out: &mut Vec<usize>) {
    match plans[b].split[i - 1] {
        (0, 0) => out.push(b),
        (k, j) => {
            lanes(binary, plans, b + 1, k as usize, out);
            lanes(binary, plans, binary[b].index as usize, j as usize, out);
        }
    }
}

/// What [`collapse`] writes while it lays out the wide nodes.
struct Emit<'a> {
    binary: &'a [Node],
    plans: &'a [Plan],
    wide: &'a mut Vec<WideNode>,
    /// Leaf lanes as (first primitive in build order, count, wide node, lane), for the layout.
    leaves: &'a mut Vec<(u32, u32, u32, u8)>,
    depth: &'a mut usize,
}

impl Emit<'_> {
    /// Appends the wide node for binary node `b` (and its subtree) at `depth`; returns its
    /// index.
    fn node(&mut self, b: usize, depth: usize) -> u32 {
        *self.depth = (*self.depth).max(depth);
        let (binary, plans) = (self.binary, self.plans);
        let (l, r) = (b + 1, binary[b].index as usize);
        let k = plans[b].node_split as usize;
        let mut children = Vec::with_capacity(WIDTH);
        lanes(binary, plans, l, k, &mut children);
        lanes(binary, plans, r, WIDTH - k, &mut children);
        let index = self.wide.len();
        self.wide.push(WideNode::EMPTY);
        for (lane, &c) in children.iter().enumerate() {
            let child = if plans[c].leaf {
                // Patched by the layout.
                self.leaves
                    .push((plans[c].first, plans[c].count, index as u32, lane as u8));
                0
            } else {
                self.node(c, depth + 1)
            };
            let node = &binary[c];
            self.wide[index].set_lane(lane, node.min, node.max, child);
        }
        index as u32
    }
}
