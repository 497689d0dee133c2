//! Counts of the work one BVH traversal does, for measuring where the time goes.

/// How much work a traversal did: nodes whose children's boxes were tested, and primitive tests.
///
/// Filled by [`Bvh::closest_hit_counted`](super::Bvh::closest_hit_counted) and
/// [`Bvh::any_hit_counted`](super::Bvh::any_hit_counted); the uncounted queries compile the
/// counting away.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraversalStats {
    /// Interior nodes visited (each one tests the boxes of its children).
    pub nodes: u64,
    /// Leaves reached.
    pub leaves: u64,
    /// Primitives in the leaves reached (each one tested, unless an any-hit query stopped
    /// in the leaf; a SIMD test of several primitives counts each of them).
    pub primitives: u64,
}

impl TraversalStats {
    /// Adds another traversal's counts to these.
    pub fn add(&mut self, other: &TraversalStats) {
        self.nodes += other.nodes;
        self.leaves += other.leaves;
        self.primitives += other.primitives;
    }
}

/// Where a traversal reports its work: [`TraversalStats`] counts, `()` ignores it (and
/// compiles to nothing).
pub(crate) trait Counter {
    /// An interior node was visited.
    fn node(&mut self);
    /// A leaf with `primitives` primitives was reached.
    fn leaf(&mut self, primitives: usize);
}

impl Counter for () {
    #[inline(always)]
    fn node(&mut self) {}
    #[inline(always)]
    fn leaf(&mut self, _: usize) {}
}

impl Counter for TraversalStats {
    #[inline(always)]
    fn node(&mut self) {
        self.nodes += 1;
    }
    #[inline(always)]
    fn leaf(&mut self, primitives: usize) {
        self.leaves += 1;
        self.primitives += primitives as u64;
    }
}
