//! The ray–box slab test of the traversal: a ray's entry distances into the eight child boxes
//! of a wide node at once. Two implementations compute the same IEEE single-precision
//! operations lane by lane, so they give bit-identical answers (and images do not depend on the
//! CPU): [`Avx`], one 8-lane register per coordinate, where the CPU has AVX; and [`Portable`],
//! two 4-lane halves (SSE on x86-64, NEON on ARM, scalar elsewhere).

use glam::{Vec3, Vec4};

use super::wide::{WIDTH, WideNode};
use crate::math::Ray;

/// `1 + 2γ₃` with `γ₃ = 3u/(1 − 3u)`, `u = ε/2`: scaling the exit distance of a slab test by
/// this makes it conservative under floating-point rounding (Ize 2013, "Robust BVH Ray
/// Traversal"; also PBRT), so rays through box edges and flat boxes are not lost.
pub(crate) const EXIT_SLACK: f32 = 1.0 + 2.0 * (1.5 * f32::EPSILON) / (1.0 - 1.5 * f32::EPSILON);

/// A ray prepared for slab tests: origin, reciprocal direction, and which planes of a box it
/// meets first along each axis.
pub(crate) struct Slabs {
    origin: Vec3,
    inv_dir: Vec3,
    /// `near[axis]`: the index in [`WideNode::planes`] of the plane met first along `axis`
    /// (the minimum for a positive direction, the maximum for a negative one).
    near: [usize; 3],
    /// `far[axis]`: the index of the other plane along `axis`.
    far: [usize; 3],
}

/// The lanes of a wide node the ray enters (bit `i` for lane `i`) and the entry distances.
pub(crate) type Entries = ([f32; WIDTH], u32);

impl Slabs {
    #[inline(always)]
    pub(crate) fn new(ray: &Ray) -> Self {
        let inv_dir = ray.direction.recip();
        let negative = inv_dir.to_array().map(|i| i.is_sign_negative() as usize);
        Self {
            origin: ray.origin,
            inv_dir,
            near: [0, 1, 2].map(|axis| axis + 3 * negative[axis]),
            far: [0, 1, 2].map(|axis| axis + 3 * (1 - negative[axis])),
        }
    }

    /// The node's (near, far) planes along `axis` for this ray: minima then maxima, or the
    /// other way round for a negative direction. Chosen by index, not by a branch per node:
    /// the direction's signs change from ray to ray.
    #[inline(always)]
    fn planes<'a>(&self, node: &'a WideNode, axis: usize) -> (&'a [f32; WIDTH], &'a [f32; WIDTH]) {
        (&node.planes[self.near[axis]], &node.planes[self.far[axis]])
    }
}

/// An implementation of the slab test: entry distances of the ray into the boxes of a wide
/// node, clipped to `[tmin, tmax]`, and the mask of the lanes whose clipped interval is not
/// empty (with the rounding slack [`EXIT_SLACK`]).
///
/// Robust to zero direction components: each slab's entry (exit) distance comes from the plane
/// met first (last) for the direction's sign (Williams et al. 2005), so `0·∞ = NaN` can only
/// appear when the origin lies on that plane of a slab the ray runs parallel to — exactly when
/// the slab puts no limit on `t` — and NaN is then ignored by the `max` (`min`) that accumulates
/// the entry (exit) distances.
pub(crate) trait SlabTest: Copy {
    /// The entries of `slabs`'s ray into `node`'s boxes.
    fn entries(self, slabs: &Slabs, node: &WideNode, tmin: f32, tmax: f32) -> Entries;
}

/// The slab test in two 4-lane halves, on every target.
#[derive(Clone, Copy)]
pub(crate) struct Portable;

impl SlabTest for Portable {
    #[inline(always)]
    fn entries(self, slabs: &Slabs, node: &WideNode, tmin: f32, tmax: f32) -> Entries {
        let mut entries = [0.0; WIDTH];
        let mut mask = 0;
        for half in 0..WIDTH / 4 {
            let lanes = 4 * half..4 * half + 4;
            let mut enter = Vec4::splat(tmin);
            let mut exit = Vec4::splat(tmax);
            for axis in 0..3 {
                let (near, far) = slabs.planes(node, axis);
                let (o, i) = (
                    Vec4::splat(slabs.origin[axis]),
                    Vec4::splat(slabs.inv_dir[axis]),
                );
                enter = max_ignoring_nan(enter, (Vec4::from_slice(&near[lanes.clone()]) - o) * i);
                exit = min_ignoring_nan(exit, (Vec4::from_slice(&far[lanes.clone()]) - o) * i);
            }
            enter.write_to_slice(&mut entries[lanes]);
            mask |= enter.cmple(exit * EXIT_SLACK).bitmask() << (4 * half);
        }
        (entries, mask)
    }
}

/// Lane-wise `max(acc, x)`, or `acc` where `x` is NaN: one `maxps` on x86-64.
#[inline(always)]
fn max_ignoring_nan(acc: Vec4, x: Vec4) -> Vec4 {
    #[cfg(target_arch = "x86_64")]
    {
        // `maxps x, acc` is `x > acc ? x : acc`, lane by lane (false for NaN). SSE is part of
        // every x86-64 target.
        use std::arch::x86_64::_mm_max_ps;
        #[allow(unused_unsafe)]
        unsafe { _mm_max_ps(x.into(), acc.into()) }.into()
    }
    #[cfg(not(target_arch = "x86_64"))]
    Vec4::select(x.cmpgt(acc), x, acc)
}

/// Lane-wise `min(acc, x)`, or `acc` where `x` is NaN: one `minps` on x86-64.
#[inline(always)]
fn min_ignoring_nan(acc: Vec4, x: Vec4) -> Vec4 {
    #[cfg(target_arch = "x86_64")]
    {
        // `minps x, acc` is `x < acc ? x : acc`, lane by lane (false for NaN).
        use std::arch::x86_64::_mm_min_ps;
        #[allow(unused_unsafe)]
        unsafe { _mm_min_ps(x.into(), acc.into()) }.into()
    }
    #[cfg(not(target_arch = "x86_64"))]
    Vec4::select(x.cmplt(acc), x, acc)
}

/// The slab test in one 8-lane AVX register per coordinate. A value exists only on a CPU that
/// has AVX ([`Avx::detect`]), which is what makes calling the AVX code sound.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy)]
pub(crate) struct Avx(());

#[cfg(target_arch = "x86_64")]
impl Avx {
    /// `Some` where the CPU has AVX (the check is cached by the standard library).
    #[inline(always)]
    pub(crate) fn detect() -> Option<Avx> {
        std::arch::is_x86_feature_detected!("avx").then_some(Avx(()))
    }
}

#[cfg(target_arch = "x86_64")]
impl SlabTest for Avx {
    #[inline(always)]
    fn entries(self, slabs: &Slabs, node: &WideNode, tmin: f32, tmax: f32) -> Entries {
        // SAFETY: an `Avx` value exists only where the CPU has AVX.
        unsafe { entries_avx(slabs, node, tmin, tmax) }
    }
}

/// [`Portable::entries`] with 8-lane registers: the same operations in the same order.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
#[inline]
fn entries_avx(slabs: &Slabs, node: &WideNode, tmin: f32, tmax: f32) -> Entries {
    use std::arch::x86_64::*;
    // The child references, read once the test has picked a lane, sit in the node's last
    // cache line: start loading it with the boxes.
    _mm_prefetch::<_MM_HINT_T0>(node.children.as_ptr().cast());
    let mut enter = _mm256_set1_ps(tmin);
    let mut exit = _mm256_set1_ps(tmax);
    for axis in 0..3 {
        let (near, far) = slabs.planes(node, axis);
        let o = _mm256_set1_ps(slabs.origin[axis]);
        let i = _mm256_set1_ps(slabs.inv_dir[axis]);
        // SAFETY: `near` and `far` are arrays of eight floats at 32-byte aligned offsets of a
        // 32-byte aligned `WideNode`.
        let (near, far) = unsafe { (_mm256_load_ps(near.as_ptr()), _mm256_load_ps(far.as_ptr())) };
        // `maxps x, acc` / `minps x, acc` keep `acc` where `x` is NaN, as in `Portable`.
        enter = _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(near, o), i), enter);
        exit = _mm256_min_ps(_mm256_mul_ps(_mm256_sub_ps(far, o), i), exit);
    }
    let inside =
        _mm256_cmp_ps::<_CMP_LE_OQ>(enter, _mm256_mul_ps(exit, _mm256_set1_ps(EXIT_SLACK)));
    let mut entries = [0.0; WIDTH];
    // SAFETY: `entries` holds eight floats.
    unsafe { _mm256_storeu_ps(entries.as_mut_ptr(), enter) };
    (entries, _mm256_movemask_ps(inside) as u32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Rng;

    /// A node with random boxes, some flat, some lanes empty.
    fn random_node(rng: &mut Rng) -> WideNode {
        let mut node = WideNode::EMPTY;
        for lane in 0..WIDTH {
            if rng.next() < 0.2 {
                continue;
            }
            let (a, b) = (rng.coords(), rng.coords());
            let (mut min, max) = (a.min(b), a.max(b));
            if rng.next() < 0.2 {
                min.y = max.y;
            }
            node.set_lane(lane, min, max, lane as u32);
        }
        node
    }

    #[test]
    fn portable_test_finds_the_boxes_a_ray_crosses() {
        let mut rng = Rng::new(3);
        for _ in 0..2000 {
            let node = random_node(&mut rng);
            let ray = Ray::unbounded(rng.coords() * 2.0, rng.coords(), 0.0);
            let (entries, mask) = Portable.entries(&Slabs::new(&ray), &node, 0.0, f32::INFINITY);
            for (lane, &entry) in entries.iter().enumerate() {
                // A point of the box on the ray (the entry point) is inside the box, up to
                // rounding; lanes not entered have no point of the ray inside.
                if mask & (1 << lane) != 0 {
                    let p = ray.at(entry);
                    let (min, max) = node.lane_box(lane);
                    let slack = 1e-4 * (1.0 + p.abs().max_element());
                    assert!(
                        p.cmpge(min - slack).all() && p.cmple(max + slack).all(),
                        "lane {lane}: {p} outside {min}..{max}"
                    );
                } else if let (min, max) = node.lane_box(lane)
                    && min.x <= max.x
                {
                    let centre = 0.5 * (min + max);
                    // The ray through the box's centre enters it.
                    let towards = Ray::unbounded(ray.origin, centre - ray.origin, 0.0);
                    let (_, m) = Portable.entries(&Slabs::new(&towards), &node, 0.0, f32::INFINITY);
                    assert!(m & (1 << lane) != 0 || centre == ray.origin, "lane {lane}");
                }
            }
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx_and_portable_tests_agree_bit_for_bit() {
        let Some(avx) = Avx::detect() else {
            eprintln!("this CPU has no AVX: nothing to compare");
            return;
        };
        let mut rng = Rng::new(11);
        for _ in 0..20_000 {
            let node = random_node(&mut rng);
            // Directions with zero components and origins on box planes included.
            let ray = Ray::unbounded(rng.coords(), rng.coords(), 0.0);
            let (tmin, tmax) = (
                rng.next(),
                [f32::INFINITY, 2.0 * rng.next()][(rng.next() * 2.0) as usize],
            );
            let slabs = Slabs::new(&ray);
            let (t, mask) = Portable.entries(&slabs, &node, tmin, tmax);
            let (t_avx, mask_avx) = avx.entries(&slabs, &node, tmin, tmax);
            assert_eq!(mask_avx, mask, "{ray:?}");
            assert_eq!(t_avx.map(f32::to_bits), t.map(f32::to_bits), "{ray:?}");
        }
    }

    #[test]
    fn slab_test_handles_zero_direction_components() {
        let unit = (Vec3::ZERO, Vec3::ONE);
        let flat = (Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0));
        // The box in lane 2 of a wide node, the other lanes empty.
        let entry = |o: Vec3, d: Vec3, (min, max): &(Vec3, Vec3)| {
            let mut wide = WideNode::EMPTY;
            wide.set_lane(2, *min, *max, 0);
            let slabs = Slabs::new(&Ray::unbounded(o, d, 0.0));
            let (t, mask) = Portable.entries(&slabs, &wide, 0.0, f32::INFINITY);
            #[cfg(target_arch = "x86_64")]
            if let Some(avx) = Avx::detect() {
                let (t_avx, mask_avx) = avx.entries(&slabs, &wide, 0.0, f32::INFINITY);
                assert_eq!(mask_avx, mask);
                assert_eq!(t_avx.map(f32::to_bits), t.map(f32::to_bits));
            }
            assert_eq!(mask & !0b100, 0, "empty lanes are never entered");
            (mask != 0).then_some(t[2])
        };
        for d in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(0.0, 0.6, 0.8),
            Vec3::new(-0.0, -0.6, -0.8),
        ] {
            // On the min and max faces of a slab the ray runs parallel to: inside.
            for o in [
                Vec3::new(0.0, 0.5, 0.5),
                Vec3::new(1.0, 0.5, 0.5),
                Vec3::new(0.0, 0.0, 0.5),
            ] {
                assert_eq!(entry(o, d, &unit), Some(0.0), "{o} {d}");
            }
            // Just outside: miss.
            assert_eq!(entry(Vec3::new(-1e-6, 0.5, 0.5), d, &unit), None);
            assert_eq!(entry(Vec3::new(1.0 + 1e-6, 0.5, 0.5), d, &unit), None);
        }
        // A flat box, approached from outside within its plane and across it.
        assert_eq!(entry(Vec3::new(-1.0, 0.5, 0.0), Vec3::X, &flat), Some(1.0));
        assert_eq!(entry(Vec3::new(0.5, 0.5, 2.0), -Vec3::Z, &flat), Some(2.0));
        assert_eq!(entry(Vec3::new(-1.0, 0.5, 1e-6), Vec3::X, &flat), None);
        // From outside along an axis.
        assert_eq!(entry(Vec3::new(0.5, 0.5, -2.0), Vec3::Z, &unit), Some(2.0));
        assert_eq!(entry(Vec3::new(0.5, 0.5, 3.0), -Vec3::Z, &unit), Some(2.0));
        assert_eq!(entry(Vec3::new(0.5, 0.5, 3.0), Vec3::Z, &unit), None);
    }
}
