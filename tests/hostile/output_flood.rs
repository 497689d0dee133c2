//! Hostile submission `output_flood`: correct code (the answer key's lab 02), except that the
//! first call of `intersect_plane` in a test process prints 500 MB (in 1 MiB writes) and still
//! returns the right answer, and the first call of `intersect_triangle` prints 20 MB and then
//! panics. A grader that keeps all of a test's output fills its disk and memory and writes
//! reports of hundreds of megabytes.
//!
//! The grader must cap what it keeps of a test's output without failing a test for its output
//! alone: Exercises 2.1 and 2.3–2.6 pass, 2.2 fails (11 of 14 points, this submission's honest
//! due); its `report.md`, `report.html` and `results.json`, and the class's `junit.xml`, stay
//! under 1 MB each, and the report says where the output was cut ("output cut").

use std::f32::consts::PI;
use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

use contracts::glam::Vec3;
use contracts::lab02::{Intersection, LightSample, Shading, SurfaceHit, TriangleHit};
use contracts::math::Ray;
use contracts::scene::{DirectionalLight, Plane, PointLight, Sphere};

/// Writes `megabytes` MiB of text to stdout, in 1 MiB writes, the first time `done` is set.
fn flood(done: &AtomicBool, megabytes: usize) {
    if done.swap(true, Ordering::SeqCst) {
        return;
    }
    let mut line = "flood ".repeat((1 << 20) / 6 + 1);
    line.truncate((1 << 20) - 1);
    line.push('\n');
    let mut out = std::io::stdout().lock();
    for _ in 0..megabytes {
        let _ = out.write_all(line.as_bytes());
    }
    let _ = out.flush();
}

static PLANE_FLOOD: AtomicBool = AtomicBool::new(false);
static TRIANGLE_FLOOD: AtomicBool = AtomicBool::new(false);

/// The reference intersections, lights and Lambertian shader, and the floods.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Intersection for Student {
    fn intersect_plane(&self, ray: &Ray, plane: &Plane) -> Option<SurfaceHit> {
        flood(&PLANE_FLOOD, 500);
        let denom = ray.direction.dot(plane.normal);
        if denom == 0.0 {
            return None;
        }
        let t = -(ray.origin.dot(plane.normal) + plane.d) / denom;
        ray.accepts(t).then_some(SurfaceHit {
            distance: t,
            normal: plane.normal,
        })
    }

    /// Möller–Trumbore (1997), as derived in docs/lab02.md with Cramer's rule.
    fn intersect_triangle(&self, ray: &Ray, v0: Vec3, v1: Vec3, v2: Vec3) -> Option<TriangleHit> {
        if !TRIANGLE_FLOOD.load(Ordering::SeqCst) {
            flood(&TRIANGLE_FLOOD, 20);
            panic!("intersect_triangle gives up after 20 MB of output");
        }
        let e1 = v1 - v0;
        let e2 = v2 - v0;
        let p = ray.direction.cross(e2);
        let det = e1.dot(p);
        if det == 0.0 {
            return None;
        }
        let inv_det = 1.0 / det;
        let s = ray.origin - v0;
        let beta = s.dot(p) * inv_det;
        if !(0.0..=1.0).contains(&beta) {
            return None;
        }
        let q = s.cross(e1);
        let gamma = ray.direction.dot(q) * inv_det;
        if gamma < 0.0 || beta + gamma > 1.0 {
            return None;
        }
        let t = e2.dot(q) * inv_det;
        ray.accepts(t).then(|| TriangleHit {
            distance: t,
            beta,
            gamma,
            normal: e1.cross(e2).normalize(),
        })
    }

    fn intersect_sphere(&self, ray: &Ray, sphere: &Sphere) -> Option<SurfaceHit> {
        let oc = ray.origin - sphere.center;
        let a = ray.direction.length_squared();
        let half_b = oc.dot(ray.direction);
        let c = oc.length_squared() - sphere.radius * sphere.radius;
        let disc = half_b * half_b - a * c;
        if disc < 0.0 {
            return None;
        }
        let root = disc.sqrt();
        let near = (-half_b - root) / a;
        let far = (-half_b + root) / a;
        let t = if ray.accepts(near) {
            near
        } else if ray.accepts(far) {
            far
        } else {
            return None;
        };
        Some(SurfaceHit {
            distance: t,
            normal: (ray.at(t) - sphere.center) / sphere.radius,
        })
    }
}

impl Shading for Student {
    fn sample_point_light(&self, light: &PointLight, position: Vec3) -> LightSample {
        let to_light = light.position - position;
        let distance = to_light.length();
        LightSample {
            direction: to_light / distance,
            distance,
            radiance: light.intensity / (distance * distance),
        }
    }

    fn sample_directional_light(&self, light: &DirectionalLight, _position: Vec3) -> LightSample {
        LightSample {
            direction: -light.direction.normalize(),
            distance: f32::INFINITY,
            radiance: light.emission,
        }
    }

    fn shade_lambertian(&self, rho_d: Vec3, normal: Vec3, lights: &[LightSample]) -> Vec3 {
        let brdf = rho_d / PI;
        lights
            .iter()
            .map(|l| brdf * l.radiance * normal.dot(l.direction).max(0.0))
            .sum()
    }
}
