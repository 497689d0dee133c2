//! Reference solution of lab 11 (docs/lab11.md).

use std::f32::consts::{FRAC_1_PI, PI};

use contracts::glam::{Vec2, Vec3};
use contracts::lab11::{AmbientOcclusion, HemisphereSample, Occlusion};
use contracts::math::{Onb, RAY_EPSILON, Ray};
use contracts::sampling::Rng;

/// The reference ambient occlusion and light-probe mappings.
#[derive(Clone, Copy, Debug, Default)]
pub struct Lab11;

impl AmbientOcclusion for Lab11 {
    fn sample_hemisphere_rejection(&self, normal: Vec3, rng: &mut Rng) -> HemisphereSample {
        loop {
            let p = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - 1.0;
            let r2 = p.length_squared();
            // Points very near the centre have no reliable direction.
            if !(1e-6..=1.0).contains(&r2) || p.dot(normal) < 0.0 {
                continue;
            }
            return HemisphereSample {
                direction: p / r2.sqrt(),
                pdf: 0.5 * FRAC_1_PI,
            };
        }
    }

    fn sample_hemisphere_cosine(&self, normal: Vec3, rng: &mut Rng) -> HemisphereSample {
        let u = rng.next_vec2();
        // Malley's method: a uniform point of the unit disc, lifted to the hemisphere.
        let (r, phi) = (u.x.sqrt(), 2.0 * PI * u.y);
        let z = (1.0 - u.x).max(0.0).sqrt();
        let direction = Onb::from_w(normal)
            .to_world(Vec3::new(r * phi.cos(), r * phi.sin(), z))
            .normalize();
        HemisphereSample {
            direction,
            pdf: direction.dot(normal).max(0.0) * FRAC_1_PI,
        }
    }

    fn ambient_occlusion(
        &self,
        position: Vec3,
        normal: Vec3,
        samples: u32,
        sampler: &dyn Fn(&mut Rng) -> HemisphereSample,
        occluded: &dyn Fn(&Ray) -> bool,
        rng: &mut Rng,
    ) -> Occlusion {
        let (mut accessible, mut bent) = (0.0f32, Vec3::ZERO);
        for _ in 0..samples {
            let s = sampler(rng);
            let ray = Ray::unbounded(position, s.direction, RAY_EPSILON);
            if s.pdf > 0.0 && !occluded(&ray) {
                // V cos θ / (π p): the accessibility's integrand over the sampler's density.
                let w = s.direction.dot(normal).max(0.0) / (PI * s.pdf);
                accessible += w;
                bent += w * s.direction;
            }
        }
        Occlusion {
            accessibility: accessible / samples.max(1) as f32,
            bent_normal: bent.try_normalize().unwrap_or(normal),
        }
    }

    fn rgbe_to_rgb(&self, [r, g, b, e]: [u8; 4]) -> Vec3 {
        if e == 0 {
            return Vec3::ZERO;
        }
        // (m + ½)/256 · 2^(e − 128): the centre of the mantissa's interval.
        let scale = f32::exp2((i32::from(e) - 136) as f32);
        (Vec3::new(r as f32, g as f32, b as f32) + 0.5) * scale
    }

    fn angular_map_uv(&self, d: Vec3) -> Vec2 {
        let s = (d.x * d.x + d.y * d.y).sqrt();
        // The angle from −z; atan2 is accurate at both poles.
        let theta = s.atan2(-d.z);
        if s == 0.0 {
            return if d.z < 0.0 {
                Vec2::splat(0.5)
            } else {
                Vec2::new(1.0, 0.5)
            };
        }
        let r = theta / (2.0 * PI * s);
        Vec2::new(0.5 + r * d.x, 0.5 - r * d.y)
    }

    fn angular_map_direction(&self, uv: Vec2) -> Option<Vec3> {
        let (a, b) = (2.0 * uv.x - 1.0, 1.0 - 2.0 * uv.y);
        let rho = (a * a + b * b).sqrt();
        if rho > 1.0 {
            return None;
        }
        if rho == 0.0 {
            return Some(Vec3::NEG_Z);
        }
        let (sin, cos) = (PI * rho).sin_cos();
        Some(Vec3::new(sin * a / rho, sin * b / rho, -cos).normalize())
    }

    fn latlong_uv(&self, d: Vec3) -> Vec2 {
        let phi = d.x.atan2(-d.z);
        let theta = (d.x * d.x + d.z * d.z).sqrt().atan2(d.y);
        Vec2::new(0.5 + phi / (2.0 * PI), theta / PI)
    }

    fn latlong_direction(&self, uv: Vec2) -> Vec3 {
        let phi = 2.0 * PI * (uv.x - 0.5);
        let (sin, cos) = (PI * uv.y).sin_cos();
        Vec3::new(sin * phi.sin(), cos, -sin * phi.cos()).normalize()
    }

    fn shade_ambient_occlusion(
        &self,
        diffuse: Vec3,
        occlusion: &Occlusion,
        environment: Vec3,
    ) -> Vec3 {
        // ρ/π ∫ L V cos dω ≈ ρ/π · L(n_b) · π A.
        diffuse * occlusion.accessibility * environment
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mappings_round_trip() {
        let r = Lab11;
        for i in 0..500 {
            let t = i as f32 * 0.618_034;
            let d = Vec3::new((3.1 * t).sin(), (1.7 * t).cos(), (2.3 * t + 1.0).sin()).normalize();
            let back = r.angular_map_direction(r.angular_map_uv(d)).unwrap();
            assert!((back - d).length() < 1e-3 || d.z > 0.999, "{d} {back}");
            let back = r.latlong_direction(r.latlong_uv(d));
            assert!((back - d).length() < 1e-4, "{d} {back}");
        }
        assert_eq!(r.angular_map_uv(Vec3::NEG_Z), Vec2::splat(0.5));
        assert!((r.angular_map_uv(Vec3::X) - Vec2::new(0.75, 0.5)).length() < 1e-6);
        assert!((r.angular_map_uv(Vec3::Y) - Vec2::new(0.5, 0.25)).length() < 1e-6);
        assert!((r.latlong_uv(Vec3::NEG_Z) - Vec2::new(0.5, 0.5)).length() < 1e-6);
        assert!((r.latlong_uv(Vec3::X) - Vec2::new(0.75, 0.5)).length() < 1e-6);
        assert!(r.latlong_uv(Vec3::Y).y.abs() < 1e-6);
        assert_eq!(r.angular_map_direction(Vec2::new(0.0, 0.0)), None);
        // The worksheet's formula: (m + 0.5)/256 · 2^(e − 128).
        assert_eq!(
            r.rgbe_to_rgb([128, 0, 255, 129]),
            Vec3::new(128.5, 0.5, 255.5) / 128.0
        );
    }
}
