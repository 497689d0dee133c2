//! The grading benchmark: grades N generated submissions of every lab (or of `--lab N`) with
//! `raylab grade` and reports the machine time per submission per lab, split into build, run
//! and report time, without the time student code spends before its time limit.
//!
//! ```text
//! cargo run -p raylab-tests --bin grading-bench -- [--submissions N] [--lab N]... [--timeout S]
//! ```
//!
//! The submissions cycle through four kinds: complete (every lab's reference solution),
//! panicking (the first function of each lab panics), looping (it never returns), and the
//! handout's stubs. Everything is kept in `target/grading-bench/`; the first submission
//! compiles the framework and its dependencies (cold), the others only their own labs.

use std::fs;
use std::path::Path;
use std::process::{Command, ExitCode};

use raylab_tests::workflow::{copy_tree, correct_code, read, root, target_dir};

/// What a generated submission holds.
#[derive(Clone, Copy, Debug)]
enum Kind {
    Complete,
    Panicking,
    Looping,
    Stubs,
}

const KINDS: [Kind; 4] = [Kind::Complete, Kind::Panicking, Kind::Looping, Kind::Stubs];

/// `code` with `line` at the start of the body of the first function of its `impl`.
fn inject_first(code: &str, line: &str) -> String {
    let start = code.find("impl ").expect("an impl block");
    let function = start + code[start..].find("fn ").expect("a function");
    let body = function + code[function..].find('{').expect("a body") + 1;
    format!("{}\n        {line}{}", &code[..body], &code[body..])
}

fn lab_code(kind: Kind, lab: u32) -> Option<String> {
    let code = correct_code(lab);
    match kind {
        Kind::Complete => Some(code),
        Kind::Panicking => Some(inject_first(
            &code,
            "if std::hint::black_box(true) { panic!(\"a bug\"); }",
        )),
        Kind::Looping => Some(inject_first(
            &code,
            "while std::hint::black_box(true) { std::hint::spin_loop(); }",
        )),
        Kind::Stubs => None,
    }
}

fn raylab(args: &[&str]) -> Result<String, String> {
    let output = Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()))
        .args(["run", "--quiet", "-p", "raylab", "--"])
        .args(args)
        .current_dir(root())
        .output()
        .map_err(|e| format!("cargo: {e}"))?;
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    if output.status.success() {
        Ok(text)
    } else {
        Err(text)
    }
}

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    match values.len() {
        0 => 0.0,
        n if n % 2 == 1 => values[n / 2],
        n => (values[n / 2 - 1] + values[n / 2]) / 2.0,
    }
}

fn run() -> Result<(), String> {
    let mut submissions = 8usize;
    let mut labs: Vec<u32> = Vec::new();
    let mut timeout = "5".to_string();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        let mut value = || args.next().ok_or(format!("{arg} needs a value"));
        match arg.as_str() {
            "--submissions" => {
                submissions = value()?
                    .parse()
                    .map_err(|e| format!("--submissions: {e}"))?
            }
            "--lab" => labs.push(value()?.parse().map_err(|e| format!("--lab: {e}"))?),
            "--timeout" => timeout = value()?,
            other => return Err(format!("unknown argument {other}")),
        }
    }
    if labs.is_empty() {
        labs = course::labs().iter().map(|l| l.number()).collect();
    }
    let work = target_dir().join("grading-bench");
    let handout = work.join("handout");
    let subs = work.join("submissions");
    for dir in [&handout, &subs] {
        let _ = fs::remove_dir_all(dir);
    }
    raylab(&[
        "handout",
        "--allow-dirty",
        "--out",
        handout.to_str().unwrap(),
    ])?;
    let mut paths = Vec::new();
    for i in 0..submissions {
        let kind = KINDS[i % KINDS.len()];
        let dir = subs.join(format!("{i:03}-{kind:?}").to_lowercase());
        copy_tree(&handout, &dir);
        for &lab in &labs {
            if let Some(code) = lab_code(kind, lab) {
                let file = dir.join(format!("labs/lab{lab:02}/src/lib.rs"));
                fs::write(&file, code).map_err(|e| format!("{}: {e}", file.display()))?;
            }
        }
        paths.push(dir.to_string_lossy().into_owned());
    }
    let grades = work.join("grades");
    let mut grade: Vec<&str> = vec!["grade"];
    grade.extend(paths.iter().map(String::as_str));
    let out = grades.to_string_lossy().into_owned();
    grade.extend(["--out", &out, "--timeout", &timeout]);
    let lab_args: Vec<String> = labs.iter().map(u32::to_string).collect();
    for lab in &lab_args {
        grade.extend(["--lab", lab]);
    }
    let started = std::time::Instant::now();
    let printed = raylab(&grade)?;
    let wall = started.elapsed().as_secs_f64();
    print_table(&grades, labs.len(), wall, &printed)
}

/// Reads `timings.csv` and prints the figures per submission per lab.
fn print_table(grades: &Path, labs: usize, wall: f64, printed: &str) -> Result<(), String> {
    let csv = read(&grades.join("timings.csv"));
    let mut rows: Vec<[f64; 4]> = Vec::new();
    let mut names = Vec::new();
    for line in csv.lines().skip(1) {
        let fields: Vec<&str> = line.split(',').collect();
        let number = |i: usize| fields[i].parse::<f64>().map_err(|e| format!("{line}: {e}"));
        rows.push([number(1)?, number(2)?, number(3)?, number(4)?]);
        names.push(fields[0].to_string());
    }
    let per_lab = |r: &[f64; 4]| (r[0] + r[1] + r[3]) / labs as f64;
    println!(
        "{} submission(s) of {labs} lab(s) graded in {wall:.0} s on {} thread(s)",
        rows.len(),
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    println!("\nper submission and lab, seconds:");
    println!(
        "  {:<16} {:>8} {:>8} {:>8} {:>8} {:>10}",
        "submission", "grading", "build", "run", "reports", "time-outs"
    );
    for (name, r) in names.iter().zip(&rows) {
        let l = labs as f64;
        println!(
            "  {name:<16} {:>8.2} {:>8.2} {:>8.2} {:>8.3} {:>10.2}",
            per_lab(r),
            r[0] / l,
            r[1] / l,
            r[3] / l,
            r[2] / l
        );
    }
    // The first submission compiles the framework: the median of the others is the steady
    // state.
    let warm: Vec<&[f64; 4]> = rows.iter().skip(1).collect();
    let column = |i: usize| -> f64 {
        let mut v: Vec<f64> = warm.iter().map(|r| r[i] / labs as f64).collect();
        median(&mut v)
    };
    let mut grading: Vec<f64> = warm.iter().map(|r| per_lab(r)).collect();
    println!(
        "\nmedian after the first: {:.2} s of grading per submission per lab (build {:.2}, run {:.2}, reports {:.3}); goal 5 s",
        median(&mut grading),
        column(0),
        column(1),
        column(3)
    );
    if let Some(line) = printed.lines().find(|l| l.starts_with("graded ")) {
        println!("raylab grade: {line}");
    }
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
