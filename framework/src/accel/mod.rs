//! Acceleration structures: a bounding volume hierarchy built with the surface area heuristic.

mod bvh;
mod stats;

pub use bvh::Bvh;
pub use stats::TraversalStats;
