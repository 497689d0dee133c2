#!/**/[allow(unused)] const READ: &[u8] = @READ@;
// Hostile submission `compile_time_read_*`: a first line that the compiler reads as an inner
// attribute and a constant (a shebang's `#!` followed by a comment, then `[`), which a scan
// that skips any `#!` line would not read at all. The constant is what one compile-time read
// gives (the test puts in `include_bytes!` of the answer key, of `/proc/self/…`, of `/etc`, of
// a file only root may read, of another submission, of the target directory's graded program
// and modules, of `/dev/zero`, or `env!` of the build's variables), and every function panics
// with it, so that what the build could read would land in the feedback.
//
// The grader's build sees the submission's sources, the prebuilt crates and the compiler,
// nothing else: each read fails to compile (0 of 14, "does not compile", the compiler saying
// it could not read the file), even with the scan switched off; the variables the build has
// name only its own jail (`/build/labs/lab02`, version `0.1.0`). No report may hold anything
// read.

use contracts::glam::Vec3;
use contracts::lab02::{Intersection, LightSample, Shading, SurfaceHit, TriangleHit};
use contracts::math::Ray;
use contracts::scene::{DirectionalLight, Plane, PointLight, Sphere};

/// Fails with what was read as the message.
fn leak() -> ! {
    panic!("READ-BEGIN {} READ-END", String::from_utf8_lossy(READ))
}

/// Leaks what the build read instead of answering.
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
