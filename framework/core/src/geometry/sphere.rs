use glam::Vec3;

use crate::math::Ray;

/// Intersects `ray` with the sphere of the given `center` and `radius`.
///
/// Returns the nearest root `t` in `[ray.tmin, ray.tmax]`: the near root, or the far root when
/// the near one is below `tmin` (so a ray starting inside the sphere hits its far side). `None`
/// when the ray misses, both roots are out of range, or the direction is zero.
///
/// Uses the numerically stable formulation of Haines et al., "Precision Improvements for
/// Ray/Sphere Intersection" (Ray Tracing Gems, ch. 7): the discriminant is computed from the
/// ray's closest approach to the centre, and the roots without cancellation. Exact for any
/// direction length; `t` is the Euclidean distance when the direction is unit length.
#[inline]
pub fn intersect_sphere(ray: &Ray, center: Vec3, radius: f32) -> Option<f32> {
    let d = ray.direction;
    let f = ray.origin - center;
    let a = d.dot(d);
    if a == 0.0 {
        return None;
    }
    let b = f.dot(d); // Half of the usual `b`.
    let c = f.dot(f) - radius * radius;
    // `l` is the vector from the centre to the point of closest approach, so
    // `b² − a·c = a·(r² − |l|²)` without the catastrophic cancellation of `b² − a·c`.
    let l = f - (b / a) * d;
    let disc = a * (radius * radius - l.length_squared());
    // A miss, or NaN from non-finite input.
    if disc < 0.0 || disc.is_nan() {
        return None;
    }
    let q = -b - disc.sqrt().copysign(b);
    // Roots `c/q` and `q/a`; `q == 0` only for a tangent ray through the origin (`c = 0`).
    let (t0, t1) = if q == 0.0 {
        (0.0, 0.0)
    } else {
        let (r0, r1) = (c / q, q / a);
        if r0 <= r1 { (r0, r1) } else { (r1, r0) }
    };
    if ray.accepts(t0) {
        Some(t0)
    } else if ray.accepts(t1) {
        Some(t1)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn on_sphere(p: Vec3, c: Vec3, r: f32) -> bool {
        ((p - c).length() - r).abs() <= 1e-4 * r.max(1.0)
    }

    #[test]
    fn near_root_from_outside() {
        let c = Vec3::new(0.0, 0.0, -5.0);
        let ray = Ray::unbounded(Vec3::ZERO, -Vec3::Z, 0.0);
        let t = intersect_sphere(&ray, c, 1.0).unwrap();
        assert!((t - 4.0).abs() < 1e-6);
        // Oblique ray: the hit is on the surface and it is the first of the two.
        let dir = Vec3::new(0.15, 0.1, -1.0).normalize();
        let ray = Ray::unbounded(Vec3::ZERO, dir, 0.0);
        let t = intersect_sphere(&ray, c, 1.0).unwrap();
        assert!(on_sphere(ray.at(t), c, 1.0));
        assert!(
            (ray.at(t) - c).dot(dir) < 0.0,
            "the near root faces the ray"
        );
    }

    #[test]
    fn far_root_from_inside() {
        let c = Vec3::new(1.0, 2.0, 3.0);
        let ray = Ray::unbounded(c + Vec3::new(0.2, 0.0, 0.0), Vec3::X, 0.0);
        let t = intersect_sphere(&ray, c, 2.0).unwrap();
        assert!((t - 1.8).abs() < 1e-5);
        // A ray leaving the surface outward (tmin > 0) misses; inward, it hits the far side.
        let p = c + Vec3::new(0.0, 2.0, 0.0);
        assert_eq!(
            intersect_sphere(&Ray::unbounded(p, Vec3::Y, 1e-4), c, 2.0),
            None
        );
        let t = intersect_sphere(&Ray::unbounded(p, -Vec3::Y, 1e-4), c, 2.0).unwrap();
        assert!((t - 4.0).abs() < 1e-4);
    }

    #[test]
    fn tmin_and_tmax_are_honoured() {
        let c = Vec3::new(0.0, 0.0, 10.0);
        let ray = |tmin, tmax| Ray::new(Vec3::ZERO, Vec3::Z, tmin, tmax);
        assert_eq!(intersect_sphere(&ray(0.0, 8.9), c, 1.0), None);
        assert_eq!(intersect_sphere(&ray(0.0, 9.0), c, 1.0), Some(9.0));
        assert_eq!(intersect_sphere(&ray(9.5, 20.0), c, 1.0), Some(11.0));
        assert_eq!(intersect_sphere(&ray(11.5, 20.0), c, 1.0), None);
        // Sphere behind the ray.
        assert_eq!(
            intersect_sphere(&Ray::unbounded(Vec3::ZERO, -Vec3::Z, 0.0), c, 1.0),
            None
        );
    }

    #[test]
    fn misses_and_degenerate_inputs() {
        let ray = Ray::unbounded(Vec3::new(0.0, 1.01, 0.0), Vec3::X, 0.0);
        assert_eq!(intersect_sphere(&ray, Vec3::new(5.0, 0.0, 0.0), 1.0), None);
        let zero = Ray::unbounded(Vec3::ZERO, Vec3::ZERO, 0.0);
        assert_eq!(intersect_sphere(&zero, Vec3::ZERO, 1.0), None);
        // Tangent ray.
        let ray = Ray::unbounded(Vec3::new(-5.0, 1.0, 0.0), Vec3::X, 0.0);
        let t = intersect_sphere(&ray, Vec3::ZERO, 1.0).unwrap();
        assert!((t - 5.0).abs() < 1e-3);
    }

    #[test]
    fn non_unit_direction() {
        let c = Vec3::new(0.0, 0.0, -5.0);
        let ray = Ray::unbounded(Vec3::ZERO, Vec3::new(0.0, 0.0, -2.0), 0.0);
        let t = intersect_sphere(&ray, c, 1.0).unwrap();
        assert!((t - 2.0).abs() < 1e-6);
    }

    #[test]
    fn small_sphere_far_away_is_precise() {
        // The case the stable formulation exists for: b² ≈ a·c.
        let c = Vec3::new(0.0, 0.0, -1.0e4);
        let r = 0.01;
        let mut hits = 0;
        for i in 0..100 {
            let y = (i as f32 - 50.0) * 0.0002;
            let dir = (Vec3::new(0.0, y, 0.0) + c).normalize();
            let ray = Ray::unbounded(Vec3::ZERO, dir, 0.0);
            if let Some(t) = intersect_sphere(&ray, c, r) {
                hits += 1;
                assert!(
                    ((ray.at(t) - c).length() - r).abs() < 2e-3,
                    "{}",
                    (ray.at(t) - c).length()
                );
            }
        }
        assert!(hits >= 90, "{hits}");
    }
}
