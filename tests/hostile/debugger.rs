//! Hostile submission `debugger`: the first call in a test process starts a debugger (`gdb`,
//! where the machine has one) attached to the test process itself, to read the harness's memory
//! — where the verdict's secret is — and prints what it got; then it is the handout's stub.
//!
//! The grader must keep other processes from tracing the harness (0 of 14 points): with the
//! harness non-dumpable and the sandbox's capabilities dropped, the attach fails ("ptrace:
//! Operation not permitted") and `GDB-ATTACHED` never appears in the report.

use std::process::{Command, Stdio};
use std::sync::Once;

use contracts::glam::Vec3;
use contracts::lab02::{Intersection, LightSample, Shading, SurfaceHit, TriangleHit};
use contracts::math::Ray;
use contracts::scene::{DirectionalLight, Plane, PointLight, Sphere};

/// Attaches `gdb` to this process once, prints the outcome, then fails like a stub.
fn attach(exercise: &str) -> ! {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let pid = std::process::id().to_string();
        let output = Command::new("gdb")
            .args(["-batch", "-p", &pid, "-ex", "info registers rip", "-ex", "x/64xg $sp"])
            .stdin(Stdio::null())
            .output();
        match output {
            Ok(o) => {
                let text = format!(
                    "{}{}",
                    String::from_utf8_lossy(&o.stdout),
                    String::from_utf8_lossy(&o.stderr)
                );
                if o.status.success() && !text.contains("ptrace:") && text.contains("rip") {
                    println!("GDB-ATTACHED\n{text}");
                } else {
                    println!("the debugger could not attach:\n{text}");
                }
            }
            Err(e) => println!("no debugger: {e}"),
        }
    });
    todo!("{exercise}")
}

/// Attaches a debugger to itself instead of answering.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Intersection for Student {
    fn intersect_plane(&self, _ray: &Ray, _plane: &Plane) -> Option<SurfaceHit> {
        attach("Exercise 2.1: intersect_plane")
    }

    fn intersect_triangle(
        &self,
        _ray: &Ray,
        _v0: Vec3,
        _v1: Vec3,
        _v2: Vec3,
    ) -> Option<TriangleHit> {
        attach("Exercise 2.2: intersect_triangle")
    }

    fn intersect_sphere(&self, _ray: &Ray, _sphere: &Sphere) -> Option<SurfaceHit> {
        attach("Exercise 2.3: intersect_sphere")
    }
}

impl Shading for Student {
    fn sample_point_light(&self, _light: &PointLight, _position: Vec3) -> LightSample {
        attach("Exercise 2.4: sample_point_light")
    }

    fn sample_directional_light(&self, _light: &DirectionalLight, _position: Vec3) -> LightSample {
        attach("Exercise 2.5: sample_directional_light")
    }

    fn shade_lambertian(&self, _rho_d: Vec3, _normal: Vec3, _lights: &[LightSample]) -> Vec3 {
        attach("Exercise 2.6: shade_lambertian")
    }
}
