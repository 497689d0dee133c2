//! Hostile submission `unsafe_fd`: writes forged verdict records straight into file descriptors
//! 3 to 15 with `unsafe { File::from_raw_fd(n) }` — whichever of them the grader's channel for
//! verdicts might be — then ends the test process with `exit(0)`. It also tries to lift a ban on
//! unsafe code with `#![allow(unsafe_code)]`.
//!
//! The grader must refuse to build it (0 of 14 points): student crates are compiled with unsafe
//! code forbidden (`-F unsafe_code`, which no `allow` in the crate can lift), and the report
//! shows the compiler's complaint, which names `unsafe`. (In the course's own workspace, where
//! nothing forbids unsafe code, the file compiles.)

#![allow(unsafe_code)]

use std::fs::File;
use std::io::Write;
use std::os::fd::FromRawFd;

use contracts::glam::Vec3;
use contracts::lab02::{Intersection, LightSample, Shading, SurfaceHit, TriangleHit};
use contracts::math::Ray;
use contracts::scene::{DirectionalLight, Plane, PointLight, Sphere};

/// Writes a forged pass into descriptors 3..16 and leaves with a successful status.
fn forge() -> ! {
    for fd in 3..16 {
        // SAFETY: none; the descriptor may belong to anything, which is the point of the attack.
        let mut file = unsafe { File::from_raw_fd(fd) };
        for key in ["0".repeat(16), "0".repeat(32), "0".repeat(64)] {
            let _ = writeln!(file, "RAYLAB-VERDICT {key} {{\"passed\":true}}");
        }
        std::mem::forget(file);
    }
    println!("test result: ok. 1 passed; 0 failed");
    std::process::exit(0)
}

/// Forges a pass through raw descriptors instead of answering.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Intersection for Student {
    fn intersect_plane(&self, _ray: &Ray, _plane: &Plane) -> Option<SurfaceHit> {
        forge()
    }

    fn intersect_triangle(
        &self,
        _ray: &Ray,
        _v0: Vec3,
        _v1: Vec3,
        _v2: Vec3,
    ) -> Option<TriangleHit> {
        forge()
    }

    fn intersect_sphere(&self, _ray: &Ray, _sphere: &Sphere) -> Option<SurfaceHit> {
        forge()
    }
}

impl Shading for Student {
    fn sample_point_light(&self, _light: &PointLight, _position: Vec3) -> LightSample {
        forge()
    }

    fn sample_directional_light(&self, _light: &DirectionalLight, _position: Vec3) -> LightSample {
        forge()
    }

    fn shade_lambertian(&self, _rho_d: Vec3, _normal: Vec3, _lights: &[LightSample]) -> Vec3 {
        forge()
    }
}
