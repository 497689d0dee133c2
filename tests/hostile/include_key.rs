//! Hostile submission `include_key`: pulls answer keys into the crate at compile time with
//! `include_str!` — lab 07's through the build's working directory
//! (`concat!(env!("PWD"), "/reference/src/lab07.rs")`), lab 03's and lab 02's through the
//! instructor's repository by its absolute path (the test puts it in for `@REPO@`) — and panics
//! with their text in every function, so that, were they included, they would land in the
//! feedback.
//!
//! The grader must not compile it (0 of 14 points): `include_str!` (like `include!`,
//! `include_bytes!` and `#[path]`) in a student crate is flagged before any build, and the
//! report says so ("flagged") and quotes the offending `include_str` line. Not a line of an
//! unreleased key may reach any report.

use contracts::glam::Vec3;
use contracts::lab02::{Intersection, LightSample, Shading, SurfaceHit, TriangleHit};
use contracts::math::Ray;
use contracts::scene::{DirectionalLight, Plane, PointLight, Sphere};

const KEY07: &str = include_str!(concat!(env!("PWD"), "/reference/src/lab07.rs"));
const KEY03: &str = include_str!("@REPO@/reference/src/lab03.rs");
const KEY02: &str = include_str!("@REPO@/reference/src/lab02.rs");

/// Fails with the keys' text as the message.
fn leak() -> ! {
    panic!("{KEY02}\n{KEY03}\n{KEY07}")
}

/// Leaks the answer keys instead of answering.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Intersection for Student {
    fn intersect_plane(&self, _ray: &Ray, _plane: &Plane) -> Option<SurfaceHit> {
        leak()
    }

    fn intersect_triangle(
        &self,
        _ray: &Ray,
        _v0: Vec3,
        _v1: Vec3,
        _v2: Vec3,
    ) -> Option<TriangleHit> {
        leak()
    }

    fn intersect_sphere(&self, _ray: &Ray, _sphere: &Sphere) -> Option<SurfaceHit> {
        leak()
    }
}

impl Shading for Student {
    fn sample_point_light(&self, _light: &PointLight, _position: Vec3) -> LightSample {
        leak()
    }

    fn sample_directional_light(&self, _light: &DirectionalLight, _position: Vec3) -> LightSample {
        leak()
    }

    fn shade_lambertian(&self, _rho_d: Vec3, _normal: Vec3, _lights: &[LightSample]) -> Vec3 {
        leak()
    }
}
