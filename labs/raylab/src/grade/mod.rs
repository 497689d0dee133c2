//! `raylab grade SUBMISSION... --out DIR`: grades each submission's `labs/labNN/src/` with the
//! course's own tests, golden data and snapshots, one exercise per process.
//!
//! For each submission: its lab sources go into the grading tree (the handout with the hidden
//! tests put back, so no unreleased solution is on disk), each lab is compiled (a lab that does
//! not compile is graded as failing and replaced by its stubs so the others still build), the
//! checks are built once, and every exercise's test runs in a process of its own with a time
//! limit. The results go to per-student reports and the class gradebooks ([`reports`]).

mod reports;
mod runner;
mod scan;
mod submission;

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};
use std::time::Duration;

use clap::Args;
use framework::Error;
use framework::grading::ExerciseInfo;
use indicatif::{ProgressBar, ProgressStyle};

use crate::handout::{TreeOptions, build_tree, io, repository_root};
use runner::Workspace;

/// Options of `raylab grade`.
#[derive(Args, Debug)]
pub struct GradeArgs {
    /// Submission directories: each a copy of the handout with the student's work in it.
    #[arg(required = true)]
    pub submissions: Vec<PathBuf>,
    /// Directory for the reports, the gradebooks and the grading tree (`DIR/.grading`).
    #[arg(long)]
    pub out: PathBuf,
    /// Grade only this lab (repeatable; default: every lab).
    #[arg(long = "lab")]
    pub labs: Vec<u32>,
    /// Labs whose solution is released: the base the other labs' exercises run in (as in the
    /// handout the students had). Labs not released use the student's own code there.
    #[arg(long, value_delimiter = ',')]
    pub release_solutions: Vec<u32>,
    /// Cargo's target directory for the builds (default: `DIR/.grading/target`). It may be
    /// shared with other builds of the same toolchain to save compiling the dependencies again:
    /// the grading tree's crates carry a version of their own (see `TreeOptions::version_tag`).
    #[arg(long)]
    pub target_dir: Option<PathBuf>,
    /// Seconds an exercise may run before it is stopped and fails (an infinite loop).
    #[arg(long, default_value_t = 60)]
    pub timeout: u64,
}

/// The grade of one exercise.
pub struct ExerciseGrade {
    /// Which exercise.
    pub info: ExerciseInfo,
    /// Whether it passed.
    pub passed: bool,
    /// Points earned.
    pub score: u32,
    /// Why it failed, or empty.
    pub output: String,
    /// Images of the failing check, relative to the student's report directory.
    pub images: Vec<PathBuf>,
    /// Wall time of its test.
    pub seconds: f64,
}

/// The grades of one submission.
pub struct StudentGrade {
    /// The submission directory's name.
    pub student: String,
    /// One entry per exercise of the graded labs, in order.
    pub exercises: Vec<ExerciseGrade>,
    /// Files outside `labs/labNN/src/` that differ from the handout (ignored for grading).
    pub changed_files: Vec<String>,
    /// Other remarks (a lab's sources missing, a lab that did not compile).
    pub notes: Vec<String>,
}

impl StudentGrade {
    /// Points earned.
    pub fn score(&self) -> u32 {
        self.exercises.iter().map(|e| e.score).sum()
    }

    /// Points available.
    pub fn max_score(&self) -> u32 {
        self.exercises.iter().map(|e| e.info.points).sum()
    }
}

/// Runs `raylab grade`.
pub fn run(args: &GradeArgs) -> Result<(), Error> {
    let labs = graded_labs(&args.labs)?;
    let students = student_names(&args.submissions)?;
    let grading = args.out.join(".grading");
    let handout = grading.join("handout");
    let workspace = Workspace {
        tree: grading.join("tree"),
        target: args
            .target_dir
            .clone()
            .unwrap_or_else(|| grading.join("target")),
        runs: grading.join("runs"),
    };
    for dir in [&handout, &workspace.tree, &workspace.runs] {
        if dir.exists() {
            fs::remove_dir_all(dir).map_err(io(dir))?;
        }
    }
    let released: BTreeSet<u32> = args.release_solutions.iter().copied().collect();
    if let Some(lab) = labs.iter().find(|l| released.contains(l)) {
        return Err(Error::Invalid {
            what: format!("--release-solutions {released:?}"),
            reason: format!(
                "lab {lab} is being graded: its solution must not be on disk while student code runs; release only the labs it builds on"
            ),
        });
    }
    fs::create_dir_all(&grading).map_err(io(&grading))?;
    let place = fs::canonicalize(&grading).map_err(io(&grading))?;
    let options = |hidden_tests| TreeOptions {
        released: released.clone(),
        hidden_tests,
        // One tag per grading directory: its builds never mix with those of the repository, a
        // handout, or another class's grading in a shared target directory.
        version_tag: hidden_tests
            .then(|| format!("grading.{:08x}", fnv1a(&place.to_string_lossy()))),
    };
    build_tree(&repository_root(), &handout, &options(false))?;
    build_tree(&repository_root(), &workspace.tree, &options(true))?;

    let bar = ProgressBar::new(args.submissions.len() as u64).with_style(
        ProgressStyle::with_template("grading {bar:30} {pos}/{len} {msg}")
            .expect("the progress template is valid"),
    );
    let mut grades = Vec::new();
    for (submission, student) in args.submissions.iter().zip(&students) {
        bar.set_message(student.clone());
        let dir = args.out.join(student);
        if dir.exists() {
            fs::remove_dir_all(&dir).map_err(io(&dir))?;
        }
        let grade = grade_submission(
            submission,
            student,
            &handout,
            &workspace,
            &labs,
            &dir,
            Duration::from_secs(args.timeout),
        )?;
        reports::write_student(&grade, &dir)?;
        bar.println(format!(
            "{student}: {}/{} points{}",
            grade.score(),
            grade.max_score(),
            if grade.changed_files.is_empty() {
                String::new()
            } else {
                format!(
                    " ({} file(s) outside labs/*/src changed, ignored)",
                    grade.changed_files.len()
                )
            }
        ));
        grades.push(grade);
        bar.inc(1);
    }
    bar.finish_and_clear();
    reports::write_class(&grades, &args.out)?;
    println!(
        "reports in {}: index.html, gradebook.csv, junit.xml, and per student report.md, report.html, results.json",
        args.out.display()
    );
    Ok(())
}

/// 32-bit FNV-1a hash of `text`: stable across runs and toolchains.
fn fnv1a(text: &str) -> u32 {
    text.bytes().fold(0x811c_9dc5, |h, b| {
        (h ^ u32::from(b)).wrapping_mul(0x0100_0193)
    })
}

/// The labs to grade: `requested`, or every lab; each must be a lab of the course.
fn graded_labs(requested: &[u32]) -> Result<Vec<u32>, Error> {
    if requested.is_empty() {
        return Ok(crate::students::labs().to_vec());
    }
    let mut labs = requested.to_vec();
    labs.sort_unstable();
    labs.dedup();
    for &lab in &labs {
        crate::students::check_lab(lab)?;
    }
    Ok(labs)
}

/// The name of each submission (its directory's name); each must be a directory, and the
/// names must differ.
fn student_names(submissions: &[PathBuf]) -> Result<Vec<String>, Error> {
    let mut names = Vec::new();
    for path in submissions {
        if !path.is_dir() {
            return Err(Error::Invalid {
                what: format!("submission {}", path.display()),
                reason: "expected a directory (a copy of the handout; unpack archives first)"
                    .into(),
            });
        }
        let name = fs::canonicalize(path)
            .map_err(io(path))?
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let name: String = name
            .chars()
            .map(|c| {
                if c.is_alphanumeric() || "-_.".contains(c) {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        if name.is_empty() || name.starts_with('.') || names.contains(&name) {
            return Err(Error::Invalid {
                what: format!("submission {}", path.display()),
                reason: format!(
                    "its directory name {name:?} must be unique among the submissions and not start with '.'"
                ),
            });
        }
        names.push(name);
    }
    Ok(names)
}

/// Grades one submission into `dir` (its images go to `dir/images/`).
fn grade_submission(
    submission: &Path,
    student: &str,
    handout: &Path,
    workspace: &Workspace,
    labs: &[u32],
    dir: &Path,
    timeout: Duration,
) -> Result<StudentGrade, Error> {
    let mut notes = Vec::new();
    let changed_files = submission::changed_files(submission, handout)?;

    // Every lab's code goes in, graded or not: the labs whose solutions are not released are
    // the base of the others.
    let mut broken = std::collections::BTreeMap::new();
    for &lab in crate::students::labs() {
        let intake = submission::install_lab_code(Some(submission), handout, &workspace.tree, lab)?;
        notes.extend(intake.missing);
        notes.extend(intake.rejected);
        if let Err(errors) = workspace.build_lib(&format!("lab{lab:02}"))? {
            broken.insert(lab, errors);
        }
    }
    // The base pipeline uses the `Student` of every lab not released: one that compiles but no
    // longer fits its contract breaks the base, and is replaced by its stubs too.
    if let Err(errors) = workspace.build_lib("reference")? {
        for &lab in crate::students::labs() {
            if errors.contains(&format!("lab{lab:02}")) {
                broken.entry(lab).or_insert_with(|| errors.clone());
            }
        }
    }
    for &lab in broken.keys() {
        notes.push(format!(
            "labs/lab{lab:02}/src does not compile with the framework; its exercises fail and the other labs use its stubs"
        ));
        submission::install_stubs(handout, &workspace.tree, lab)?;
    }
    let to_build: Vec<u32> = labs
        .iter()
        .copied()
        .filter(|l| !broken.contains_key(l))
        .collect();
    let build = workspace.build_checks(&to_build)?;

    let mut exercises = Vec::new();
    for &lab in labs {
        let infos = framework::labs::exercise_infos(lab).unwrap_or_default();
        let failure = |info: ExerciseInfo, output: String| ExerciseGrade {
            info,
            passed: false,
            score: 0,
            output,
            images: Vec::new(),
            seconds: 0.0,
        };
        let executable = match (broken.get(&lab), build.executables.get(&lab)) {
            (Some(errors), _) => {
                let why = format!("labs/lab{lab:02}/src does not compile:\n{errors}");
                exercises.extend(infos.into_iter().map(|i| failure(i, why.clone())));
                continue;
            }
            (None, None) => {
                let errors = build.errors.get(&lab).cloned().unwrap_or_default();
                let why = format!(
                    "the lab's checks do not compile against labs/lab{lab:02}/src (was a public item renamed or removed?):\n{errors}"
                );
                exercises.extend(infos.into_iter().map(|i| failure(i, why.clone())));
                continue;
            }
            (None, Some(executable)) => executable,
        };
        let tests = runner::list_tests(executable)?;
        for info in infos {
            let Some(test) = tests.iter().find(|t| t.starts_with(&info.test_prefix())) else {
                let why = format!(
                    "the checks have no test {}… for Exercise {}",
                    info.test_prefix(),
                    info.id
                );
                exercises.push(failure(info, why));
                continue;
            };
            let scratch = workspace.runs.join(student).join(info.id);
            if scratch.exists() {
                fs::remove_dir_all(&scratch).map_err(io(&scratch))?;
            }
            let run = runner::run_exercise(executable, test, &info, &scratch, timeout)?;
            let mut images = Vec::new();
            for image in &run.images {
                let name = format!(
                    "{}-{}",
                    info.id,
                    image.file_name().unwrap_or_default().to_string_lossy()
                );
                let relative = PathBuf::from("images")
                    .join(format!("lab{lab:02}"))
                    .join(name);
                crate::handout::copy_file(image, &dir.join(&relative))?;
                images.push(relative);
            }
            exercises.push(ExerciseGrade {
                score: if run.passed { info.points } else { 0 },
                info,
                passed: run.passed,
                output: run.output,
                images,
                seconds: run.seconds,
            });
        }
    }
    Ok(StudentGrade {
        student: student.to_string(),
        exercises,
        changed_files,
        notes,
    })
}
