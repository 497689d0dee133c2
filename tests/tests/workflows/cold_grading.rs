//! A grading's own failures are never a student's: `raylab grade` on a grading directory of its
//! own (its checks and graded program not built yet, as on a new machine) with a build time
//! limit far shorter than that build. What every submission shares is built before the first
//! submission, on nobody's clock, so the honest submission graded first keeps full marks; and a
//! build that never ends (a constant evaluated for ever) is stopped, tried again with twice the
//! time, and left "not graded" with its figures — never "does not compile".
//!
//! The tree is kept in `target/raylab-cold-grading-test/` to be looked at.

use std::fs;
use std::process::Command;
use std::time::Instant;

use grading::prerequisite;
use raylab_tests::workflow::{copy_tree, correct_code, read, target_dir, workflow_target_dir};

/// The build time limit, seconds: ample for one lab's crate, far too short for the checks and
/// the graded program of a grading that has not built them.
const BUILD_TIMEOUT: u64 = 15;

#[test]
fn a_cold_grading_charges_no_student_for_its_own_builds() {
    let test = "a_cold_grading_charges_no_student_for_its_own_builds";
    if !(prerequisite::program_or_skip(test, "bwrap", "apt-get install bubblewrap")
        && prerequisite::rust_target_or_skip(test, "wasm32-unknown-unknown"))
    {
        return;
    }
    let work = target_dir().join("raylab-cold-grading-test");
    let _ = fs::remove_dir_all(&work);
    fs::create_dir_all(&work).unwrap();
    let raylab = target_dir().join("debug/raylab");
    let handout = work.join("handout");
    let status = Command::new(&raylab)
        .args(["handout", "--allow-dirty", "--out"])
        .arg(&handout)
        .status()
        .unwrap();
    assert!(status.success(), "raylab handout failed");
    let endless = format!(
        "{}\n/// Evaluated while the crate compiles: a build that never ends.\n#[allow(long_running_const_eval)]\npub const SPIN: u64 = {{\n    let mut i = 1u64;\n    while i != 0 {{\n        i = i.wrapping_mul(3);\n    }}\n    i\n}};\n",
        read(&handout.join("labs/lab01/src/lib.rs"))
    );
    let subs = work.join("submissions");
    for (name, code) in [("a-honest", correct_code(1)), ("b-endless-build", endless)] {
        let dir = subs.join(name);
        copy_tree(&handout, &dir);
        fs::write(dir.join("labs/lab01/src/lib.rs"), code).unwrap();
    }
    // A grading directory of its own: its checks and graded program are built anew.
    let grades = work.join("grades");
    let started = Instant::now();
    let output = Command::new(&raylab)
        .arg("grade")
        .arg(subs.join("a-honest"))
        .arg(subs.join("b-endless-build"))
        .arg("--out")
        .arg(&grades)
        .args(["--lab", "1", "--timeout", "30"])
        .args(["--build-timeout", &BUILD_TIMEOUT.to_string()])
        .arg("--target-dir")
        .arg(workflow_target_dir())
        .output()
        .unwrap();
    let printed = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    println!(
        "raylab grade took {:.0} s:\n{printed}",
        started.elapsed().as_secs_f64()
    );
    assert!(output.status.success(), "{printed}");
    // The shared build came first, and took longer than a submission's build may.
    let shared = printed
        .lines()
        .find_map(|l| l.strip_prefix("built what every submission shares in "))
        .and_then(|rest| rest.split(' ').next())
        .and_then(|s| s.parse::<f64>().ok())
        .expect("grade says how long the shared build took");
    println!("the shared build took {shared} s against a build limit of {BUILD_TIMEOUT} s");

    let results = |name: &str| -> serde_json::Value {
        serde_json::from_str(&read(&grades.join(name).join("results.json"))).unwrap()
    };
    let honest = results("a-honest");
    // The exercises' tests (a number each); the written answers' has none and no status.
    let exercises: Vec<_> = honest["tests"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|t| t["number"].is_string())
        .collect();
    assert!(
        honest["score"] == 10.0
            && exercises.len() == 6
            && exercises.iter().all(|t| t["status"] == "passed"),
        "the honest submission graded first lost points to the grading's own build: {honest:#}"
    );
    let endless = results("b-endless-build");
    assert_eq!(endless["score"], 0.0, "{endless:#}");
    let exercises = endless["tests"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|t| t["number"].is_string());
    assert_eq!(exercises.clone().count(), 6, "{endless:#}");
    for t in exercises {
        let why = t["output"].as_str().unwrap_or_default();
        assert!(
            why.contains("was not graded")
                && why.contains(&format!("did not finish within {} s", 2 * BUILD_TIMEOUT))
                && why.contains(&format!("first attempt stopped at {BUILD_TIMEOUT} s"))
                && why.contains("not a compile error")
                && !why.contains("does not compile"),
            "a build stopped at the time limit was not reported as the grader's: {why}"
        );
    }
    let report = read(&grades.join("b-endless-build/report.md"));
    assert!(report.contains("not graded"), "{report}");
}
