//! # Lab 11 — ambient occlusion and HDR light probes
//!
//! A surface lit by a whole environment instead of a few lamps: directions drawn over the
//! hemisphere (by rejection, then cosine-weighted), the accessibility of a point and its bent
//! normal, the RGBE pixels of a Radiance HDR file, and the two ways a light probe's image
//! covers the sphere of directions — Debevec's angular map and the latitude–longitude map.
//!
//! Read `docs/lab11.md` first: it states every formula, and says what each check checks.
//! Then fill in the functions below (in any order) and run
//!
//! ```text
//! cargo test -p lab11                   # all nine exercises
//! cargo test -p lab11 exercise_11_3     # one exercise
//! raylab report --lab 11 --pipeline student   # the report's figures with your code
//! ```
//!
//! Texture coordinates of a probe are image coordinates: `u` to the right, `v` down from the
//! top row. The world is y-up, and the probe's camera looks along −z.

// The parameters of the stubs below are unused until you fill them in.
#![allow(unused_variables)]

#[allow(unused_imports)]
use contracts::glam::{Vec2, Vec3};
#[allow(unused_imports)]
use contracts::lab11::{AmbientOcclusion, HemisphereSample, Occlusion};
#[allow(unused_imports)]
use contracts::math::{Onb, RAY_EPSILON, Ray};
use contracts::sampling::Rng;

/// Your ambient occlusion and light-probe mappings. The checks, the renderer and
/// `raylab report --lab 11` call it through the `AmbientOcclusion` trait.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl AmbientOcclusion for Student {
    /// **Exercise 11.1** — a uniform direction of the hemisphere by rejection
    /// (docs/lab11.md, Exercise 11.1).
    ///
    /// Draw `x, y, z` in `[−1, 1]` from three `rng.next_f32()`; keep drawing until the point
    /// lies in the unit ball and on the side of `normal`; return it normalized with its pdf.
    /// Hint: the hemisphere has a solid angle of 2π.
    fn sample_hemisphere_rejection(&self, normal: Vec3, rng: &mut Rng) -> HemisphereSample {
        todo!("Exercise 11.1: sample_hemisphere_rejection (docs/lab11.md, Exercise 11.1)")
    }

    /// **Exercise 11.2** — a cosine-weighted direction (docs/lab11.md, Exercise 11.2).
    ///
    /// From `u = rng.next_vec2()` make a direction in the frame of `normal` (`Onb::from_w`)
    /// whose density is `cos θ/π`, and return it with that pdf. Hint: a point uniform on the
    /// unit disc, lifted straight up onto the hemisphere — mind how the disc's radius is drawn.
    fn sample_hemisphere_cosine(&self, normal: Vec3, rng: &mut Rng) -> HemisphereSample {
        todo!("Exercise 11.2: sample_hemisphere_cosine (docs/lab11.md, Exercise 11.2)")
    }

    /// **Exercise 11.3** — accessibility and bent normal (docs/lab11.md, Exercise 11.3).
    ///
    /// For each of the `samples` samples draw `sampler(rng)`, trace `Ray::unbounded(position,
    /// direction, RAY_EPSILON)` with `occluded`, and add up the free ones, each weighted by the
    /// integrand over the sample's `pdf`. Hint: do not assume which sampler you are given —
    /// the checks pass one of their own.
    fn ambient_occlusion(
        &self,
        position: Vec3,
        normal: Vec3,
        samples: u32,
        sampler: &dyn Fn(&mut Rng) -> HemisphereSample,
        occluded: &dyn Fn(&Ray) -> bool,
        rng: &mut Rng,
    ) -> Occlusion {
        todo!("Exercise 11.3: ambient_occlusion (docs/lab11.md, Exercise 11.3)")
    }

    /// **Exercise 11.4** — an RGBE pixel to linear RGB (docs/lab11.md, Exercise 11.4).
    ///
    /// Hint: the exponent byte is biased by 128 and the mantissas are 8-bit fractions; an
    /// exponent of 0 is black.
    fn rgbe_to_rgb(&self, rgbe: [u8; 4]) -> Vec3 {
        todo!("Exercise 11.4: rgbe_to_rgb (docs/lab11.md, Exercise 11.4)")
    }

    /// **Exercise 11.5** — a direction to angular-map coordinates (docs/lab11.md,
    /// Exercise 11.5).
    ///
    /// Hint: the distance from the centre grows linearly with the angle from −z; the
    /// direction's `(x, y)` says which way to go from the centre. Straight back (+z) is the rim.
    fn angular_map_uv(&self, direction: Vec3) -> Vec2 {
        todo!("Exercise 11.5: angular_map_uv (docs/lab11.md, Exercise 11.5)")
    }

    /// **Exercise 11.6** — angular-map coordinates to a direction (docs/lab11.md,
    /// Exercise 11.6).
    ///
    /// Hint: undo Exercise 11.5 step by step; `None` outside the disc.
    fn angular_map_direction(&self, uv: Vec2) -> Option<Vec3> {
        todo!("Exercise 11.6: angular_map_direction (docs/lab11.md, Exercise 11.6)")
    }

    /// **Exercise 11.7** — a direction to latitude–longitude coordinates (docs/lab11.md,
    /// Exercise 11.7).
    ///
    /// Hint: `v` is the polar angle from +y over π, `u` the azimuth about +y over 2π, shifted
    /// so that −z is the middle of the image.
    fn latlong_uv(&self, direction: Vec3) -> Vec2 {
        todo!("Exercise 11.7: latlong_uv (docs/lab11.md, Exercise 11.7)")
    }

    /// **Exercise 11.8** — latitude–longitude coordinates to a direction (docs/lab11.md,
    /// Exercise 11.8).
    fn latlong_direction(&self, uv: Vec2) -> Vec3 {
        todo!("Exercise 11.8: latlong_direction (docs/lab11.md, Exercise 11.8)")
    }

    /// **Exercise 11.9** — the ambient-occlusion shader (docs/lab11.md, Exercise 11.9).
    ///
    /// Hint: write the Lambertian reflection of the environment, take its radiance out of
    /// the integral as the bent normal's, and see what is left of the integral.
    fn shade_ambient_occlusion(
        &self,
        diffuse: Vec3,
        occlusion: &Occlusion,
        environment: Vec3,
    ) -> Vec3 {
        todo!("Exercise 11.9: shade_ambient_occlusion (docs/lab11.md, Exercise 11.9)")
    }
}
