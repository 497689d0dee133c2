use glam::{BVec4A, Vec3, Vec4};

use crate::math::Ray;

/// Intersects `ray` with the triangle `(v0, v1, v2)`, from either side.
///
/// Returns `(t, beta, gamma)` with the hit point `(1 − beta − gamma)·v0 + beta·v1 + gamma·v2`,
/// where `ray.tmin ≤ t ≤ ray.tmax`, `beta ≥ 0`, `gamma ≥ 0` and `beta + gamma ≤ 1`. `None` for a
/// miss, a degenerate (zero-area) triangle, or a ray parallel to the triangle's plane.
///
/// This is the watertight algorithm of Woop, Benthin and Wald, "Watertight Ray/Triangle
/// Intersection" (JCGT 2013): the vertices are moved into a ray-aligned frame (translated to the
/// origin, permuted so the direction's largest component is `z`, and sheared so the direction
/// becomes `(0, 0, 1)`) and the hit is decided by the signs of three 2D edge functions. The
/// edge function of an edge depends only on that edge's two vertices, so two triangles sharing
/// an edge can never both miss a ray that crosses it (no cracks in closed meshes, also not
/// through shared vertices); values that round to exactly zero are recomputed in `f64`.
///
/// To test one ray against many triangles, prepare it once with [`TriangleRay::new`] and call
/// [`TriangleRay::intersect`]: the answers are bit for bit the same.
#[inline(always)]
pub fn intersect_triangle(ray: &Ray, v0: Vec3, v1: Vec3, v2: Vec3) -> Option<(f32, f32, f32)> {
    TriangleRay::new(ray).intersect(ray, v0, v1, v2)
}

/// The axes that the cyclic permutation moving the direction's largest component last puts in
/// `x`, `y` and `z`, by the index of that component: `(y, z, x)` when `x` is largest, `(z, x, y)`
/// for `y`, `(x, y, z)` for `z`. (Cyclic, so it keeps the handedness; and since both sides of
/// the triangle count, the sign of that component needs no further care.)
const PERMUTED_AXES: [[usize; 3]; 3] = [[1, 2, 0], [2, 0, 1], [0, 1, 2]];

/// `v`'s components in the order `axes`.
#[inline(always)]
fn permute(v: Vec3, [kx, ky, kz]: [usize; 3]) -> Vec3 {
    let v = v.to_array();
    Vec3::new(v[kx], v[ky], v[kz])
}

/// The 2D edge function `p.x·q.y − p.y·q.x` in double precision, rounded to `f32`: its sign is
/// exact for `f32` inputs (the watertight test's fallback on edges).
#[inline(always)]
fn edge_function_f64(px: f32, py: f32, qx: f32, qy: f32) -> f32 {
    (px as f64 * qy as f64 - py as f64 * qx as f64) as f32
}

/// The barycentrics `(β, γ)` from the scaled ones `v`, `w` and `1 / det`, clamped so that the
/// documented ranges hold exactly despite rounding.
#[inline(always)]
fn clamped_barycentrics(v: f32, w: f32, inv_det: f32) -> (f32, f32) {
    let beta = (v * inv_det).min(1.0);
    let gamma = (w * inv_det).min(1.0 - beta);
    (beta, gamma)
}

/// The part of the watertight triangle test ([`intersect_triangle`]) that depends on the ray
/// only — its origin, the axis permutation and the shear — computed once for a ray that is
/// tested against many triangles (Woop et al. precompute it the same way).
#[derive(Clone, Copy, Debug)]
pub struct TriangleRay {
    origin: Vec3,
    /// The axes moved to `x`, `y` and `z` (a row of [`PERMUTED_AXES`]).
    axes: [usize; 3],
    /// Shear of the permuted `x` and `y` by the permuted `z` (`d.x / d.z`, `d.y / d.z`).
    sx: f32,
    sy: f32,
    /// Scale of the permuted `z` (`1 / d.z`).
    sz: f32,
}

impl TriangleRay {
    /// Prepares the triangle test for rays with `ray`'s origin and direction.
    #[inline(always)]
    pub fn new(ray: &Ray) -> Self {
        // Permute the axes so that the direction's largest component is the last one; chosen
        // by index, not by a branch: the direction changes from ray to ray.
        let ad = ray.direction.abs();
        let largest = if ad.x > ad.y && ad.x > ad.z {
            0
        } else if ad.y > ad.z {
            1
        } else {
            2
        };
        let axes = PERMUTED_AXES[largest];
        let d = permute(ray.direction, axes);
        // Shear so that the direction becomes +z (up to the scale `sz` applied to `z` only).
        let sz = 1.0 / d.z;
        TriangleRay {
            origin: ray.origin,
            axes,
            sx: d.x * sz,
            sy: d.y * sz,
            sz,
        }
    }

    /// The distance `t` of the watertight test's hit on `(v0, v1, v2)` for `ray` (same rules
    /// as for [`intersect`](Self::intersect)), without the barycentrics: what a peer BVH of
    /// `raylab bench` needs to run the framework's kernel in its own traversal.
    #[inline(always)]
    pub fn distance(&self, ray: &Ray, v0: Vec3, v1: Vec3, v2: Vec3) -> Option<f32> {
        self.intersect(ray, v0, v1, v2).map(|(t, _, _)| t)
    }

    /// [`intersect_triangle`] for `ray`, which must have the origin and direction this was
    /// prepared for (its `tmin` and `tmax` may differ, a closest-hit search shrinks `tmax`).
    #[inline(always)]
    pub(crate) fn intersect(
        &self,
        ray: &Ray,
        v0: Vec3,
        v1: Vec3,
        v2: Vec3,
    ) -> Option<(f32, f32, f32)> {
        debug_assert_eq!(
            ray.origin.to_array().map(f32::to_bits),
            self.origin.to_array().map(f32::to_bits)
        );
        let o = self.origin;
        let p = self.axes;
        let (a, b, c) = (permute(v0 - o, p), permute(v1 - o, p), permute(v2 - o, p));
        let (sx, sy, sz) = (self.sx, self.sy, self.sz);
        let (ax, ay) = (a.x - sx * a.z, a.y - sy * a.z);
        let (bx, by) = (b.x - sx * b.z, b.y - sy * b.z);
        let (cx, cy) = (c.x - sx * c.z, c.y - sy * c.z);
        // Scaled barycentrics: twice the signed areas of the sub-triangles opposite each
        // vertex, as seen along the ray.
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            // On (or extremely close to) an edge: decide with the exact sign from double
            // precision.
            u = edge_function_f64(cx, cy, bx, by);
            v = edge_function_f64(ax, ay, cx, cy);
            w = edge_function_f64(bx, by, ax, ay);
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        // `t·det`, interpolating the vertices' sheared z.
        let t_scaled = (u * a.z + v * b.z + w * c.z) * sz;
        let inv_det = 1.0 / det;
        let t = t_scaled * inv_det;
        // Also rejects NaN, which only non-finite input or a zero direction can produce.
        if !ray.accepts(t) {
            return None;
        }
        let (beta, gamma) = clamped_barycentrics(v, w, inv_det);
        Some((t, beta, gamma))
    }

    /// [`intersect`](Self::intersect) for the four triangles of `block` at once (SIMD lanes):
    /// the same operations in the same order, lane by lane, so each lane's answer is bit for bit
    /// the one `intersect` gives for that triangle with the same `ray`.
    #[inline(always)]
    pub(crate) fn intersect4(&self, ray: &Ray, block: &TriangleBlock) -> BlockHits {
        let [kx, ky, kz] = self.axes;
        let o = permute(self.origin, self.axes).to_array().map(Vec4::splat);
        let (sx, sy, sz) = (
            Vec4::splat(self.sx),
            Vec4::splat(self.sy),
            Vec4::splat(self.sz),
        );
        // Translated, permuted and sheared, as in `intersect`: (x − sx·z, y − sy·z, z).
        let vertex = |k: usize| {
            let v = &block.vertices[k];
            let (x, y, z) = (v[kx] - o[0], v[ky] - o[1], v[kz] - o[2]);
            (x - sx * z, y - sy * z, z)
        };
        let (ax, ay, az) = vertex(0);
        let (bx, by, bz) = vertex(1);
        let (cx, cy, cz) = vertex(2);
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        let on_edge = (u.cmpeq(Vec4::ZERO) | v.cmpeq(Vec4::ZERO) | w.cmpeq(Vec4::ZERO)).bitmask();
        if on_edge != 0 {
            let (mut uu, mut vv, mut ww) = (u.to_array(), v.to_array(), w.to_array());
            let [ax, ay, bx, by, cx, cy] = [ax, ay, bx, by, cx, cy].map(|x| x.to_array());
            for lane in (0..4).filter(|lane| on_edge & (1 << lane) != 0) {
                uu[lane] = edge_function_f64(cx[lane], cy[lane], bx[lane], by[lane]);
                vv[lane] = edge_function_f64(ax[lane], ay[lane], cx[lane], cy[lane]);
                ww[lane] = edge_function_f64(bx[lane], by[lane], ax[lane], ay[lane]);
            }
            (u, v, w) = (uu.into(), vv.into(), ww.into());
        }
        let zero = Vec4::ZERO;
        let outside = (u.cmplt(zero) | v.cmplt(zero) | w.cmplt(zero))
            & (u.cmpgt(zero) | v.cmpgt(zero) | w.cmpgt(zero));
        let det = u + v + w;
        let t_scaled = (u * az + v * bz + w * cz) * sz;
        let inv_det = Vec4::ONE / det;
        let t = t_scaled * inv_det;
        // `ray.accepts(t)` lane by lane (false for NaN).
        let accepted = t.cmpge(Vec4::splat(ray.tmin)) & t.cmple(Vec4::splat(ray.tmax));
        let hit = !outside & det.cmpne(zero) & accepted;
        BlockHits {
            mask: BVec4A::bitmask(hit),
            t: t.to_array(),
            v: v.to_array(),
            w: w.to_array(),
            inv_det: inv_det.to_array(),
        }
    }
}

/// Four triangles side by side (structure of arrays) for [`TriangleRay::intersect4`]:
/// `vertices[k][axis]` holds coordinate `axis` of vertex `k` of the four triangles, one per
/// lane. Lanes without a triangle have NaN coordinates, which no ray hits.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub(crate) struct TriangleBlock {
    pub vertices: [[Vec4; 3]; 3],
}

impl TriangleBlock {
    /// Four empty lanes.
    pub(crate) const EMPTY: TriangleBlock = TriangleBlock {
        vertices: [[Vec4::NAN; 3]; 3],
    };

    /// Puts the triangle `[v0, v1, v2]` in `lane`.
    pub(crate) fn set(&mut self, lane: usize, triangle: [Vec3; 3]) {
        for (k, v) in triangle.into_iter().enumerate() {
            for axis in 0..3 {
                self.vertices[k][axis][lane] = v[axis];
            }
        }
    }

    /// The triangle in `lane`.
    #[inline(always)]
    pub(crate) fn get(&self, lane: usize) -> [Vec3; 3] {
        let lane = lane & 3;
        self.vertices
            .map(|[x, y, z]| Vec3::new(x.to_array()[lane], y.to_array()[lane], z.to_array()[lane]))
    }
}

/// What [`TriangleRay::intersect4`] found: the lanes hit within the ray's `[tmin, tmax]`, and
/// per lane the values `intersect` would have returned.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BlockHits {
    /// Bit `i` set when lane `i`'s triangle is hit.
    pub mask: u32,
    /// Ray parameter of each lane's hit.
    pub t: [f32; 4],
    v: [f32; 4],
    w: [f32; 4],
    inv_det: [f32; 4],
}

impl BlockHits {
    /// The barycentrics `(β, γ)` of lane `lane`'s hit, as `intersect` returns them.
    #[inline(always)]
    pub(crate) fn barycentrics(&self, lane: usize) -> (f32, f32) {
        let lane = lane & 3;
        clamped_barycentrics(self.v[lane], self.w[lane], self.inv_det[lane])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Rng;

    fn check_hit(ray: &Ray, v: [Vec3; 3], hit: (f32, f32, f32)) {
        let (t, b, g) = hit;
        assert!(ray.accepts(t));
        assert!(b >= 0.0 && g >= 0.0 && b + g <= 1.0, "{b} {g}");
        let p = (1.0 - b - g) * v[0] + b * v[1] + g * v[2];
        assert!((p - ray.at(t)).length() < 1e-4, "{p} vs {}", ray.at(t));
    }

    #[test]
    fn hit_interior_point_from_both_sides() {
        let v = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let target = 0.5 * v[0] + 0.2 * v[1] + 0.3 * v[2];
        for origin in [Vec3::new(0.3, -0.4, 2.0), Vec3::new(-0.5, 0.7, -3.0)] {
            let ray = Ray::unbounded(origin, (target - origin).normalize(), 0.0);
            let hit = intersect_triangle(&ray, v[0], v[1], v[2]).expect("hit");
            check_hit(&ray, v, hit);
            assert!((hit.1 - 0.2).abs() < 1e-5 && (hit.2 - 0.3).abs() < 1e-5);
        }
    }

    #[test]
    fn random_rays_agree_with_barycentric_reference() {
        let mut rng = Rng::new(7);
        let mut hits = 0;
        for _ in 0..20_000 {
            let v = [rng.vec(), rng.vec(), rng.vec()];
            let origin = rng.vec() * 3.0;
            let dir = (rng.vec() * 0.5 - origin).normalize();
            let ray = Ray::unbounded(origin, dir, 0.0);
            // Reference in f64: plane hit, then barycentrics by areas.
            let [p0, p1, p2] = v.map(|p| p.as_dvec3());
            let n = (p1 - p0).cross(p2 - p0);
            let (o, dd) = (origin.as_dvec3(), dir.as_dvec3());
            let denom = n.dot(dd);
            let expected = (denom.abs() > 1e-9)
                .then(|| n.dot(p0 - o) / denom)
                .and_then(|t| {
                    let p = o + t * dd;
                    let b = (p - p0).cross(p2 - p0).dot(n) / n.length_squared();
                    let g = (p1 - p0).cross(p - p0).dot(n) / n.length_squared();
                    (t >= 0.0 && b >= 0.0 && g >= 0.0 && b + g <= 1.0).then_some((t, b, g, p))
                });
            let got = intersect_triangle(&ray, v[0], v[1], v[2]);
            match (expected, got) {
                (Some((t, b, g, _)), Some(h)) => {
                    hits += 1;
                    check_hit(&ray, v, h);
                    assert!(
                        (t as f32 - h.0).abs() < 1e-3 * (1.0 + t as f32),
                        "{t} {h:?}"
                    );
                    assert!((b as f32 - h.1).abs() < 1e-3 && (g as f32 - h.2).abs() < 1e-3);
                }
                (None, None) => {}
                // Within rounding of an edge either answer is fine.
                (Some((_, b, g, _)), None) => {
                    assert!(b.min(g).min(1.0 - b - g) < 1e-4, "missed {v:?} {ray:?}")
                }
                (None, Some(h)) => {
                    assert!(h.1.min(h.2).min(1.0 - h.1 - h.2) < 1e-4, "false hit {h:?}")
                }
            }
        }
        assert!(hits > 1000, "{hits}");
    }

    #[test]
    fn edges_and_vertices_are_hit() {
        let v = [
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let points = [
            v[0],
            v[1],
            v[2],
            0.5 * (v[0] + v[1]),
            0.5 * (v[1] + v[2]),
            0.5 * (v[2] + v[0]),
        ];
        for p in points {
            let origin = p + Vec3::new(0.0, 0.0, 5.0);
            let ray = Ray::unbounded(origin, -Vec3::Z, 0.0);
            let hit =
                intersect_triangle(&ray, v[0], v[1], v[2]).unwrap_or_else(|| panic!("missed {p}"));
            check_hit(&ray, v, hit);
            assert!((hit.0 - 5.0).abs() < 1e-6);
        }
        // Just outside an edge misses.
        let ray = Ray::unbounded(Vec3::new(0.0, -1.001, 5.0), -Vec3::Z, 0.0);
        assert!(intersect_triangle(&ray, v[0], v[1], v[2]).is_none());
    }

    #[test]
    fn shared_edges_of_a_closed_mesh_leave_no_cracks() {
        // An octahedron: every ray from inside must hit at least one face.
        let p = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z]
            .map(|v| v * 1.7 + Vec3::new(0.1, 0.2, 0.3));
        let faces = [
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ];
        let mut rng = Rng::new(99);
        let center = Vec3::new(0.1, 0.2, 0.3);
        for i in 0..50_000 {
            // Aim at points on edges (and vertices) of the mesh from random inside points.
            let f = faces[i % 8];
            let s = rng.next();
            let target = if i % 7 == 0 {
                p[f[0]]
            } else {
                p[f[0]].lerp(p[f[1]], s)
            };
            let origin = center + rng.vec() * 0.3;
            let ray = Ray::unbounded(origin, (target - origin).normalize(), 0.0);
            let hit = faces
                .iter()
                .any(|f| intersect_triangle(&ray, p[f[0]], p[f[1]], p[f[2]]).is_some());
            assert!(hit, "crack: {ray:?}");
        }
    }

    #[test]
    fn tmin_and_tmax_are_honoured() {
        let v = [
            Vec3::new(-1.0, -1.0, 3.0),
            Vec3::new(1.0, -1.0, 3.0),
            Vec3::new(0.0, 1.0, 3.0),
        ];
        let ray = |tmin, tmax| Ray::new(Vec3::ZERO, Vec3::Z, tmin, tmax);
        assert!(intersect_triangle(&ray(0.0, 3.0), v[0], v[1], v[2]).is_some());
        assert!(intersect_triangle(&ray(3.0, 4.0), v[0], v[1], v[2]).is_some());
        assert!(intersect_triangle(&ray(0.0, 2.99), v[0], v[1], v[2]).is_none());
        assert!(intersect_triangle(&ray(3.01, 9.0), v[0], v[1], v[2]).is_none());
        // Behind the origin.
        let back = Ray::unbounded(Vec3::ZERO, -Vec3::Z, 0.0);
        assert!(intersect_triangle(&back, v[0], v[1], v[2]).is_none());
    }

    #[test]
    fn degenerate_and_parallel_return_none() {
        let ray = Ray::unbounded(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z, 0.0);
        // Collinear vertices.
        let (a, b, c) = (
            Vec3::ZERO,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(2.0, 2.0, 0.0),
        );
        assert!(intersect_triangle(&ray, a, b, c).is_none());
        // All vertices equal.
        assert!(intersect_triangle(&ray, Vec3::ZERO, Vec3::ZERO, Vec3::ZERO).is_none());
        let through = Ray::unbounded(Vec3::new(0.0, 0.0, 1.0), -Vec3::Z, 0.0);
        assert!(intersect_triangle(&through, Vec3::ZERO, Vec3::ZERO, Vec3::ZERO).is_none());
        // A ray in the triangle's plane (parallel), also one crossing its interior.
        let v = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let in_plane = Ray::unbounded(Vec3::new(-1.0, 0.25, 0.0), Vec3::X, 0.0);
        assert!(intersect_triangle(&in_plane, v[0], v[1], v[2]).is_none());
        let above = Ray::unbounded(Vec3::new(-1.0, 0.25, 0.5), Vec3::X, 0.0);
        assert!(intersect_triangle(&above, v[0], v[1], v[2]).is_none());
        // A zero direction.
        let zero = Ray::unbounded(Vec3::new(0.2, 0.2, 0.0), Vec3::ZERO, 0.0);
        assert!(intersect_triangle(&zero, v[0], v[1], v[2]).is_none());
    }

    #[test]
    fn non_unit_direction_gives_parameter_t() {
        let v = [
            Vec3::new(-1.0, -1.0, 4.0),
            Vec3::new(1.0, -1.0, 4.0),
            Vec3::new(0.0, 1.0, 4.0),
        ];
        let ray = Ray::unbounded(Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0), 0.0);
        let (t, _, _) = intersect_triangle(&ray, v[0], v[1], v[2]).unwrap();
        assert!((t - 2.0).abs() < 1e-6);
    }

    /// `intersect4` on the block of `triangles` (padded with empty lanes) agrees lane by lane,
    /// bit for bit, with `intersect`.
    fn assert_block_agrees(ray: &Ray, triangles: &[[Vec3; 3]]) {
        let mut block = TriangleBlock::EMPTY;
        for (lane, &t) in triangles.iter().enumerate() {
            block.set(lane, t);
            assert_eq!(block.get(lane), t);
        }
        let prepared = TriangleRay::new(ray);
        let hits = prepared.intersect4(ray, &block);
        for lane in 0..4 {
            let scalar = triangles
                .get(lane)
                .and_then(|&[a, b, c]| prepared.intersect(ray, a, b, c));
            let simd = (hits.mask & (1 << lane) != 0).then(|| {
                let (beta, gamma) = hits.barycentrics(lane);
                (hits.t[lane], beta, gamma)
            });
            let bits = |h: Option<(f32, f32, f32)>| h.map(|(t, b, g)| [t, b, g].map(f32::to_bits));
            assert_eq!(
                bits(simd),
                bits(scalar),
                "lane {lane} of {triangles:?}, {ray:?}"
            );
        }
    }

    #[test]
    fn four_lanes_agree_with_one_at_a_time() {
        let mut rng = Rng::new(5);
        // Random triangles and rays, with shrunk intervals.
        for _ in 0..20_000 {
            let n = 1 + (rng.next() * 4.0) as usize;
            let triangles: Vec<[Vec3; 3]> =
                (0..n).map(|_| [rng.vec(), rng.vec(), rng.vec()]).collect();
            let mut ray = Ray::unbounded(rng.vec() * 2.0, rng.vec(), 0.0);
            if rng.next() < 0.3 {
                (ray.tmin, ray.tmax) = (rng.next(), 1.0 + rng.next());
            }
            assert_block_agrees(&ray, &triangles);
        }
        // Rays through shared edges and vertices of a fan, where the edge functions round to
        // zero and the `f64` fallback decides, and axis-aligned directions.
        let fan = [
            [Vec3::ZERO, Vec3::X, Vec3::Y],
            [Vec3::ZERO, Vec3::Y, -Vec3::X],
            [Vec3::ZERO, -Vec3::X, -Vec3::Y],
            [Vec3::ZERO, -Vec3::Y, Vec3::X],
        ];
        for i in 0..20_000 {
            let target = match i % 3 {
                0 => Vec3::ZERO,
                1 => Vec3::X * rng.next(),
                _ => Vec3::new(rng.next(), 1.0 - rng.next(), 0.0) * 0.5,
            };
            let origin = if i % 5 == 0 {
                target + Vec3::Z
            } else {
                rng.vec() + Vec3::Z * 2.0
            };
            let ray = Ray::unbounded(origin, target - origin, 0.0);
            assert_block_agrees(&ray, &fan);
        }
        // Degenerate triangles, a ray in their plane, a zero direction.
        let degenerate = [
            [Vec3::ZERO, Vec3::ONE, Vec3::ONE * 2.0],
            [Vec3::ZERO; 3],
            [Vec3::ZERO, Vec3::X, Vec3::Y],
        ];
        for ray in [
            Ray::unbounded(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z, 0.0),
            Ray::unbounded(Vec3::new(-1.0, 0.25, 0.0), Vec3::X, 0.0),
            Ray::unbounded(Vec3::new(0.2, 0.2, 0.0), Vec3::ZERO, 0.0),
        ] {
            assert_block_agrees(&ray, &degenerate);
        }
    }
}
