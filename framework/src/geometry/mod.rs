//! The framework's own ray–primitive kernels, used by the BVH traversal for every lab after
//! lab02 (where students write their own, see `labs::lab02`).

mod plane;
mod sphere;
mod triangle;

pub use plane::intersect_plane;
pub use sphere::intersect_sphere;
pub(crate) use triangle::TriangleBlock;
pub use triangle::{TriangleRay, intersect_triangle};

mod builtin;

pub use builtin::BuiltinIntersection;
