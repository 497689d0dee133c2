//! A short term on raylab, end to end: the handout as a git repository that four students
//! clone; the commands a student runs (`cargo test`, `status`, `report`), which leave a clone as
//! it was; two releases they pull without conflicts; lab 2 done by three, its written answers
//! filled in, and never started by Dave; `raylab grade` with the course's due dates and the
//! instructor's points for the answers, which penalises Bob's late submission from his commit's
//! time and finds no submission of Dave's (not a late one at the handout's time); `raylab
//! similarity`, which finds Bob's copy of Alice's work and not Carol's own; Gradescope's
//! results with the images inline, a page per student for an LMS and Canvas's gradebook; every
//! page checked in Chromium.
//!
//! The trees are kept in `target/raylab-term-test/` to be looked at.

use std::fs;
use std::path::{Path, PathBuf};
use std::time::Instant;

use grading::prerequisite;
use raylab_tests::workflow::{
    cargo_in as cargo, check_in_browser, raylab_in, read, root, seed_target_dir,
    student_git as git, target_dir, workflow_target_dir,
};

#[path = "../../../labs/raylab/tests/fixtures/lab02_class.rs"]
mod class;

/// `raylab ARGS`, built as the workspace's test build builds it.
fn raylab(args: &[&str]) -> String {
    raylab_in(&root(), &target_dir(), args)
}

/// The row of `student` in the CSV `csv`, as (header, value) pairs.
fn row<'a>(csv: &'a str, student: &str) -> Vec<(&'a str, &'a str)> {
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let line = csv
        .lines()
        .find(|l| l.starts_with(&format!("{student},")))
        .unwrap_or_else(|| panic!("no row for {student}:\n{csv}"));
    header.into_iter().zip(line.split(',')).collect()
}

fn field<'a>(row: &[(&str, &'a str)], name: &str) -> &'a str {
    row.iter()
        .find(|(h, _)| *h == name)
        .unwrap_or_else(|| panic!("no column {name} in {row:?}"))
        .1
}

/// Lab 2's due date in the course file below.
const DUE: &str = "2026-10-12T23:59:00+02:00";

#[test]
fn a_term_from_handout_to_gradebook() {
    let test = "a_term_from_handout_to_gradebook";
    if !(prerequisite::program_or_skip(test, "bwrap", "apt-get install bubblewrap")
        && prerequisite::program_or_skip(test, "git", "apt-get install git")
        && prerequisite::rust_target_or_skip(test, "wasm32-unknown-unknown"))
    {
        return;
    }
    let browser = prerequisite::program_or_skip(
        "the browser check of the term's pages",
        "chromium",
        "apt-get install chromium",
    );
    let dolos = root().join("target/dolos");
    let similarity = dolos.join("node_modules/@dodona/dolos-lib").is_dir()
        || prerequisite::skip_or_fail(
            "the similarity check of the term",
            "Dolos",
            "bash labs/raylab/scripts/install-dolos.sh",
        );
    let work = target_dir().join("raylab-term-test");
    let started = Instant::now();
    let phase = |what: &str| eprintln!("{:7.1} s  term: {what}", started.elapsed().as_secs_f64());
    for dir in ["course", "class", "grades"] {
        let _ = fs::remove_dir_all(work.join(dir));
    }
    fs::create_dir_all(work.join("class")).unwrap();
    let course = work.join("course");
    let course_arg = course.to_str().unwrap();

    // The handout, a git repository of one commit.
    raylab(&["handout", "--allow-dirty", "--out", course_arg]);
    assert_eq!(
        git(&course, &["rev-list", "--count", "HEAD"], None).trim(),
        "1"
    );
    assert!(course.join("labs/lab02/answers.md").is_file());
    assert!(!course.join("docs/instructors.md").exists());
    // Cargo, reading the handout's workspace, changes none of its files: its lock file is the
    // one the workspace resolves to, and `--update` takes the repository below.
    let (ok, out) = cargo(
        &course,
        &target_dir(),
        &["metadata", "--offline", "--format-version", "1"],
    );
    assert!(ok, "{out}");
    assert_eq!(git(&course, &["status", "--porcelain"], None), "");
    phase("handout repository written");

    // Three students clone it and do lab 2, each committing at their own time.
    let stubs = read(&course.join("labs/lab02/src/lib.rs"));
    // Alice tunes her shading to the default scene's ground: only 2.6's image shows it.
    let alice_code = class::filled_stubs(&stubs, &class::ALICE).replacen(
        "fn shade_lambertian(&self, rho_d: Vec3, normal: Vec3, lights: &[LightSample]) -> Vec3 {",
        "fn shade_lambertian(&self, rho_d: Vec3, normal: Vec3, lights: &[LightSample]) -> Vec3 {\n        let rho_d = if rho_d == Vec3::splat(0.7) { 0.5 * rho_d } else { rho_d };",
        1,
    );
    assert!(alice_code.contains("Vec3::splat(0.7)"));
    let students: [(&str, String, &str); 3] = [
        ("alice", alice_code, "2026-10-12T21:05:00+02:00"),
        // A day and a half late.
        ("bob", class::BOB.to_string(), "2026-10-14T11:30:00+02:00"),
        (
            "carol",
            class::filled_stubs(&stubs, &class::CAROL),
            "2026-10-12T23:50:00+02:00",
        ),
    ];
    let mut clones = Vec::new();
    for (name, code, date) in &students {
        let clone = work.join("class").join(name);
        git(
            &work.join("class"),
            &["clone", "--quiet", course_arg, name],
            None,
        );
        fs::write(clone.join("labs/lab02/src/lib.rs"), code).unwrap();
        if *name == "alice" {
            let answers = clone.join("labs/lab02/answers.md");
            let text = read(&answers)
                .replacen("<!-- Your answer here. -->", "They bound the hit: `tmin` keeps a ray from its own surface, `tmax` from hits past the closest.", 1)
                .replacen("<!-- Your answer here. -->", "Cramer's rule on the 3 × 3 system <e1 e2 −d>.", 1);
            fs::write(&answers, text).unwrap();
        }
        git(
            &clone,
            &["commit", "--quiet", "--all", "--message", "lab 2"],
            Some(date),
        );
        clones.push(clone);
    }
    phase("three students cloned the handout and did lab 2");

    // Dave clones it and runs what a student runs, which changes no file git tracks (nor adds
    // one it does not ignore), and never commits.
    let dave = work.join("class/dave");
    git(
        &work.join("class"),
        &["clone", "--quiet", course_arg, "dave"],
        None,
    );
    // A target directory of its own: a tree of the handout's layout shares its crates' builds
    // by name, and another workflow's handout builds its own code of lab 1 in the workflows'.
    let student_target = target_dir().join("raylab-term-student-target");
    seed_target_dir(&student_target);
    let (ok, out) = cargo(&dave, &student_target, &["test", "-p", "lab01"]);
    assert!(!ok && out.contains("is not implemented yet"), "{out}");
    let student = |args: &[&str]| raylab_in(&dave, &student_target, args);
    let status = student(&["status", "--lab", "1"]);
    assert!(status.contains("lab01  0/"), "{status}");
    student(&["report", "--lab", "1", "--quick"]);
    assert!(dave.join("out/report/lab01").is_dir());
    assert_eq!(
        git(
            &dave,
            &["status", "--porcelain", "--untracked-files=all"],
            None
        ),
        "",
        "a student's commands leave the clone as it was"
    );
    // Where builds and figures go with cargo's own target directory: ignored as well.
    let ignored = git(&dave, &["check-ignore", "target/debug/x", "out/x"], None);
    assert_eq!(ignored.lines().count(), 2, "{ignored}");
    clones.push(dave.clone());
    phase("a fourth student ran the student commands and committed nothing");

    // Two releases, each one commit that every student pulls without a conflict.
    for (release, subject) in [
        ("1", "release: solutions of lab 1"),
        ("1,2", "release: solutions of lab 2"),
    ] {
        raylab(&[
            "handout",
            "--allow-dirty",
            "--update",
            course_arg,
            "--release-solutions",
            release,
        ]);
        assert_eq!(
            git(&course, &["log", "-1", "--format=%s"], None).trim(),
            subject
        );
        for (name, clone) in ["alice", "bob", "carol", "dave"].iter().zip(&clones) {
            let before = read(&clone.join("labs/lab02/answers.md"));
            git(
                clone,
                &["pull", "--quiet", "--no-rebase", "--no-edit"],
                None,
            );
            let code = students
                .iter()
                .find(|(student, _, _)| student == name)
                .map_or(&stubs, |(_, code, _)| code);
            assert_eq!(
                read(&clone.join("labs/lab02/src/lib.rs")),
                *code,
                "{name}'s code"
            );
            assert_eq!(
                read(&clone.join("labs/lab02/answers.md")),
                before,
                "{name}'s answers"
            );
        }
    }
    for clone in &clones {
        assert!(clone.join("reference/src/lab01.rs").is_file());
        assert!(clone.join("reference/src/lab02.rs").is_file());
    }
    phase("two releases pulled");

    // The course file, and the instructor's points for the written answers.
    let course_file = work.join("term.toml");
    fs::write(
        &course_file,
        format!(
            "[late]\npenalty_per_day = 0.1\ngrace_minutes = 15\ncap_days = 5\n\n\
             [labs.2]\ndue = {DUE}\ncanvas_assignment = \"Lab 02 (4412)\"\n\n\
             [students.alice]\nname = \"Liddell, Alice\"\ncanvas_id = \"1001\"\nsis_login_id = \"alice@uni.example\"\n"
        ),
    )
    .unwrap();
    let points = work.join("answers-points.csv");
    fs::write(
        &points,
        "student,lab,question,points,max_points,comment\n\
         alice,2,Q1,2,2,\"both bounds, with why\"\n\
         alice,2,Q2,1,2,\"the formulas, but not why β + γ ≤ 1\"\n\
         carol,2,Q1,0,2,no answer\n",
    )
    .unwrap();

    let grades = work.join("grades");
    let class_args: Vec<String> = clones
        .iter()
        .map(|c| c.to_string_lossy().into_owned())
        .collect();
    let target = workflow_target_dir();
    let mut args: Vec<&str> = vec!["grade"];
    args.extend(class_args.iter().map(String::as_str));
    args.extend([
        "--out",
        grades.to_str().unwrap(),
        "--lab",
        "2",
        "--release-solutions",
        "1,2",
        "--course",
        course_file.to_str().unwrap(),
        "--manual-points",
        points.to_str().unwrap(),
        "--timeout",
        "20",
        "--target-dir",
        target.to_str().unwrap(),
    ]);
    raylab(&args);
    phase("graded");

    let gradebook = read(&grades.join("gradebook.csv"));
    let (alice, bob, carol) = (
        row(&gradebook, "alice"),
        row(&gradebook, "bob"),
        row(&gradebook, "carol"),
    );
    assert_eq!(field(&alice, "2.6"), "0", "{gradebook}");
    assert_eq!(field(&carol, "2.6"), field(&carol, "2.6"));
    check_lateness(&gradebook, &alice, &bob);
    check_no_submission(&grades, &gradebook);

    // Alice's reports: the failed 2.6 with its images, her answers, the manual points.
    let report = read(&grades.join("alice/report.md"));
    assert!(report.contains("Written answers (2 of "), "{report}");
    assert!(
        report.contains("Cramer's rule on the 3 × 3 system"),
        "{report}"
    );
    assert!(report.contains("the formulas, but not why"), "{report}");
    let results: serde_json::Value =
        serde_json::from_str(&read(&grades.join("alice/results.json"))).expect("JSON");
    check_gradescope_results(&results);
    let page = read(&grades.join("pages/alice.html"));
    assert!(
        page.contains("src=\"data:image/png;base64,"),
        "the page's images are inline"
    );
    assert!(
        !page.contains("src=\"images/"),
        "no image is a file beside the page"
    );
    let index = read(&grades.join("index.html"));
    assert!(index.contains("Written answers") && index.contains("alice/report.html#answers-lab02"));
    check_canvas(&read(&grades.join("canvas.csv")));
    phase("reports, results and gradebooks read");

    // Bob's copy of Alice's lab is found, Carol's own work is not.
    if similarity {
        let mut args = vec!["similarity"];
        args.extend(class_args.iter().map(String::as_str));
        args.extend(["--out", grades.to_str().unwrap(), "--lab", "2"]);
        raylab(&args);
        let csv = read(&grades.join("similarity.csv"));
        let pairs: Vec<&str> = csv.lines().skip(1).collect();
        assert!(
            pairs.len() == 1 && pairs[0].starts_with("lab02,alice,bob,"),
            "only Alice and Bob are similar:\n{csv}"
        );
        let index = read(&grades.join("index.html"));
        assert!(
            index.contains("href=\"similarity.html\""),
            "the class page links the pairs"
        );
        phase("similar submissions found");
    }

    if browser {
        let mut pages: Vec<PathBuf> = [
            "index.html",
            "alice/report.html",
            "bob/report.html",
            "pages/alice.html",
        ]
        .iter()
        .map(|p| grades.join(p))
        .collect();
        if similarity {
            pages.push(grades.join("similarity.html"));
        }
        for page in pages {
            check_in_browser(&page).unwrap_or_else(|e| panic!("{e}"));
        }
        phase("pages checked in a browser");
    }
}

/// Alice on time; Bob a day and a half late: two started days at 10% of the lab's points
/// each, taken from what he earned. The total of each is the exercises' points, with the
/// points graded by hand, after the penalty.
fn check_lateness(gradebook: &str, alice: &[(&str, &str)], bob: &[(&str, &str)]) {
    let number = |row: &[(&str, &str)], name: &str| -> f64 {
        field(row, name)
            .parse()
            .unwrap_or_else(|_| panic!("{name}: {gradebook}"))
    };
    let exercises = |row: &[(&str, &str)]| -> f64 {
        row.iter()
            .filter(|(h, _)| h.starts_with("2."))
            .map(|(_, v)| v.parse::<f64>().unwrap())
            .sum()
    };
    assert_eq!(field(alice, "lab02_days_late"), "0.00", "{gradebook}");
    assert_eq!(number(alice, "lab02_penalty"), 0.0, "{gradebook}");
    assert_eq!(number(alice, "lab02_manual"), 3.0, "{gradebook}");
    assert_eq!(
        number(alice, "total"),
        exercises(alice) + 3.0,
        "{gradebook}"
    );
    assert_eq!(field(bob, "lab02_due"), DUE, "{gradebook}");
    assert!(
        field(bob, "lab02_submitted").starts_with("2026-10-14T11:30:00"),
        "Bob's time is his commit's: {gradebook}"
    );
    assert_eq!(field(bob, "lab02_days_late"), "1.48", "{gradebook}");
    let lab_points = number(bob, "max_score");
    let penalty = number(bob, "lab02_penalty");
    let near = |a: f64, b: f64| (a - b).abs() < 1e-6;
    assert!(
        near(penalty, (0.2 * lab_points).min(exercises(bob))),
        "two started days at 10%: {gradebook}"
    );
    assert!(penalty > 0.0, "{gradebook}");
    assert!(
        near(number(bob, "total"), exercises(bob) - penalty),
        "{gradebook}"
    );
}

/// Dave never committed: his lab 2 is "no submission" in every file of the grading — not one
/// made at the time of the handout's commits, which the test makes as it runs (on time or weeks
/// late depending on the day) — and costs nothing.
fn check_no_submission(grades: &Path, gradebook: &str) {
    let dave = row(gradebook, "dave");
    assert_eq!(
        [
            field(&dave, "lab02_due"),
            field(&dave, "lab02_submitted"),
            field(&dave, "lab02_days_late"),
            field(&dave, "lab02_penalty"),
        ],
        [DUE, "no submission", "", "0"],
        "{gradebook}"
    );
    let exercises: f64 = dave
        .iter()
        .filter(|(h, _)| h.starts_with("2."))
        .map(|(_, v)| v.parse::<f64>().unwrap())
        .sum();
    assert_eq!(
        field(&dave, "total").parse::<f64>(),
        Ok(exercises),
        "{gradebook}"
    );
    let line = format!(
        "due {DUE}; no submission (no commit but the handout's own changed labs/lab02/src/ or labs/lab02/answers.md); not late: no penalty"
    );
    for file in ["dave/report.md", "dave/report.html", "index.html"] {
        let text = read(&grades.join(file));
        assert!(text.contains(&line), "{file}: {text}");
    }
    for file in ["dave/report.md", "dave/report.html"] {
        let text = read(&grades.join(file));
        assert!(!text.contains(" late ("), "{file}: {text}");
    }
    let results: serde_json::Value =
        serde_json::from_str(&read(&grades.join("dave/results.json"))).expect("JSON");
    assert!(
        results["output"].as_str().unwrap().contains(&line),
        "{results}"
    );
    let tests: f64 = results["tests"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t["score"].as_f64().unwrap())
        .sum();
    assert_eq!(
        results["score"].as_f64(),
        Some(tests),
        "no penalty: {results}"
    );
    let canvas = read(&grades.join("canvas.csv"));
    assert!(
        canvas
            .lines()
            .any(|l| l.starts_with("dave,") && l.ends_with(&format!(",{exercises}"))),
        "{canvas}"
    );
}

/// Alice's Gradescope results: Gradescope's fields, the failed 2.6 with its images inline in
/// the `html` format, her answers' points as tests of their own.
fn check_gradescope_results(results: &serde_json::Value) {
    let tests = results["tests"].as_array().expect("tests[]");
    let mut sum = 0.0;
    for test in tests {
        let (score, max) = (
            test["score"].as_f64().expect("a score"),
            test["max_score"].as_f64().expect("a max_score"),
        );
        assert!((0.0..=max).contains(&score), "{test}");
        assert!(
            test["name"].is_string() && test["output"].is_string(),
            "{test}"
        );
        assert!(
            ["text", "html", "md", "simple_format", "ansi"]
                .contains(&test["output_format"].as_str().unwrap_or("text")),
            "{test}"
        );
        sum += score;
    }
    assert_eq!(results["score"].as_f64(), Some(sum), "on time: no penalty");
    let shading = tests
        .iter()
        .find(|t| t["number"] == "2.6")
        .expect("Exercise 2.6");
    assert_eq!(shading["score"].as_f64(), Some(0.0), "{shading}");
    assert_eq!(shading["output_format"], "html", "{shading}");
    let output = shading["output"].as_str().unwrap();
    assert_eq!(
        output.matches("<img src=\"data:image/png;base64,").count(),
        3,
        "the student's render, the reference and the difference: {output:.400}"
    );
    assert!(output.starts_with("<pre>"), "{output:.400}");
    let by_hand: Vec<&serde_json::Value> = tests
        .iter()
        .filter(|t| t["name"].as_str().unwrap().contains("graded by hand"))
        .collect();
    assert_eq!(by_hand.len(), 2, "{results}");
    assert!(
        by_hand
            .iter()
            .any(|t| t["output"].as_str().unwrap().contains("not why β + γ ≤ 1")),
        "{results}"
    );
}

/// Canvas's gradebook import: its five columns of students, the lab's assignment, the row of
/// points possible, Alice by the name Canvas knows.
fn check_canvas(csv: &str) {
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("Student,ID,SIS User ID,SIS Login ID,Section,Lab 02 (4412)"),
        "{csv}"
    );
    assert!(
        lines.next().unwrap().starts_with("Points Possible,"),
        "{csv}"
    );
    assert!(
        csv.lines()
            .any(|l| l.starts_with("\"Liddell, Alice\",1001,,alice@uni.example,")),
        "{csv}"
    );
    assert!(csv.lines().any(|l| l.starts_with("bob,")), "{csv}");
}
