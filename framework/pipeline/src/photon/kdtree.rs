//! An immutable, balanced 3-d tree over points: the photon map's index (docs/architecture.md,
//! "Decisions").
//!
//! The tree is built once. Its points are stored in one `Vec`, permuted so that every subtree
//! is a contiguous range: the range `lo..hi` of more than [`LEAF_SIZE`] points is split at its
//! middle, `mid = lo + (hi − lo) / 2`, along the axis on which its points spread the most (the
//! median: ordered by coordinate, then by index, the points of `lo..mid` lie at or below the
//! one at `mid`, those of `mid..hi` at or above it). The nodes' splits are a second `Vec` in
//! breadth-first order (node `i`'s children are `2i` and `2i + 1`), a few per cent of the
//! points' size, so that the top of the tree stays in the cache. Children are found by
//! arithmetic: no node is allocated, and the depth is `log₂(n / LEAF_SIZE)` however the points
//! lie (on a plane, a line, or all at one position).
//!
//! Building and querying use explicit work lists, not recursion. A query's answer is fixed by
//! the points alone: candidates are ranked by squared distance, then by index, so the tree's
//! shape and the order of the search never show in it.

use glam::Vec3;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// The most points a range holds without being split: a query tests them one after another.
pub const LEAF_SIZE: usize = 16;

/// A point of the tree: where it is, and its index in the slice the tree was built from.
#[derive(Clone, Copy, Debug)]
struct Entry {
    position: Vec3,
    index: u32,
}

/// A point a query found: its index in the slice the tree was built from, and its squared
/// distance to the query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Neighbour {
    /// The point's index in the slice given to [`KdTree::new`].
    pub index: u32,
    /// Its squared distance to the query point, `(dx² + dy²) + dz²` in `f32`.
    pub distance_squared: f32,
}

impl Neighbour {
    /// The ranking of found points: nearer first, then the lower index.
    fn rank(&self, other: &Self) -> Ordering {
        self.distance_squared
            .total_cmp(&other.distance_squared)
            .then(self.index.cmp(&other.index))
    }
}

/// A [`Neighbour`] in a heap whose top is the worst of those kept.
struct Ranked(Neighbour);

impl PartialEq for Ranked {
    fn eq(&self, other: &Self) -> bool {
        self.0.rank(&other.0) == Ordering::Equal
    }
}
impl Eq for Ranked {}
impl PartialOrd for Ranked {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Ranked {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0.rank(&other.0)
    }
}

/// The breadth-first number of the root; node `i`'s children are `2i` and `2i + 1`.
const ROOT: usize = 1;

/// Where a node splits its range: the points before its middle lie at or below `value` on
/// `axis` (0, 1 or 2), the others at or above it.
#[derive(Clone, Copy, Debug)]
struct Split {
    value: f32,
    axis: u8,
}

/// A range of the tree still to be searched (node `node`), with the distance of the query
/// point to the region the range lies in, per axis (zero along the axes where the point is
/// inside it).
#[derive(Clone, Copy)]
struct Pending {
    lo: usize,
    hi: usize,
    node: usize,
    offset: Vec3,
}

/// An immutable, balanced 3-d tree over points, with the query of the photon map's radiance
/// estimate (the `k` nearest within a radius) and a radius query.
#[derive(Clone, Debug)]
pub struct KdTree {
    /// The points, permuted so that every subtree is a contiguous range.
    entries: Vec<Entry>,
    /// The splits of the nodes, by breadth-first number ([`ROOT`] first); unused at the
    /// numbers of leaves.
    splits: Vec<Split>,
}

impl KdTree {
    /// The tree of `points`. Positions are expected to be finite (the photon map drops the
    /// others): a point with a NaN coordinate is never found, one with an infinite coordinate
    /// only within an infinite limit, and neither hides the others.
    ///
    /// # Panics
    ///
    /// With more than `u32::MAX + 1` points (48 GiB of positions), whose indices a `u32` cannot
    /// hold.
    pub fn new(points: &[Vec3]) -> Self {
        let mut entries: Vec<Entry> = points
            .iter()
            .enumerate()
            .map(|(i, &position)| Entry {
                position,
                index: u32::try_from(i).expect("at most 2^32 points"),
            })
            .collect();
        let mut splits = Vec::new();
        let mut ranges = vec![(0, entries.len(), ROOT)];
        while let Some((lo, hi, node)) = ranges.pop() {
            if hi - lo <= LEAF_SIZE {
                continue;
            }
            let range = &mut entries[lo..hi];
            let axis = widest_axis(range);
            let half = range.len() / 2;
            range.select_nth_unstable_by(half, |a, b| {
                a.position[axis]
                    .total_cmp(&b.position[axis])
                    .then(a.index.cmp(&b.index))
            });
            if splits.len() <= node {
                splits.resize(
                    node + 1,
                    Split {
                        value: 0.0,
                        axis: 0,
                    },
                );
            }
            splits[node] = Split {
                value: range[half].position[axis],
                axis: axis as u8,
            };
            let mid = lo + half;
            ranges.push((lo, mid, 2 * node));
            ranges.push((mid, hi, 2 * node + 1));
        }
        Self { entries, splits }
    }

    /// The at most `k` points nearest to `point` whose squared distance to it is at most
    /// `max_distance_squared` (∞ for no limit), nearest first, equal distances in the order of
    /// index: exactly the first `k` of all points within the radius sorted by (squared
    /// distance, index). Nothing for a non-finite `point` or a negative or NaN limit.
    pub fn nearest_within(
        &self,
        point: Vec3,
        k: usize,
        max_distance_squared: f32,
    ) -> Vec<Neighbour> {
        let k = k.min(self.entries.len());
        if k == 0 || !point.is_finite() || !is_distance_limit(max_distance_squared) {
            return Vec::new();
        }
        let mut best: BinaryHeap<Ranked> = BinaryHeap::with_capacity(k);
        self.search(
            point,
            |best_so_far: &mut BinaryHeap<Ranked>| match best_so_far.peek() {
                Some(worst) if best_so_far.len() == k => worst.0.distance_squared,
                _ => max_distance_squared,
            },
            &mut best,
            |best, found| {
                if found.distance_squared > max_distance_squared || found.distance_squared.is_nan()
                {
                    return;
                }
                if best.len() < k {
                    best.push(Ranked(found));
                } else if let Some(mut worst) = best.peek_mut() {
                    if found.rank(&worst.0) == Ordering::Less {
                        *worst = Ranked(found);
                    }
                }
            },
        );
        best.into_sorted_vec().into_iter().map(|r| r.0).collect()
    }

    /// The indices of every point whose squared distance to `point` is at most
    /// `max_distance_squared`, in increasing order. Nothing for a non-finite `point` or a
    /// negative or NaN limit.
    pub fn within(&self, point: Vec3, max_distance_squared: f32) -> Vec<u32> {
        if self.entries.is_empty() || !point.is_finite() || !is_distance_limit(max_distance_squared)
        {
            return Vec::new();
        }
        let mut found: Vec<u32> = Vec::new();
        self.search(
            point,
            |_: &mut Vec<u32>| max_distance_squared,
            &mut found,
            |found, neighbour| {
                if neighbour.distance_squared <= max_distance_squared {
                    found.push(neighbour.index);
                }
            },
        );
        found.sort_unstable();
        found
    }

    /// Visits, nearest region first, every point of every range whose region may hold a point
    /// within `bound(state)` of `point` (squared), handing each to `visit`. The bound is taken
    /// again before each range, so that it may shrink as points are found; a range is skipped
    /// only when its region lies strictly farther than the bound, so that a point at exactly
    /// the bound is always visited.
    fn search<S>(
        &self,
        point: Vec3,
        bound: impl Fn(&mut S) -> f32,
        state: &mut S,
        mut visit: impl FnMut(&mut S, Neighbour),
    ) {
        let mut pending = Vec::with_capacity(64);
        pending.push(Pending {
            lo: 0,
            hi: self.entries.len(),
            node: ROOT,
            offset: Vec3::ZERO,
        });
        while let Some(Pending {
            lo,
            hi,
            node,
            offset,
        }) = pending.pop()
        {
            if squared_length(offset) > bound(state) {
                continue;
            }
            if hi - lo <= LEAF_SIZE {
                for entry in &self.entries[lo..hi] {
                    let distance_squared = squared_length(entry.position - point);
                    visit(
                        state,
                        Neighbour {
                            index: entry.index,
                            distance_squared,
                        },
                    );
                }
                continue;
            }
            let mid = lo + (hi - lo) / 2;
            let split = self.splits[node];
            let axis = usize::from(split.axis);
            let gap = point[axis] - split.value;
            let (near, far) = if gap < 0.0 {
                ((lo, mid, 2 * node), (mid, hi, 2 * node + 1))
            } else {
                ((mid, hi, 2 * node + 1), (lo, mid, 2 * node))
            };
            // The far side lies beyond the split plane: at least |gap| away along the axis,
            // which in floating point too is at most the point's own distance along it.
            let mut far_offset = offset;
            far_offset[axis] = gap.abs();
            // Skipped only when surely too far, as at the top of the loop: a NaN (a split
            // between points with NaN coordinates) searches the far side.
            let far_distance = squared_length(far_offset);
            if far_distance.is_nan() || far_distance <= bound(state) {
                pending.push(Pending {
                    lo: far.0,
                    hi: far.1,
                    node: far.2,
                    offset: far_offset,
                });
            }
            pending.push(Pending {
                lo: near.0,
                hi: near.1,
                node: near.2,
                offset,
            });
        }
    }
}

/// Whether `limit` is a squared distance a query may be limited to: zero, positive or ∞.
fn is_distance_limit(limit: f32) -> bool {
    limit >= 0.0
}

/// `(x² + y²) + z²`: the squared distance of the query, in one order of operations, so that a
/// lower bound made of smaller components is never larger than a distance.
fn squared_length(v: Vec3) -> f32 {
    (v.x * v.x + v.y * v.y) + v.z * v.z
}

/// The axis along which the points of `range` spread the most (the first of equal spreads).
fn widest_axis(range: &[Entry]) -> usize {
    let mut min = Vec3::INFINITY;
    let mut max = Vec3::NEG_INFINITY;
    for entry in range {
        min = min.min(entry.position);
        max = max.max(entry.position);
    }
    let extent = max - min;
    let mut axis = 0;
    for a in 1..3 {
        if extent[a] > extent[axis] {
            axis = a;
        }
    }
    axis
}

#[cfg(test)]
mod tests {
    use super::*;
    use raylab_core::sampling::Rng;

    /// The answer by definition: every point within the limit, sorted by (squared distance,
    /// index), the first `k`.
    fn brute_nearest(points: &[Vec3], q: Vec3, k: usize, r2: f32) -> Vec<Neighbour> {
        let mut all: Vec<Neighbour> = points
            .iter()
            .enumerate()
            .map(|(i, p)| Neighbour {
                index: i as u32,
                distance_squared: squared_length(*p - q),
            })
            .filter(|n| n.distance_squared <= r2)
            .collect();
        all.sort_by(Neighbour::rank);
        all.truncate(k);
        all
    }

    fn brute_within(points: &[Vec3], q: Vec3, r2: f32) -> Vec<u32> {
        (0..points.len() as u32)
            .filter(|&i| squared_length(points[i as usize] - q) <= r2)
            .collect()
    }

    fn unit(rng: &mut Rng) -> Vec3 {
        Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32())
    }

    /// Clouds of `n` points in about the unit cube, by name: the awkward ones are degenerate
    /// (a plane, a line, one position), duplicated or on a lattice (many equal distances).
    fn cloud(shape: &str, n: usize, rng: &mut Rng) -> Vec<Vec3> {
        (0..n)
            .map(|i| match shape {
                "uniform" => unit(rng),
                "clustered" => {
                    let centre = Vec3::splat((rng.next_below(4) as f32) * 0.25);
                    centre + unit(rng) * 0.01
                }
                "coplanar" => Vec3::new(rng.next_f32(), 0.5, rng.next_f32()),
                "collinear" => Vec3::new(0.25, rng.next_f32(), 0.75),
                "one position" => Vec3::splat(0.5),
                "duplicated" => {
                    let mut pick = Rng::new(7, (i % 13) as u64);
                    unit(&mut pick)
                }
                "lattice" => Vec3::new(
                    rng.next_below(5) as f32 * 0.25,
                    rng.next_below(5) as f32 * 0.25,
                    rng.next_below(5) as f32 * 0.25,
                ),
                _ => unreachable!("no cloud named {shape}"),
            })
            .collect()
    }

    const SHAPES: [&str; 7] = [
        "uniform",
        "clustered",
        "coplanar",
        "collinear",
        "one position",
        "duplicated",
        "lattice",
    ];

    #[test]
    fn nearest_and_within_equal_a_linear_search_on_every_kind_of_cloud() {
        let mut rng = Rng::new(11, 0);
        let mut checked = 0;
        for shape in SHAPES {
            for n in [0, 1, 2, LEAF_SIZE, LEAF_SIZE + 1, 100, 1500] {
                for (scale, offset) in
                    [(1e-4, 0.0), (1.0, 0.0), (1e3, 0.0), (1.0, 1e3), (1e-4, 1e3)]
                {
                    let points: Vec<Vec3> = cloud(shape, n, &mut rng)
                        .into_iter()
                        .map(|p| p * scale + Vec3::splat(offset))
                        .collect();
                    let tree = KdTree::new(&points);
                    for query in 0..12 {
                        let q = match query % 3 {
                            // On a point: distances of exactly zero.
                            0 if n > 0 => points[rng.next_below(n as u32) as usize],
                            // Inside the cloud, and well outside it.
                            1 => unit(&mut rng) * scale + Vec3::splat(offset),
                            _ => (unit(&mut rng) * 3.0 - 1.0) * scale + Vec3::splat(offset),
                        };
                        let radius = [0.0, 1e-3, 0.1, 0.3, 1.0, f32::INFINITY][query % 6];
                        let r2 = (radius * scale) * (radius * scale);
                        for k in [0, 1, 5, 50, n.saturating_sub(1), n, n + 3] {
                            assert_eq!(
                                tree.nearest_within(q, k, r2),
                                brute_nearest(&points, q, k, r2),
                                "{shape}, {n} points ×{scale} +{offset}, query {q}, k {k}, r² {r2}"
                            );
                            checked += 1;
                        }
                        assert_eq!(
                            tree.within(q, r2),
                            brute_within(&points, q, r2),
                            "{shape}, {n} points ×{scale} +{offset}, query {q}, r² {r2}"
                        );
                    }
                }
            }
        }
        assert!(checked > 10_000, "{checked} queries");
    }

    #[test]
    fn ties_are_answered_by_index_whatever_the_order_of_the_points() {
        // Eight points at the same distance from the origin, twice: the answer is the lowest
        // indices at the smaller distance, then the lowest indices at the next.
        let corners: Vec<Vec3> = (0..16)
            .map(|i| {
                let s = if i < 8 { 1.0 } else { 2.0 };
                Vec3::new(
                    if i & 1 == 0 { s } else { -s },
                    if i & 2 == 0 { s } else { -s },
                    if i & 4 == 0 { s } else { -s },
                )
            })
            .collect();
        let reversed: Vec<Vec3> = corners.iter().rev().copied().collect();
        let found = KdTree::new(&corners).nearest_within(Vec3::ZERO, 10, f32::INFINITY);
        let indices: Vec<u32> = found.iter().map(|n| n.index).collect();
        assert_eq!(indices, [0, 1, 2, 3, 4, 5, 6, 7, 8, 9]);
        let found = KdTree::new(&reversed).nearest_within(Vec3::ZERO, 10, f32::INFINITY);
        let indices: Vec<u32> = found.iter().map(|n| n.index).collect();
        assert_eq!(indices, [8, 9, 10, 11, 12, 13, 14, 15, 0, 1]);
    }

    #[test]
    fn bad_queries_find_nothing_and_nothing_panics() {
        let tree = KdTree::new(&[Vec3::ZERO, Vec3::ONE]);
        assert!(tree.nearest_within(Vec3::NAN, 2, 1.0).is_empty());
        assert!(
            tree.nearest_within(Vec3::INFINITY, 2, f32::INFINITY)
                .is_empty()
        );
        assert!(tree.nearest_within(Vec3::ZERO, 2, -1.0).is_empty());
        assert!(tree.nearest_within(Vec3::ZERO, 2, f32::NAN).is_empty());
        assert!(tree.within(Vec3::ZERO, f32::NAN).is_empty());
        assert_eq!(tree.nearest_within(Vec3::ZERO, usize::MAX, 0.0).len(), 1);
        assert!(
            KdTree::new(&[])
                .nearest_within(Vec3::ZERO, 5, 1.0)
                .is_empty()
        );
        assert!(
            KdTree::new(&[])
                .within(Vec3::ZERO, f32::INFINITY)
                .is_empty()
        );
        // A point with a NaN coordinate is never found, and the others still are, even where
        // most points' coordinates along an axis are NaN or infinite.
        let tree = KdTree::new(&[Vec3::NAN, Vec3::ZERO, Vec3::new(f32::NAN, 0.0, 0.0)]);
        let found = tree.nearest_within(Vec3::ZERO, 3, f32::INFINITY);
        assert_eq!(found.iter().map(|n| n.index).collect::<Vec<_>>(), [1]);
        let mut rng = Rng::new(5, 0);
        let points: Vec<Vec3> = (0..2000)
            .map(|i| match i % 5 {
                0 => unit(&mut rng),
                1 => Vec3::new(f32::NAN, rng.next_f32(), rng.next_f32()),
                2 => Vec3::new(-f32::NAN, rng.next_f32(), rng.next_f32()),
                3 => Vec3::new(rng.next_f32(), f32::INFINITY, f32::NAN),
                _ => Vec3::new(f32::NEG_INFINITY, rng.next_f32(), rng.next_f32()),
            })
            .collect();
        let tree = KdTree::new(&points);
        for _ in 0..200 {
            let q = unit(&mut rng);
            for (k, r2) in [(10, 0.01), (2000, f32::INFINITY)] {
                let found = tree.nearest_within(q, k, r2);
                assert_eq!(found, brute_nearest(&points, q, k, r2), "query {q}");
                // An infinite coordinate is at an infinite distance, within an infinite limit.
                let findable = |i: u32| match i % 5 {
                    0 => true,
                    4 => r2.is_infinite(),
                    _ => false,
                };
                assert!(found.iter().all(|n| findable(n.index)), "query {q}");
            }
        }
    }

    #[test]
    fn a_million_photons_at_one_position_build_and_answer_without_deep_recursion() {
        let points = vec![Vec3::new(1e3, -2.0, 0.5); 1 << 20];
        let tree = KdTree::new(&points);
        let found = tree.nearest_within(points[0], 50, 0.0);
        let indices: Vec<u32> = found.iter().map(|n| n.index).collect();
        assert_eq!(indices, (0..50).collect::<Vec<u32>>());
        assert_eq!(tree.within(points[0], 1.0).len(), 1 << 20);
    }
}
