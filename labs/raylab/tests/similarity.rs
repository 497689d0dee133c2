//! `raylab similarity` on a class of three: two near-copies of lab 2 and one honest solution.
//!
//! Alice fills in the handout's stubs; Bob hands in her code with the variables renamed, the
//! functions and the two `impl` blocks in another order and his own comments; Carol solves the
//! lab on her own. Dolos must find Alice and Bob above the threshold and neither with Carol.

// `raylab similarity` is an instructor's command.
#![cfg(feature = "instructor")]

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The repository the command line was built from.
fn repository() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[path = "fixtures/lab02_class.rs"]
mod class;

use class::{ALICE, BOB, CAROL};

/// Lab 2's stubs with each `todo!` replaced by one of `answers`.
fn filled_stubs(answers: &[&str; 6]) -> String {
    let stubs = fs::read_to_string(repository().join("labs/lab02/src/lib.rs")).unwrap();
    class::filled_stubs(&stubs, answers)
}

/// A submission named `student` in `class` whose lab 2 is `lib_rs`.
fn submission(class: &Path, student: &str, lib_rs: &str) -> String {
    let src = class.join(student).join("labs/lab02/src");
    fs::create_dir_all(&src).unwrap();
    fs::write(src.join("lib.rs"), lib_rs).unwrap();
    class.join(student).to_string_lossy().into_owned()
}

/// The rows of similarity.csv after its header.
fn rows(csv: &str) -> Vec<Vec<String>> {
    csv.lines()
        .skip(1)
        .map(|line| line.split(',').map(str::to_string).collect())
        .collect()
}

#[test]
fn near_copies_are_similar_and_an_honest_solution_is_not() {
    let dolos = repository().join("target/dolos");
    if !dolos.join("node_modules/@dodona/dolos-lib").is_dir()
        && !grading::prerequisite::skip_or_fail(
            "similarity::near_copies_are_similar_and_an_honest_solution_is_not",
            "Dolos",
            "bash labs/raylab/scripts/install-dolos.sh",
        )
    {
        return;
    }
    let class = std::env::temp_dir().join(format!("raylab-similarity-{}", std::process::id()));
    let out = class.join("out");
    fs::create_dir_all(&out).unwrap();
    let submissions = [
        submission(&class, "alice", &filled_stubs(&ALICE)),
        submission(&class, "bob", BOB),
        submission(&class, "carol", &filled_stubs(&CAROL)),
        // Dan has not started: the stubs as handed out are no submission to compare.
        submission(
            &class,
            "dan",
            &fs::read_to_string(repository().join("labs/lab02/src/lib.rs")).unwrap(),
        ),
    ];
    // The class page of `raylab grade`, to which the similar pairs are added.
    fs::write(
        out.join("index.html"),
        "<html><body><h1>Grades</h1><footer><p>stamp</p></footer></body></html>",
    )
    .unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .arg("similarity")
        .args(&submissions)
        .args(["--out", &out.to_string_lossy(), "--lab", "2", "--dolos"])
        .arg(&dolos)
        .output()
        .expect("raylab runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        stdout.contains("lab02: 3 submissions compared, 1 of 3 pairs at or above 0.6"),
        "{stdout}"
    );

    let csv = fs::read_to_string(out.join("similarity.csv")).unwrap();
    let rows = rows(&csv);
    assert_eq!(rows.len(), 1, "only Alice and Bob are similar:\n{csv}");
    let [lab, a, b, similarity, longest, fragment_a, fragment_b] = &rows[0][..] else {
        panic!("seven columns: {csv}");
    };
    assert_eq!(
        (lab.as_str(), a.as_str(), b.as_str()),
        ("lab02", "alice", "bob")
    );
    let similarity: f64 = similarity.parse().unwrap();
    assert!(similarity >= 0.8, "Alice and Bob: {similarity}");
    assert!(longest.parse::<u32>().unwrap() > 10, "{csv}");
    assert!(fragment_a.starts_with("labs/lab02/src/lib.rs:"), "{csv}");
    assert!(fragment_b.starts_with("labs/lab02/src/lib.rs:"), "{csv}");

    let page = fs::read_to_string(out.join("similarity.html")).unwrap();
    assert!(page.contains("<td>alice</td><td>bob</td>"), "{page}");
    assert!(page.contains("dan: labs/lab02/src is the stubs, unchanged"));
    let index = fs::read_to_string(out.join("index.html")).unwrap();
    assert!(
        index.contains("<section id=\"similarity\">")
            && index.contains("href=\"similarity.html\"")
            && index.contains("<td>alice</td><td>bob</td>"),
        "{index}"
    );
    fs::remove_dir_all(&class).ok();
}
