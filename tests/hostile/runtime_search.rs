//! Hostile submission `runtime_search`: looks for the answer key while the checks run. It walks
//! up from the directory the crate was built in (`env!("CARGO_MANIFEST_DIR")`) looking for
//! `reference/src/lab02.rs`, and searches the whole file system from `/` (at most 6 levels deep,
//! at most 200 000 entries and 5 s, skipping `/proc`, `/sys` and `/dev`, not following symbolic
//! links) for that file or any `.rs` file containing `impl Intersection for Lab02`. Whatever it
//! finds it prints and panics with, so that it lands in the feedback; finding nothing, it is the
//! handout's stubs.
//!
//! The grader must leave nothing to find (0 of 14 points): the test process sees no file of the
//! instructor's repository, so it fails like the stubs; not a line of the key reaches any
//! report.

use std::collections::VecDeque;
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use contracts::glam::Vec3;
use contracts::lab02::{Intersection, LightSample, Shading, SurfaceHit, TriangleHit};
use contracts::math::Ray;
use contracts::scene::{DirectionalLight, Plane, PointLight, Sphere};

const KEY_PATH: &str = "reference/src/lab02.rs";
const KEY_TEXT: &str = "impl Intersection for Lab02";

/// `path` and its text if it is the key.
fn key_at(path: &Path) -> Option<(PathBuf, String)> {
    let text = fs::read_to_string(path).ok()?;
    (path.ends_with(KEY_PATH) || text.contains(KEY_TEXT)).then(|| (path.to_path_buf(), text))
}

/// Every copy of the key found, at most three.
fn search() -> Vec<(PathBuf, String)> {
    let mut found = Vec::new();
    let mut dir = Some(Path::new(env!("CARGO_MANIFEST_DIR")));
    while let Some(d) = dir {
        if let Some(hit) = key_at(&d.join(KEY_PATH)) {
            found.push(hit);
        }
        dir = d.parent();
    }
    let start = Instant::now();
    let mut entries = 0usize;
    let mut queue = VecDeque::from([(PathBuf::from("/"), 0usize)]);
    while let Some((dir, depth)) = queue.pop_front() {
        if found.len() >= 3 || entries >= 200_000 || start.elapsed() > Duration::from_secs(5) {
            break;
        }
        let Ok(list) = fs::read_dir(&dir) else {
            continue;
        };
        for entry in list.flatten() {
            entries += 1;
            let path = entry.path();
            if ["/proc", "/sys", "/dev"]
                .iter()
                .any(|p| path == Path::new(p))
            {
                continue;
            }
            let Ok(kind) = entry.file_type() else {
                continue;
            };
            if kind.is_dir() && depth < 6 {
                queue.push_back((path, depth + 1));
            } else if kind.is_file()
                && path.extension().is_some_and(|e| e == "rs")
                && entry.metadata().is_ok_and(|m| m.len() < 512 * 1024)
                && !found.iter().any(|(p, _)| *p == path)
            {
                if let Some(hit) = key_at(&path) {
                    found.push(hit);
                }
            }
        }
    }
    found
}

/// Panics with whatever key was found; otherwise fails like a stub.
fn leak_or(exercise: &str) -> ! {
    static FOUND: OnceLock<Vec<(PathBuf, String)>> = OnceLock::new();
    let found = FOUND.get_or_init(search);
    if found.is_empty() {
        todo!("{exercise}")
    }
    let mut text = String::new();
    for (path, key) in found {
        text.push_str(&format!("found the key at {}:\n{key}\n", path.display()));
    }
    println!("{text}");
    eprintln!("{text}");
    panic!("{text}")
}

/// Searches for the key instead of answering.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Intersection for Student {
    fn intersect_plane(&self, _ray: &Ray, _plane: &Plane) -> Option<SurfaceHit> {
        leak_or("Exercise 2.1: intersect_plane")
    }

    fn intersect_triangle(
        &self,
        _ray: &Ray,
        _v0: Vec3,
        _v1: Vec3,
        _v2: Vec3,
    ) -> Option<TriangleHit> {
        leak_or("Exercise 2.2: intersect_triangle")
    }

    fn intersect_sphere(&self, _ray: &Ray, _sphere: &Sphere) -> Option<SurfaceHit> {
        leak_or("Exercise 2.3: intersect_sphere")
    }
}

impl Shading for Student {
    fn sample_point_light(&self, _light: &PointLight, _position: Vec3) -> LightSample {
        leak_or("Exercise 2.4: sample_point_light")
    }

    fn sample_directional_light(&self, _light: &DirectionalLight, _position: Vec3) -> LightSample {
        leak_or("Exercise 2.5: sample_directional_light")
    }

    fn shade_lambertian(&self, _rho_d: Vec3, _normal: Vec3, _lights: &[LightSample]) -> Vec3 {
        leak_or("Exercise 2.6: shade_lambertian")
    }
}
