use glam::Vec3;

use crate::math::Ray;

/// Intersects `ray` with the plane of points `p` where `p·normal + d = 0`.
///
/// Returns `t = −(origin·normal + d) / (direction·normal)` when it lies in
/// `[ray.tmin, ray.tmax]`; `None` when the ray is parallel to the plane (including a ray lying
/// in it) or the hit is out of range. `normal` need not be unit length.
#[inline]
pub fn intersect_plane(ray: &Ray, normal: Vec3, d: f32) -> Option<f32> {
    let denom = ray.direction.dot(normal);
    if denom == 0.0 {
        return None;
    }
    let t = -(ray.origin.dot(normal) + d) / denom;
    // NaN (non-finite inputs) fails the comparison and is rejected.
    ray.accepts(t).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hit_lies_on_the_plane() {
        let n = Vec3::new(0.3, 1.0, -0.2).normalize();
        let d = -1.5;
        let ray = Ray::unbounded(
            Vec3::new(0.1, -2.0, 0.4),
            Vec3::new(0.2, 1.0, 0.1).normalize(),
            0.0,
        );
        let t = intersect_plane(&ray, n, d).expect("hit");
        assert!((ray.at(t).dot(n) + d).abs() < 1e-5);
        assert!(t > 0.0);
    }

    #[test]
    fn either_side_and_unnormalized_normal() {
        // Plane y = 1 written with a scaled normal.
        let ray = Ray::unbounded(Vec3::new(0.0, 3.0, 0.0), -Vec3::Y, 0.0);
        let t = intersect_plane(&ray, Vec3::new(0.0, 2.0, 0.0), -2.0).unwrap();
        assert!((t - 2.0).abs() < 1e-6);
        let ray = Ray::unbounded(Vec3::ZERO, Vec3::Y, 0.0);
        assert_eq!(intersect_plane(&ray, -Vec3::Y, 1.0), Some(1.0));
    }

    #[test]
    fn parallel_ray_misses() {
        let ray = Ray::unbounded(Vec3::new(0.0, 1.0, 0.0), Vec3::X, 0.0);
        assert_eq!(intersect_plane(&ray, Vec3::Y, 0.0), None);
        // A ray lying in the plane is parallel too.
        let ray = Ray::unbounded(Vec3::ZERO, Vec3::X, 0.0);
        assert_eq!(intersect_plane(&ray, Vec3::Y, 0.0), None);
    }

    #[test]
    fn tmin_and_tmax_are_honoured() {
        let n = Vec3::Z;
        let ray = |tmin, tmax| Ray::new(Vec3::ZERO, Vec3::Z, tmin, tmax);
        assert_eq!(intersect_plane(&ray(0.0, 10.0), n, -5.0), Some(5.0));
        assert_eq!(intersect_plane(&ray(5.0, 5.0), n, -5.0), Some(5.0));
        assert_eq!(intersect_plane(&ray(0.0, 4.9), n, -5.0), None);
        assert_eq!(intersect_plane(&ray(5.1, 10.0), n, -5.0), None);
        // Behind the origin.
        assert_eq!(intersect_plane(&ray(0.0, 10.0), n, 5.0), None);
    }
}
