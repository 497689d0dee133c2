//! The instructor's workflow end to end: `raylab handout` writes a student tree without the
//! solutions, in which a lab's checks fail on the stubs and pass on correct code; `raylab grade`
//! grades four submissions — complete; partial, with a panic, an infinite loop and a NaN; lab 02
//! done with lab 01 not started; and one that edited its tests — into reports, gradebooks and
//! Gradescope results.
//!
//! The trees are kept in `target/raylab-handout-test/` to be looked at.

use std::fs;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

use grading::prerequisite;
use raylab_tests::workflow::{
    cargo_in as cargo, check_in_browser, copy_tree, correct_code, output_text, read, root,
    target_dir, workflow_target_dir,
};

/// `raylab ARGS`, built as the workspace's test build builds it, so that nothing is compiled
/// again.
fn raylab(args: &[&str]) -> (bool, String) {
    let mut all = vec!["run", "--quiet", "-p", "raylab", "--"];
    all.extend_from_slice(args);
    cargo(&root(), &target_dir(), &all)
}

/// `--timeout` of the gradings, in seconds: room enough for an honest exercise in WebAssembly
/// on a machine busy with the other workflow tests (the infinite loop is stopped by its budget
/// of work before).
const TIMEOUT: &str = "20";

fn write_lab(tree: &Path, lab: u32, code: &str) {
    fs::write(tree.join(format!("labs/lab{lab:02}/src/lib.rs")), code).unwrap();
}

/// Inserts `line` at the start of the body of `signature` in `code`.
fn inject(code: &str, signature: &str, line: &str) -> String {
    assert!(code.contains(signature), "no `{signature}` in the code");
    code.replace(signature, &format!("{signature}\n        {line}"))
}

fn csv_row<'a>(csv: &'a str, student: &str) -> Vec<&'a str> {
    csv.lines()
        .find(|l| l.starts_with(&format!("{student},")))
        .unwrap_or_else(|| panic!("no row for {student} in\n{csv}"))
        .split(',')
        .collect()
}

#[test]
fn handout_then_grade_four_submissions() {
    let test = "handout_then_grade_four_submissions";
    if !(prerequisite::program_or_skip(test, "bwrap", "apt-get install bubblewrap")
        && prerequisite::rust_target_or_skip(test, "wasm32-unknown-unknown"))
    {
        return;
    }
    let browser = prerequisite::program_or_skip(
        "the browser check of the grading pages",
        "chromium",
        "apt-get install chromium",
    );
    // The build directories stay between runs; `raylab grade` renews everything else in its
    // `--out`.
    let work = target_dir().join("raylab-handout-test");
    let started = Instant::now();
    let phase = |what: &str| eprintln!("{:7.1} s  {what}", started.elapsed().as_secs_f64());
    let handout = work.join("handout");
    let subs = work.join("submissions");
    for dir in [&handout, &subs] {
        let _ = fs::remove_dir_all(dir);
    }

    // The handout: no solution code, no corpus, no hidden test. (`--allow-dirty`: what is
    // tested is the working tree, committed or not.)
    let (ok, out) = raylab(&[
        "handout",
        "--allow-dirty",
        "--out",
        handout.to_str().unwrap(),
    ]);
    assert!(ok, "{out}");
    // Student-facing docs only: how grading works is the instructors'.
    for doc in ["docs/instructors.md", "docs/performance.md"] {
        assert!(!handout.join(doc).exists(), "the handout holds {doc}");
    }
    assert!(handout.join("docs/lab01.md").is_file());
    phase("handout written");
    // The handout's target directory (also the grading's) starts with the dependencies this
    // run has compiled: what is checked is the workflow, not a second build of crates.io.
    let handout_target = workflow_target_dir();
    // The stubs written again: the new handout has the repository's file dates, older than
    // the correct code an earlier run built in this target directory.
    let stubs = read(&handout.join("labs/lab01/src/lib.rs"));
    write_lab(&handout, 1, &stubs);
    phase("target directory seeded");
    assert!(
        !handout.join("tests").exists(),
        "the mutant corpus holds solutions"
    );
    assert!(!handout.join(".ci").exists());
    // The command line's tests are the instructors': their fixtures hold solutions of lab 2.
    assert!(!handout.join("labs/raylab/tests").exists());
    for lab in [1, 2, 3, 4, 7] {
        assert!(
            !handout
                .join(format!("reference/src/lab{lab:02}.rs"))
                .exists()
        );
    }
    let (ok, out) = cargo(
        &handout,
        &handout_target,
        &[
            "test", "-q", "-p", "lab01", "--test", "checks", "--", "--list", "--format", "terse",
        ],
    );
    assert!(
        ok && out.contains("exercise_1_5_") && !out.contains("exercise_1_6_"),
        "{out}"
    );
    phase("handout's lab01 checks built");

    // A syntax error in lab 05 stops neither lab 01's tests nor `status`, which names lab 05
    // with the compiler's first error and shows every other lab's table.
    let lab05 = handout.join("labs/lab05/src/lib.rs");
    let stubs = read(&lab05);
    fs::write(&lab05, format!("{stubs}\nfn broken( {{\n")).unwrap();
    let (ok, out) = cargo(
        &handout,
        &handout_target,
        &[
            "test", "-q", "-p", "lab01", "--test", "checks", "--", "--list",
        ],
    );
    assert!(ok && out.contains("exercise_1_1_"), "{out}");
    let (ok, out) = cargo(
        &handout,
        &handout_target,
        &["run", "-q", "-p", "raylab", "--", "status"],
    );
    fs::write(&lab05, &stubs).unwrap();
    assert!(ok, "{out}");
    assert!(
        out.contains("lab05  not checked: its code does not compile")
            && out.contains("unclosed delimiter")
            && out.contains("labs/lab05/src/lib.rs"),
        "{out}"
    );
    for lab in [1, 2, 3, 4, 6, 7, 8, 9, 10, 11] {
        assert!(
            out.contains(&format!("\nlab{lab:02}  0/"))
                || out.starts_with(&format!("lab{lab:02}  0/")),
            "lab {lab}:\n{out}"
        );
    }
    phase("a broken lab05 stops only its own row of status");
    let (ok, out) = raylab(&[
        "handout",
        "--allow-dirty",
        "--out",
        handout.to_str().unwrap(),
    ]);
    assert!(
        !ok && out.contains("expected a directory that does not exist yet"),
        "{out}"
    );

    // Three submissions.
    let complete = subs.join("complete");
    copy_tree(&handout, &complete);
    for lab in [1, 2, 3, 4, 7] {
        write_lab(&complete, lab, &correct_code(lab));
    }
    let partial = subs.join("partial");
    copy_tree(&handout, &partial);
    // A wrong focal length: Exercise 1.4's property check fails; 1.6's image of the whole
    // camera is judged with the key's `ray_direction` and passes (one mistake, one exercise).
    let lab01 = inject(
        &correct_code(1),
        "fn ray_direction(&self, basis: &CameraBasis, focal_distance: f32, ip: Vec2) -> Vec3 {",
        "let focal_distance = focal_distance * 1.25;",
    );
    write_lab(&partial, 1, &lab01);
    let lab02 = inject(
        &correct_code(2),
        "fn intersect_sphere(&self, ray: &Ray, sphere: &Sphere) -> Option<SurfaceHit> {",
        "let roots: Vec<f32> = Vec::new();\n        let _first = roots[(ray.origin.x.abs() as usize).min(2)];",
    );
    let lab02 = inject(
        &lab02,
        "fn intersect_plane(&self, ray: &Ray, plane: &Plane) -> Option<SurfaceHit> {",
        "let mut step = 0.0f32;\n        while step < 1.0 { step *= 2.0; }",
    );
    // Shading tuned to one material of the default scene: every property of 2.6 holds on
    // random albedos, and only its image, written into the report, shows the dim ground.
    let lab02 = inject(
        &lab02,
        "fn shade_lambertian(&self, rho_d: Vec3, normal: Vec3, lights: &[LightSample]) -> Vec3 {",
        "let rho_d = if rho_d == Vec3::splat(0.7) { 0.5 * rho_d } else { rho_d };",
    );
    write_lab(&partial, 2, &lab02);
    let lab03 = inject(
        &correct_code(3),
        "fn sample_triangle(&self, [v0, v1, v2]: [Vec3; 3], u: Vec2) -> Vec3 {",
        "if u.x >= 0.0 { return v0 * (u.x - 1.0).sqrt(); }",
    );
    write_lab(&partial, 3, &lab03);
    // Lab 01 not started, lab 02 done: every check of lab 02 has the answer key's camera.
    let lab02_only = subs.join("lab02-only");
    copy_tree(&handout, &lab02_only);
    write_lab(&lab02_only, 2, &correct_code(2));
    let edited = subs.join("edited");
    copy_tree(&handout, &edited);
    let checks = edited.join("labs/lab01/tests/checks.rs");
    let text = read(&checks).replace(
        "grading::lab_program!(lab01, lab01_checks, reference);",
        "fn main() {}",
    );
    assert_ne!(text, read(&checks), "the edit changes the lab's program");
    fs::write(&checks, text).unwrap();
    fs::write(edited.join("labs/lab01/golden/extra.json"), "[]").unwrap();

    // In the handout (built in a target directory of its own: cargo would take a tree of the
    // same layout and version for the repository's; the grading tree below has a version of
    // its own and shares this one): stubs fail, correct code passes.
    let (ok, out) = cargo(&handout, &handout_target, &["test", "-p", "lab01"]);
    assert!(!ok && out.contains("is not implemented yet"), "{out}");
    write_lab(&handout, 1, &correct_code(1));
    let (ok, out) = cargo(&handout, &handout_target, &["test", "-p", "lab01"]);
    assert!(ok && out.contains("5 passed"), "{out}");
    write_lab(&handout, 1, &stubs);
    phase("handout's lab01 tested, stubs and correct code");

    // Grade labs 1–3 (the partial submission's infinite loop is in lab 3).
    let grades = work.join("grades");
    let (ok, out) = raylab(&[
        "grade",
        complete.to_str().unwrap(),
        partial.to_str().unwrap(),
        lab02_only.to_str().unwrap(),
        edited.to_str().unwrap(),
        "--out",
        grades.to_str().unwrap(),
        "--lab",
        "1",
        "--lab",
        "2",
        "--lab",
        "3",
        "--timeout",
        TIMEOUT,
        "--target-dir",
        handout_target.to_str().unwrap(),
    ]);
    assert!(ok, "{out}");
    phase("four submissions graded");
    eprintln!(
        "{}",
        out.lines().rev().take(3).collect::<Vec<_>>().join("\n")
    );

    let csv = read(&grades.join("gradebook.csv"));
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let column = |id: &str| header.iter().position(|h| *h == id).unwrap();
    let max = |row: &[&str]| row[column("max_score")].parse::<u32>().unwrap();
    let total = |row: &[&str]| row[column("total")].parse::<u32>().unwrap();

    let row = csv_row(&csv, "complete");
    assert_eq!(total(&row), max(&row), "complete: {csv}");
    assert_eq!(row[column("changed_files")], "0");
    assert!(
        header.contains(&"1.6"),
        "hidden exercises are graded: {csv}"
    );

    let row = csv_row(&csv, "partial");
    // Each exercise is checked with the answer key everywhere else: the wrong focal length
    // costs Exercise 1.4 alone (1.6, the whole camera, is judged with the key's 1.4) and
    // nothing in labs 2 and 3, the NaN triangle sample 3.3 alone, the panic 2.3, the infinite
    // loop 2.1 and the tuned shading 2.6 alone. (1.6 is worth no points of its own: it passes,
    // below.)
    for id in [
        "1.1", "1.2", "1.3", "1.5", "2.2", "2.4", "2.5", "3.1", "3.2", "3.4",
    ] {
        assert_ne!(row[column(id)], "0", "partial, Exercise {id}: {csv}");
    }
    for id in ["1.4", "2.1", "2.3", "2.6", "3.3"] {
        assert_eq!(row[column(id)], "0", "partial, Exercise {id}: {csv}");
    }
    let report = read(&grades.join("partial/report.md"));
    assert!(report.contains("index out of bounds"), "{report}");
    // Each failure says what kind it is, and a panic where it was raised.
    for (id, status) in [
        ("1.4", "wrong"),
        ("2.1", "timed out"),
        ("2.3", "crashed"),
        ("1.1", "passed"),
        // Judged with the key's 1.4 in place of the student's, and saying so.
        ("1.6", "passed (with the key's code for 1.4)"),
    ] {
        assert!(
            report
                .lines()
                .any(|l| l.starts_with(&format!("| {id} ")) && l.contains(&format!("| {status} |"))),
            "partial, Exercise {id} is not '{status}':\n{report}"
        );
    }
    assert!(
        report.contains("panicked at labs/lab02/src/lib.rs:"),
        "{report}"
    );
    assert!(report.contains("returned [NaN, NaN, NaN]"), "{report}");
    // The loop is stopped by its budget of work, long before the time limit.
    assert!(
        report.contains("Exercise 2.1 — `intersect_plane`")
            && report.contains(contracts::wire::OUT_OF_WORK),
        "{report}"
    );
    let html = read(&grades.join("partial/report.html"));
    let image = html
        .split("<img src=\"")
        .nth(1)
        .and_then(|rest| rest.split('"').next())
        .unwrap_or_else(|| panic!("no image in the partial report:\n{html}"));
    assert!(grades.join("partial").join(image).is_file(), "{image}");

    let report = read(&grades.join("lab02-only/report.md"));
    assert!(
        report
            .lines()
            .any(|l| l.starts_with("| 1.1 ") && l.contains("| not started |")),
        "lab02-only, Exercise 1.1 is not 'not started':\n{report}"
    );
    // Nothing a student sees names the instructor's directories.
    for name in ["partial", "lab02-only"] {
        for file in ["report.md", "report.html", "results.json"] {
            let text = read(&grades.join(name).join(file));
            let root = raylab_tests::workflow::root();
            let root = root.canonicalize().unwrap_or(root);
            for path in [root.to_string_lossy(), grades.to_string_lossy()] {
                assert!(
                    !text.contains(&*path),
                    "{name}/{file} names {path}:\n{text:.2000}"
                );
            }
        }
    }

    let row = csv_row(&csv, "lab02-only");
    for id in ["2.1", "2.2", "2.3", "2.4", "2.5", "2.6"] {
        assert_ne!(row[column(id)], "0", "lab02-only, Exercise {id}: {csv}");
    }
    for id in ["1.1", "1.2", "3.1"] {
        assert_eq!(row[column(id)], "0", "lab02-only, Exercise {id}: {csv}");
    }

    let row = csv_row(&csv, "edited");
    assert_eq!(
        row[column("1.1")],
        "0",
        "edited tests have no effect: {csv}"
    );
    assert_eq!(total(&row), 0, "{csv}");
    assert_eq!(row[column("changed_files")], "2", "{csv}");
    let report = read(&grades.join("edited/report.md"));
    assert!(
        report.contains("modified: labs/lab01/tests/checks.rs"),
        "{report}"
    );
    assert!(
        report.contains("added: labs/lab01/golden/extra.json"),
        "{report}"
    );

    let results: serde_json::Value =
        serde_json::from_str(&read(&grades.join("partial/results.json"))).unwrap();
    let tests = results["tests"].as_array().unwrap();
    let score: f64 = tests.iter().map(|t| t["score"].as_f64().unwrap()).sum();
    assert_eq!(results["score"].as_f64(), Some(score));
    let hidden = tests.iter().find(|t| t["number"] == "1.6").unwrap();
    assert_eq!(hidden["visibility"], "after_due_date");
    // The exercises' tests pass or fail; the written answers' (no number) has no status.
    assert!(
        tests
            .iter()
            .filter(|t| t["number"].is_string())
            .all(|t| t["status"] == "passed" || t["status"] == "failed")
    );

    let junit = read(&grades.join("junit.xml"));
    assert!(junit.contains("<testsuite name=\"partial\""), "{junit}");
    // A failure's type is its status (quick-junit writes `message` first).
    assert!(
        junit.split("<failure ").skip(1).any(|f| f
            .split('>')
            .next()
            .unwrap()
            .contains("type=\"crashed\"")),
        "{junit}"
    );
    // Every link and image of the pages resolves: files beside them, anchors within them.
    for page in ["index.html", "partial/report.html", "complete/report.html"] {
        let path = grades.join(page);
        let html = read(&path);
        let dir = path.parent().unwrap();
        let ids: Vec<&str> = html
            .split("id=\"")
            .skip(1)
            .filter_map(|r| r.split('"').next())
            .collect();
        for marker in ["href=\"", "src=\""] {
            for target in html
                .split(marker)
                .skip(1)
                .filter_map(|r| r.split('"').next())
            {
                match target.strip_prefix('#') {
                    Some(id) => assert!(ids.contains(&id), "{page}: no id {id} for its link"),
                    None => {
                        // A page beside this one, and the anchor in it a link names.
                        let (file, anchor) = target.split_once('#').unwrap_or((target, ""));
                        assert!(dir.join(file).is_file(), "{page}: {file} does not exist");
                        assert!(
                            anchor.is_empty()
                                || read(&dir.join(file)).contains(&format!("id=\"{anchor}\"")),
                            "{page}: {file} has no anchor {anchor}"
                        );
                    }
                }
            }
        }
    }

    // What a reader sees in a browser: text, every image loaded, every anchor there.
    for page in ["index.html", "partial/report.html", "complete/report.html"] {
        if browser {
            check_in_browser(&grades.join(page)).unwrap_or_else(|e| panic!("{e}"));
        }
    }
    phase("pages checked in a browser");
    let (ok, out) = raylab(&[
        "report",
        "--lab",
        "3",
        "--quick",
        "--out",
        work.join("report").to_str().unwrap(),
    ]);
    assert!(ok, "{out}");
    if browser {
        let checked = check_in_browser(&work.join("report/lab03/report.html"))
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(!checked.contains(" 0 images"), "{checked}");
    }
    phase("lab 3's report made");

    gradescope_grades_like_grade(&work, &partial, &grades, &handout_target);
    phase("graded as on Gradescope");
}

/// `raylab gradescope`'s bundle: its `run_autograder` grades a submission in a stand-in for
/// Gradescope's `/autograder` as `raylab grade` does, into results.json. (The builds are those
/// of the grading above: same grading directory, same target directory.)
fn gradescope_grades_like_grade(work: &Path, partial: &Path, grades: &Path, target: &Path) {
    let bundle = work.join("gradescope");
    let autograder = work.join("autograder");
    for dir in [&bundle, &autograder] {
        let _ = fs::remove_dir_all(dir);
    }
    let (ok, out) = raylab(&[
        "gradescope",
        "--allow-dirty",
        "--out",
        bundle.to_str().unwrap(),
        "--lab",
        "1",
        "--timeout",
        TIMEOUT,
    ]);
    assert!(ok, "{out}");
    for file in [
        "setup.sh",
        "run_autograder",
        "Cargo.lock",
        "reference/src/lib.rs",
    ] {
        assert!(bundle.join(file).is_file(), "the bundle has no {file}");
    }
    for left_out in [".ci", "target", ".git"] {
        assert!(!bundle.join(left_out).exists(), "the bundle has {left_out}");
    }
    // Gradescope unpacks the bundle into source/ and the upload into submission/ (here a
    // student who zipped the handout's folder rather than its contents).
    fs::create_dir_all(autograder.join("submission")).unwrap();
    fs::rename(&bundle, autograder.join("source")).unwrap();
    copy_tree(partial, &autograder.join("submission/my-raylab"));
    // In bubblewrap, as on one machine: the builds are those of the grading above. (`--run-as`,
    // where a container cannot start bubblewrap, is the hostile corpus's second run, in
    // hostile_submissions.rs; the sandbox's unit tests check what it keeps the exercise from.)
    let output = Command::new(autograder.join("source/run_autograder"))
        .env("AUTOGRADER", &autograder)
        .env("RAYLAB", target_dir().join("debug/raylab"))
        .env("RAYLAB_TARGET_DIR", target)
        .env("RAYLAB_GRADING_DIR", grades)
        .output()
        .expect("run_autograder runs");
    let log = output_text(&output);
    assert!(output.status.success(), "{log}");
    let text = read(&autograder.join("results/results.json"));
    let results: serde_json::Value = serde_json::from_str(&text).expect("results.json is JSON");

    // Gradescope's required fields: a score (or every test's), and for each test a score and
    // a max_score; name, number, status, output and visibility as it documents them.
    let tests = results["tests"].as_array().expect("tests[]");
    // The seconds the grading took, which Gradescope shows beside the score.
    assert!(results["execution_time"].is_u64(), "{text}");
    // The exercises, then the written answers as a test of no points and no status.
    let numbers: Vec<Option<&str>> = tests.iter().map(|t| t["number"].as_str()).collect();
    assert_eq!(
        numbers,
        [
            Some("1.1"),
            Some("1.2"),
            Some("1.3"),
            Some("1.4"),
            Some("1.5"),
            Some("1.6"),
            None
        ],
        "{text}"
    );
    let answers = &tests[6];
    assert!(
        answers["name"]
            .as_str()
            .is_some_and(|n| n.starts_with("Lab 01 written answers ("))
            && answers["score"] == 0
            && answers["max_score"] == 0
            && answers["output_format"] == "html"
            && answers["status"].is_null(),
        "{answers}"
    );
    let mut sum = 0.0;
    for test in &tests[..6] {
        let score = test["score"].as_f64().expect("a test's score");
        let max = test["max_score"].as_f64().expect("a test's max_score");
        assert!((0.0..=max).contains(&score), "{test}");
        assert!(
            test["name"].is_string() && test["output"].is_string(),
            "{test}"
        );
        assert!(
            ["passed", "failed"].contains(&test["status"].as_str().unwrap()),
            "{test}"
        );
        let visibility = test["visibility"].as_str().unwrap();
        assert!(
            ["hidden", "after_due_date", "after_published", "visible"].contains(&visibility),
            "{test}"
        );
        let wanted = if test["number"] == "1.4" { 0.0 } else { max };
        assert_eq!(score, wanted, "partial's camera: {test}");
        sum += score;
    }
    assert_eq!(results["score"].as_f64(), Some(sum), "{text}");
    assert!(
        results["output"]
            .as_str()
            .unwrap()
            .contains("built and run in bubblewrap"),
        "{text}"
    );
    assert!(
        !text.contains(work.to_str().unwrap()),
        "an instructor path: {text}"
    );

    // A submission with nothing to grade still gets a result that says why.
    fs::remove_dir_all(autograder.join("submission")).unwrap();
    fs::write(autograder.join("submission"), "not a directory").unwrap();
    let output = Command::new(autograder.join("source/run_autograder"))
        .env("AUTOGRADER", &autograder)
        .env("RAYLAB", target_dir().join("debug/raylab"))
        .env("RAYLAB_TARGET_DIR", target)
        .env("RAYLAB_GRADING_DIR", grades)
        .output()
        .expect("run_autograder runs");
    assert!(output.status.success());
    let text = read(&autograder.join("results/results.json"));
    let results: serde_json::Value = serde_json::from_str(&text).expect("results.json is JSON");
    assert_eq!(results["score"].as_f64(), Some(0.0), "{text}");
    assert!(
        results["output"]
            .as_str()
            .unwrap()
            .contains("could not grade this submission"),
        "{text}"
    );
}
