//! Input generators shared by the labs' property checks and golden-case generators.

use glam::{UVec2, Vec2, Vec3};
use proptest::prelude::*;

/// A point with coordinates in `[-range, range]`.
pub fn point(range: f32) -> impl Strategy<Value = Vec3> + Clone {
    (-range..range, -range..range, -range..range).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// A unit vector (normalized point of the unit cube, away from the origin).
pub fn unit_vector() -> impl Strategy<Value = Vec3> + Clone {
    point(1.0)
        .prop_filter("not too short", |v| v.length() > 0.1)
        .prop_map(Vec3::normalize)
}

/// The scales, in scene units, at which checks run their configurations again: from a mesh's
/// triangles or a lamp of 10⁻⁴ units to a terrain of 10³. Lengths scale with the
/// configuration, so the answer is known; an absolute epsilon in the student's code shows up
/// at one end or the other.
pub const SCALES: [f32; 5] = [1e-4, 1e-2, 1.0, 1e2, 1e3];

/// One of [`SCALES`].
pub fn scale() -> impl Strategy<Value = f32> + Clone {
    prop::sample::select(SCALES.to_vec())
}

/// An image resolution between 1×1 and 4096×4096.
pub fn resolution() -> impl Strategy<Value = UVec2> + Clone {
    (1u32..4096, 1u32..4096).prop_map(|(w, h)| UVec2::new(w, h))
}

/// A raster position inside an image of the given resolution.
pub fn raster_in(res: UVec2) -> impl Strategy<Value = Vec2> + Clone {
    (0.0..res.x as f32, 0.0..res.y as f32).prop_map(|(x, y)| Vec2::new(x, y))
}

/// A random, not too thin triangle.
pub fn triangle_strategy() -> impl Strategy<Value = [Vec3; 3]> + Clone {
    (point(3.0), point(3.0), point(3.0))
        .prop_map(|(a, b, c)| [a, b, c])
        .prop_filter("not degenerate", |[a, b, c]| {
            let n = (*b - *a).cross(*c - *a).length();
            n > 0.5 && n > 0.05 * ((*b - *a).length_squared() + (*c - *a).length_squared())
        })
}

/// A random index of refraction: air, water, glass, diamond-like, or anything in `[1, 2.5]`.
pub fn index_strategy() -> impl Strategy<Value = f32> + Clone {
    prop_oneof![
        Just(1.0f32),
        Just(1.33f32),
        Just(1.5f32),
        Just(2.42f32),
        1.0f32..2.5,
    ]
}

/// A deterministic stream of inputs from a strategy, for golden-case generation.
pub fn samples<S: Strategy>(strategy: S, count: usize, seed: u8) -> Vec<S::Value> {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
    let mut runner = TestRunner::new_with_rng(
        Config::default(),
        TestRng::from_seed(RngAlgorithm::ChaCha, &[seed; 32]),
    );
    (0..count)
        .map(|_| {
            strategy
                .new_tree(&mut runner)
                .expect("strategies used for golden data do not reject everything")
                .current()
        })
        .collect()
}
