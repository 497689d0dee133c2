//! Acceleration structures: a bounding volume hierarchy built with the surface area heuristic,
//! and one over triangles that keeps their vertices in leaf order.

mod bvh;
mod sah;
mod slabs;
mod stats;
mod triangles;
mod wide;

pub use bvh::Bvh;
pub use stats::TraversalStats;
pub use triangles::{MeshHit, TriangleBvh};
