//! A figure of a student's report, from `raylab report` to the instructor's pages: the written
//! answers show it as `figures/NAME.png`, `report` copies it beside them where git keeps it, a
//! clone of the student's repository (without `out/`) carries it, and `grade` takes it into
//! `report.md`, `report.html`, the page for an LMS and Gradescope's `results.json`, byte for
//! byte; an image the answers name outside the submission is named as not taken. The grading's
//! output, not a terminal, is a log of plain lines: the submission, the lab built, each exercise.
//!
//! The trees are kept in `target/raylab-answer-figures-test/` to be looked at.

use std::fs;
use std::path::Path;

use base64::Engine as _;
use grading::prerequisite;
use raylab_tests::workflow::{
    check_in_browser, raylab_in, read, root, student_git, target_dir, workflow_target_dir,
};

/// The figure of lab 1's report that the answer shows.
const FIGURE: &str = "default-base-colour.png";

/// `raylab ARGS`, built as the workspace's test build builds it; its output.
fn raylab(args: &[&str]) -> String {
    raylab_in(&root(), &target_dir(), args)
}

/// git in `dir`, as a student with an identity of their own.
fn git(dir: &Path, args: &[&str]) {
    student_git(dir, args, None);
}

#[test]
fn a_figure_travels_from_the_report_to_the_instructor_s_pages() {
    let test = "a_figure_travels_from_the_report_to_the_instructor_s_pages";
    if !(prerequisite::program_or_skip(test, "bwrap", "apt-get install bubblewrap")
        && prerequisite::program_or_skip(test, "git", "apt-get install git")
        && prerequisite::rust_target_or_skip(test, "wasm32-unknown-unknown"))
    {
        return;
    }
    let work = target_dir().join("raylab-answer-figures-test");
    let _ = fs::remove_dir_all(&work);
    fs::create_dir_all(&work).unwrap();
    let course = work.join("course");
    raylab(&[
        "handout",
        "--allow-dirty",
        "--out",
        course.to_str().unwrap(),
    ]);
    git(&work, &["clone", "--quiet", "course", "ada-work"]);
    let clone = work.join("ada-work");

    // Ada's answer shows a figure of her report, and a file outside her submission.
    let answers = clone.join("labs/lab01/answers.md");
    let text = read(&answers).replacen(
        "<!-- Your answer here. -->",
        &format!(
            "Linear in the pixels.\n\n![The base colour](figures/{FIGURE})\n\n![secret](../../../../etc/hostname)"
        ),
        1,
    );
    fs::write(&answers, text).unwrap();
    let report = work.join("report");
    let out = raylab(&[
        "report",
        "--lab",
        "1",
        "--quick",
        "--out",
        report.to_str().unwrap(),
        "--answers",
        answers.to_str().unwrap(),
    ]);
    let figure = fs::read(report.join("lab01").join(FIGURE)).unwrap();
    let copy = clone.join("labs/lab01/figures").join(FIGURE);
    assert!(out.contains("(shown in the answers)"), "{out}");
    assert_eq!(
        fs::read(&copy).unwrap(),
        figure,
        "the copy beside the answers"
    );

    // Handed in through git: a clone has the figure, and no `out/`.
    git(&clone, &["add", "-A"]);
    git(&clone, &["commit", "--quiet", "--message", "lab 1 answers"]);
    fs::create_dir_all(work.join("class")).unwrap();
    git(
        &work.join("class"),
        &["clone", "--quiet", clone.to_str().unwrap(), "ada"],
    );
    let submission = work.join("class/ada");
    assert!(!submission.join("out").exists());
    assert!(submission.join("labs/lab01/figures").join(FIGURE).is_file());

    let grades = work.join("grades");
    let target = workflow_target_dir();
    let log = raylab(&[
        "grade",
        submission.to_str().unwrap(),
        "--out",
        grades.to_str().unwrap(),
        "--lab",
        "1",
        "--timeout",
        "20",
        "--target-dir",
        target.to_str().unwrap(),
    ]);
    // Its output is no terminal: progress comes as plain lines, the points line too.
    for line in [
        "grading ada (1 of 1)",
        "ada: labs/lab01/src compiled (",
        "ada: Exercise 1.1 not started (",
        "ada: 0/",
        "graded 1 submission(s) in ",
    ] {
        assert!(log.contains(line), "{line:?} in:\n{log}");
    }

    let taken = grades.join("ada/images/lab01/answers-1.png");
    assert_eq!(fs::read(&taken).unwrap(), figure, "the grader's copy");
    let markdown = read(&grades.join("ada/report.md"));
    assert!(
        markdown.contains("> ![The base colour](images/lab01/answers-1.png)"),
        "{markdown}"
    );
    assert!(
        markdown.contains("../../../../etc/hostname")
            && markdown.contains("a path that leaves the submission"),
        "{markdown}"
    );
    assert!(
        !markdown.contains("labs/lab01/figures"),
        "not a change: {markdown}"
    );
    let page = read(&grades.join("ada/report.html"));
    assert!(
        page.contains("<img src=\"images/lab01/answers-1.png\" alt=\"The base colour\">"),
        "{page}"
    );
    let inline = format!(
        "src=\"data:image/png;base64,{}\"",
        base64::engine::general_purpose::STANDARD.encode(&figure)
    );
    let standalone = read(&grades.join("pages/ada.html"));
    assert!(
        standalone.contains(&inline),
        "the page for an LMS has it inline"
    );
    let results: serde_json::Value =
        serde_json::from_str(&read(&grades.join("ada/results.json"))).unwrap();
    let written = results["tests"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| {
            t["name"]
                .as_str()
                .unwrap()
                .starts_with("Lab 01 written answers")
        })
        .expect("the answers in results.json");
    assert_eq!(written["output_format"], "html", "{written}");
    assert_eq!(written["max_score"], 0, "{written}");
    assert!(
        written["output"].as_str().unwrap().contains(&inline),
        "Gradescope's page has it inline"
    );
    if prerequisite::program_or_skip(test, "chromium", "apt-get install chromium") {
        for page in ["ada/report.html", "pages/ada.html"] {
            check_in_browser(&grades.join(page)).unwrap_or_else(|e| panic!("{e}"));
        }
    }
}
