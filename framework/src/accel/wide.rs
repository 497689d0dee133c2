//! The 8-wide form of the BVH that queries traverse: each node holds the boxes of up to eight
//! children side by side (one array of eight per coordinate), so one slab test in SIMD
//! registers decides all eight (see `slabs.rs`).

use glam::Vec3;

use super::sah::Node;

/// Children per wide node.
pub(crate) const WIDTH: usize = 8;
/// Marks a child reference as a leaf: `LEAF | (count − 1) << COUNT_SHIFT | first`, owning
/// `indices[first..first + count]`. Without it, a reference is the index of a wide node.
pub(crate) const LEAF: u32 = 1 << 31;
/// Position of a leaf's primitive count (minus one, 3 bits: leaves hold at most 8).
const COUNT_SHIFT: u32 = 28;
/// Largest number of primitives whose indices fit a leaf reference.
pub(crate) const MAX_PRIMITIVES: usize = 1 << COUNT_SHIFT;

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

fn leaf_ref(node: &Node) -> u32 {
    debug_assert!((1..=8).contains(&node.count) && (node.index as usize) < MAX_PRIMITIVES);
    LEAF | (node.count - 1) << COUNT_SHIFT | node.index
}

/// Collapses a binary hierarchy (depth first, as the builder lays it out) into 8-wide nodes,
/// depth first; the root is `result[0]`. Each wide node takes its binary node's two children,
/// then repeatedly replaces the interior child of largest surface area by its two children
/// until it has eight (the usual SAH-guided collapse).
pub(crate) fn collapse(binary: &[Node]) -> Vec<WideNode> {
    let mut wide = Vec::with_capacity(binary.len() / 2 + 1);
    match binary.first() {
        None => {}
        Some(root) if root.count > 0 => {
            // A single leaf: one wide node with one lane.
            let mut node = WideNode::EMPTY;
            node.set_lane(0, root.min, root.max, leaf_ref(root));
            wide.push(node);
        }
        Some(_) => {
            collapse_node(binary, 0, &mut wide);
        }
    }
    wide
}

/// Appends the wide node for interior binary node `b` (and its subtree); returns its index.
fn collapse_node(binary: &[Node], b: usize, wide: &mut Vec<WideNode>) -> u32 {
    let children = |i: usize| [i + 1, binary[i].index as usize];
    let area = |i: usize| {
        let d = (binary[i].max - binary[i].min).max(Vec3::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    };
    let mut lanes: Vec<usize> = children(b).to_vec();
    while lanes.len() < WIDTH {
        let widest = lanes
            .iter()
            .enumerate()
            .filter(|&(_, &c)| binary[c].count == 0)
            .max_by(|a, b| area(*a.1).total_cmp(&area(*b.1)))
            .map(|(lane, _)| lane);
        let Some(lane) = widest else { break };
        let opened = lanes[lane];
        let [left, right] = children(opened);
        // Keep the lanes in the binary tree's order (left subtree first).
        lanes.splice(lane..=lane, [left, right]);
    }
    let index = wide.len();
    wide.push(WideNode::EMPTY);
    for (lane, &c) in lanes.iter().enumerate() {
        let node = &binary[c];
        let child = if node.count > 0 {
            leaf_ref(node)
        } else {
            collapse_node(binary, c, wide)
        };
        wide[index].set_lane(lane, node.min, node.max, child);
    }
    index as u32
}
