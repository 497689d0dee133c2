//! Hostile submission `process_flood`: the first call in a test process starts up to 2000
//! `sleep 61.25` processes (until starting one fails) and keeps their handles; then (like every
//! later call) it is the handout's stub. The sleepers outlive the test process, and a grader
//! without a limit on processes lets each exercise add 2000 more.
//!
//! The grader must bound the number of processes a test may start and end every process of an
//! exercise when the exercise ends (0 of 14 points): once `raylab grade` has returned, no
//! `sleep 61.25` is left running.

use std::process::{Child, Command, Stdio};
use std::sync::{Mutex, Once};

use contracts::glam::Vec3;
use contracts::lab02::{Intersection, LightSample, Shading, SurfaceHit, TriangleHit};
use contracts::math::Ray;
use contracts::scene::{DirectionalLight, Plane, PointLight, Sphere};

/// The processes started, kept until the test process ends.
static SLEEPERS: Mutex<Vec<Child>> = Mutex::new(Vec::new());

/// Starts the sleepers once per process, then fails like a stub.
fn flood(exercise: &str) -> ! {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let Ok(mut sleepers) = SLEEPERS.lock() else {
            return;
        };
        while sleepers.len() < 2000 {
            match Command::new("sleep")
                .arg("61.25")
                .stdin(Stdio::null())
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
            {
                Ok(child) => sleepers.push(child),
                Err(_) => break,
            }
        }
    });
    todo!("{exercise}")
}

/// Starts processes instead of answering.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Intersection for Student {
    fn intersect_plane(&self, _ray: &Ray, _plane: &Plane) -> Option<SurfaceHit> {
        flood("Exercise 2.1: intersect_plane")
    }

    fn intersect_triangle(
        &self,
        _ray: &Ray,
        _v0: Vec3,
        _v1: Vec3,
        _v2: Vec3,
    ) -> Option<TriangleHit> {
        flood("Exercise 2.2: intersect_triangle")
    }

    fn intersect_sphere(&self, _ray: &Ray, _sphere: &Sphere) -> Option<SurfaceHit> {
        flood("Exercise 2.3: intersect_sphere")
    }
}

impl Shading for Student {
    fn sample_point_light(&self, _light: &PointLight, _position: Vec3) -> LightSample {
        flood("Exercise 2.4: sample_point_light")
    }

    fn sample_directional_light(&self, _light: &DirectionalLight, _position: Vec3) -> LightSample {
        flood("Exercise 2.5: sample_directional_light")
    }

    fn shade_lambertian(&self, _rho_d: Vec3, _normal: Vec3, _lights: &[LightSample]) -> Vec3 {
        flood("Exercise 2.6: shade_lambertian")
    }
}
