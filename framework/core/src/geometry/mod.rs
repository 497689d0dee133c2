//! The framework's own ray–primitive kernels, used by the BVH traversal for every lab after
//! lab02 (where students write their own, see `contracts::lab02`).
//!
//! They answer Exercises 2.1–2.3. A student's crate cannot hand the question back to them: it
//! depends on the contracts alone, and `raylab-core` is not among its dependencies (docs/
//! architecture.md, "Invariants"). The pipeline packages them as a lab02 `Intersection` for the
//! parts of lab02's checks that are not the student's.

mod plane;
mod sphere;
mod triangle;

pub use plane::intersect_plane;
pub use sphere::intersect_sphere;
pub(crate) use triangle::TriangleBlock;
pub use triangle::TriangleRay;
pub use triangle::intersect_triangle;
