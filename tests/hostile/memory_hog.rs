//! Hostile submission `memory_hog`: the first call in a test process allocates 6 GiB in 64 MiB
//! chunks, writes every 4096th byte so that each page is really in memory, and keeps it all
//! alive; then (like every later call) it is the handout's stub. On a grading machine without a
//! limit it pushes everything else out of memory.
//!
//! The grader must bound a test process's memory (0 of 14 points): the process dies or fails to
//! allocate long before it has 6 GiB, and each exercise's reason says it ran "out of memory" or
//! "crashed" — never "timed out", which would mean the clock and not the limit stopped it.

use std::sync::Mutex;

use contracts::glam::Vec3;
use contracts::lab02::{Intersection, LightSample, Shading, SurfaceHit, TriangleHit};
use contracts::math::Ray;
use contracts::scene::{DirectionalLight, Plane, PointLight, Sphere};

const CHUNK: usize = 64 << 20;
const TOTAL: usize = 6 << 30;

/// The memory taken, kept until the process ends.
static HOARD: Mutex<Vec<Vec<u8>>> = Mutex::new(Vec::new());

/// Takes 6 GiB once per process, then fails like a stub.
fn hog(exercise: &str) -> ! {
    if let Ok(mut hoard) = HOARD.lock() {
        while hoard.len() * CHUNK < TOTAL {
            let mut chunk = vec![0u8; CHUNK];
            for byte in chunk.iter_mut().step_by(4096) {
                *byte = 1;
            }
            hoard.push(chunk);
        }
    }
    todo!("{exercise}")
}

/// Takes all the memory instead of answering.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Intersection for Student {
    fn intersect_plane(&self, _ray: &Ray, _plane: &Plane) -> Option<SurfaceHit> {
        hog("Exercise 2.1: intersect_plane")
    }

    fn intersect_triangle(
        &self,
        _ray: &Ray,
        _v0: Vec3,
        _v1: Vec3,
        _v2: Vec3,
    ) -> Option<TriangleHit> {
        hog("Exercise 2.2: intersect_triangle")
    }

    fn intersect_sphere(&self, _ray: &Ray, _sphere: &Sphere) -> Option<SurfaceHit> {
        hog("Exercise 2.3: intersect_sphere")
    }
}

impl Shading for Student {
    fn sample_point_light(&self, _light: &PointLight, _position: Vec3) -> LightSample {
        hog("Exercise 2.4: sample_point_light")
    }

    fn sample_directional_light(&self, _light: &DirectionalLight, _position: Vec3) -> LightSample {
        hog("Exercise 2.5: sample_directional_light")
    }

    fn shade_lambertian(&self, _rho_d: Vec3, _normal: Vec3, _lights: &[LightSample]) -> Vec3 {
        hog("Exercise 2.6: shade_lambertian")
    }
}
