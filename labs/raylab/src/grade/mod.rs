//! `raylab grade SUBMISSION... --out DIR`: grades each submission's `labs/labNN/src/` with the
//! course's own tests, golden data and snapshots, one exercise per process.
//!
//! Before the first submission, what every submission shares is built from the grading tree
//! (the handout with the hidden tests put back and the whole answer key, its labs the
//! handout's stubs): each graded lab's graded program (its checks with every key,
//! `grading::graded`, which holds no student code) and the crates a lab compiles against, with
//! the build jail around them ([`shared_build`], [`jail`]). Then, for each submission: the
//! graded labs' sources — regular files only ([`submission`]) — are scanned for what names
//! files outside the lab at compile time, a warning ([`scan`]), and each lab is compiled to a
//! WebAssembly module in the build jail, which holds its sources and nothing else of this
//! machine's ([`lab_build`], [`sandbox`]; a lab that does not compile is graded as failing, a
//! build the grader could not finish as not graded). Each lab's graded program runs every
//! exercise in a sandboxed process of its own with a time limit, calling the student's code
//! only inside its module, where it can address nothing of the program's; an exercise passes
//! only on the check's verdict record ([`runner`]). An exercise's files are gone when it ends,
//! but for the images the report keeps. After each submission the tree is verified against
//! its hashes. The results go to per-student reports and the class gradebooks ([`reports`]),
//! written when every student process has ended.

mod answers;
pub(crate) mod class;
mod feedback;
mod grades;
mod jail;
mod lab_build;
mod markdown;
mod progress;
mod reports;
mod runner;
pub(crate) mod rustc_record;
mod sandbox;
mod scan;
mod shared_build;
pub(crate) mod submission;
pub mod term;
mod tree;

use course::{ExerciseInfo, LabId};
use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};
use std::time::Duration;

use clap::Args;
use raylab_core::Error;

use crate::handout::{TreeOptions, build_tree, io, repository_root};
use class::{graded_labs, student_names};
use grades::{ExerciseGrade, Status, StudentGrade, Timings};
use lab_build::{Built, HostPaths, LabBuild};
use progress::{Progress, seconds};
use runner::ExerciseRun;
use sandbox::{Limits, RunAs, Sandbox};
use shared_build::{Shared, Workspace};
use tree::Manifest;

/// Options of `raylab grade`.
#[derive(Args, Clone, Debug)]
pub struct GradeArgs {
    /// Submission directories: each a copy of the handout with the student's work in it.
    #[arg(required = true)]
    pub submissions: Vec<PathBuf>,
    /// Directory for the reports, the gradebooks and the grading tree (`DIR/.grading`).
    #[arg(long)]
    pub out: PathBuf,
    /// Grade only this lab (repeatable; default: every lab).
    #[arg(long = "lab", value_name = "N")]
    pub labs: Vec<LabId>,
    /// Labs whose solution was released in the handout the students had (as given to
    /// `raylab handout`), so that those files are not reported as changed. The checks' base is
    /// always the whole answer key.
    #[arg(long, value_delimiter = ',')]
    pub release_solutions: Vec<LabId>,
    /// Cargo's target directory for the builds (default: `DIR/.grading/target`). Share one
    /// between gradings to compile the dependencies once, and the framework once per version of
    /// the course: gradings of different courses or versions in one directory do not mix up
    /// their programs.
    #[arg(long)]
    pub target_dir: Option<PathBuf>,
    /// Seconds an exercise may run before it is stopped and fails (an infinite loop).
    #[arg(long, default_value_t = 60)]
    pub timeout: u64,
    /// Address space an exercise's process may use, MiB (more fails it: "ran out of memory").
    #[arg(long, default_value_t = 4096)]
    pub memory_limit: u64,
    /// Seconds one compiler run of a submission's build may take (a run stopped at the limit
    /// is tried once more with twice the time; a second stop leaves the lab ungraded, not
    /// failed). The shared crates are built before any submission, without this limit.
    #[arg(long, default_value_t = 900)]
    pub build_timeout: u64,
    /// Run student code without the bubblewrap sandbox (where it cannot be installed). Student
    /// code then runs as your user, able to read and write what you can; every report says so.
    #[arg(long)]
    pub unsandboxed: bool,
    /// Build and run student code as this unprivileged user (a name or a user id) instead of
    /// in bubblewrap, for machines whose containers cannot make user namespaces (Gradescope's):
    /// needs root; each build is chrooted into the build jail, and nothing the user runs can
    /// write the grader's files.
    #[arg(long, value_name = "USER", conflicts_with = "unsandboxed")]
    pub run_as: Option<String>,
    /// Also write the one submission's Gradescope results to this file — and, should the
    /// submission not be graded at all, a result of 0 points that says why (Gradescope's
    /// `run_autograder`, written by `raylab gradescope`).
    #[arg(long, value_name = "FILE")]
    pub results_json: Option<PathBuf>,
    /// The course file (TOML): each lab's due date, late penalty, grace period and cap, the
    /// students' extensions and Canvas identities (docs/instructors.md, "Deadlines").
    #[arg(long, value_name = "FILE")]
    pub course: Option<PathBuf>,
    /// When a student submitted (repeatable): `STUDENT=2026-10-05T23:59:00+02:00`. Otherwise
    /// the time of the last git commit that changed the lab's sources or answers, if the
    /// submission is a git repository; with no such commit but the handout's own, "no
    /// submission" (never late).
    #[arg(long, value_name = "STUDENT=TIME")]
    pub submitted_at: Vec<String>,
    /// The students' submission times as CSV, columns `student,submitted_at`.
    #[arg(long, value_name = "FILE")]
    pub submission_times: Option<PathBuf>,
    /// Gradescope's submission metadata (`/autograder/submission_metadata.json`): the
    /// submission's time and due date, extensions included (`raylab gradescope` passes it).
    #[arg(long, value_name = "FILE")]
    pub gradescope_metadata: Option<PathBuf>,
    /// Points graded by hand, CSV with columns `student,lab,question,points,max_points,comment`,
    /// added to the lab's points, the reports and the gradebooks.
    #[arg(long, value_name = "FILE")]
    pub manual_points: Option<PathBuf>,
    /// Grade without scanning the sources (the hostile-submission test's proof that no
    /// guarantee rests on the scan: the build sees nothing but the submission either way).
    #[arg(long, hide = true)]
    pub no_scan: bool,
}

/// Runs `raylab grade`.
pub fn run(args: &GradeArgs) -> Result<(), Error> {
    // The grading tree's manifests name its own paths, which cargo reads relative to each
    // manifest: every directory is made absolute first.
    let absolute = |path: &Path| std::path::absolute(path).map_err(io(path));
    let args = &GradeArgs {
        out: absolute(&args.out)?,
        target_dir: args.target_dir.as_deref().map(absolute).transpose()?,
        ..args.clone()
    };
    let Some(results) = &args.results_json else {
        return grade_class(args);
    };
    if args.submissions.len() != 1 {
        return Err(Error::Invalid {
            what: format!("--results-json {}", results.display()),
            reason: format!(
                "expected one submission to write the results of, not {}",
                args.submissions.len()
            ),
        });
    }
    let outcome = grade_class(args);
    let graded = student_names(&args.submissions)
        .ok()
        .map(|names| args.out.join(&names[0]).join("results.json"))
        .filter(|path| outcome.is_ok() && path.is_file());
    match graded {
        Some(path) => crate::handout::copy_file(&path, results)?,
        None => {
            // The details are the grader's (on its output, which `main` prints): the student
            // is told that the grader failed, not where.
            let why = match &outcome {
                Ok(()) => "the grader wrote no results",
                Err(_) => {
                    "the grader failed before it could grade (its output says why); this is no mark of the code"
                }
            };
            let text = reports::ungraded_results(why);
            if let Some(dir) = results.parent() {
                fs::create_dir_all(dir).map_err(io(dir))?;
            }
            fs::write(results, text).map_err(io(results))?;
        }
    }
    outcome
}

/// Grades the class of `args`: reports per student and for the class.
fn grade_class(args: &GradeArgs) -> Result<(), Error> {
    let ClassInputs {
        labs,
        students,
        terms,
        times,
        gradescope,
        mut manual,
    } = ClassInputs::read(args)?;
    let sandbox = make_sandbox(args)?;
    let (handout, workspace) = prepare_workspace(args, sandbox)?;
    let trees = TreeSetup::new(args, &workspace.tag)?;
    build_tree(&repository_root(), &handout, &trees.options(false))?;
    let started = std::time::Instant::now();
    let bar = Progress::new(args.submissions.len());
    let class = ClassRun {
        args,
        labs: &labs,
        students: &students,
        terms: terms.as_ref(),
        times: &times,
        gradescope: gradescope.as_ref(),
        handout: &handout,
        workspace: &workspace,
        trees: &trees,
        bar: &bar,
    };
    let mut tree = class.build_shared()?;
    let mut grades = Vec::new();
    for (k, (submission, student)) in args.submissions.iter().zip(&students).enumerate() {
        grades.push(class.grade_student(k, submission, student, &mut manual, &mut tree)?);
        bar.submission_done();
    }
    class.write_reports(&grades, started)
}

/// What a class's grading reads and checks before anything is built.
struct ClassInputs {
    /// The graded labs.
    labs: Vec<LabId>,
    /// The students, one per submission.
    students: Vec<String>,
    /// The course's terms, if a course file is given.
    terms: Option<term::CourseTerms>,
    /// The submission times given.
    times: term::SubmissionTimes,
    /// Gradescope's submission metadata, if given.
    gradescope: Option<term::GradescopeSubmission>,
    /// The points graded by hand, per student.
    manual: std::collections::BTreeMap<String, Vec<term::ManualPoints>>,
}

impl ClassInputs {
    /// Reads the labs, the students, the course's terms, the times and the manual points.
    fn read(args: &GradeArgs) -> Result<Self, Error> {
        let labs = graded_labs(&args.labs)?;
        let students = student_names(&args.submissions)?;
        // The course's terms are read and checked before anything is built.
        let terms = args
            .course
            .as_deref()
            // On Gradescope (one submission, `--results-json`) extensions are Gradescope's: the
            // file's students are not the submission's folder.
            .map(|path| {
                term::CourseTerms::load(path, args.results_json.is_none().then_some(&students[..]))
            })
            .transpose()?;
        let times = term::SubmissionTimes::new(
            &args.submitted_at,
            args.submission_times.as_deref(),
            &students,
        )?;
        if let Some(path) = &args.gradescope_metadata
            && students.len() != 1
        {
            return Err(Error::Invalid {
                what: format!("--gradescope-metadata {}", path.display()),
                reason: format!(
                    "Gradescope's metadata is one submission's, not {}'s",
                    students.len()
                ),
            });
        }
        let gradescope = args
            .gradescope_metadata
            .as_deref()
            .map(term::GradescopeSubmission::load)
            .transpose()?;
        let manual = args
            .manual_points
            .as_deref()
            .map(|path| term::manual_points(path, &students, &labs))
            .transpose()?
            .unwrap_or_default();
        Ok(Self {
            labs,
            students,
            terms,
            times,
            gradescope,
            manual,
        })
    }
}

/// The sandbox that builds and runs student code, with the limits of `args`.
fn make_sandbox(args: &GradeArgs) -> Result<Sandbox, Error> {
    let memory = args.memory_limit << 20;
    let run_as = args.run_as.as_deref().map(RunAs::resolve).transpose()?;
    let sandbox = Sandbox::new(
        args.unsandboxed,
        run_as,
        Limits {
            memory,
            build_memory: memory.max(8 << 30),
            processes: 256,
            file_size: 64 << 20,
            build_file_size: 4 << 30,
            // Two threads may each use the whole wall-clock limit.
            cpu_seconds: 2 * args.timeout + 5,
            // The compiler's threads over a run and its retry at twice the time.
            build_cpu_seconds: 6 * args.build_timeout + 5,
        },
    )?;
    if !sandbox.is_sandboxed() {
        eprintln!(
            "warning: --unsandboxed: student code runs as your user and can read and write everything you can"
        );
    }
    Ok(sandbox)
}

/// The grading directory's handout and workspace, cleared of a previous grading's.
fn prepare_workspace(args: &GradeArgs, sandbox: Sandbox) -> Result<(PathBuf, Workspace), Error> {
    let grading = args.out.join(".grading");
    let handout = grading.join("handout");
    fs::create_dir_all(&grading).map_err(io(&grading))?;
    let place = fs::canonicalize(&grading).map_err(io(&grading))?;
    // One tag per grading directory: its builds never mix with those of the repository, a
    // handout, or another class's grading in a shared target directory.
    let tag = format!("{:08x}", fnv1a(&place.to_string_lossy()));
    let workspace = Workspace {
        tree: grading.join("tree"),
        // Absolute: cargo runs in the grading tree, the grader where it was started.
        target: std::path::absolute(
            args.target_dir
                .clone()
                .unwrap_or_else(|| grading.join("target")),
        )
        .map_err(io(&grading))?,
        runs: grading.join("runs"),
        jail: grading.join("jail"),
        tag: tag.clone(),
        sandbox,
        build_timeout: Duration::from_secs(args.build_timeout),
    };
    for dir in [&handout, &workspace.tree, &workspace.runs] {
        if dir.exists() {
            fs::remove_dir_all(dir).map_err(io(dir))?;
        }
    }
    Ok((handout, workspace))
}

/// How the handout and the grading tree are built from the repository.
struct TreeSetup {
    /// Labs whose solution was released in the handout.
    released: BTreeSet<LabId>,
    /// The grading directory's tag.
    tag: String,
    /// The framework's tag, by its content.
    framework_tag: String,
}

impl TreeSetup {
    /// The released labs of `args`, the grading's `tag` and the framework's digest.
    fn new(args: &GradeArgs, tag: &str) -> Result<Self, Error> {
        let released: BTreeSet<LabId> = args.release_solutions.iter().copied().collect();
        let framework_tag = format!(
            "framework.{}",
            Manifest::of(&repository_root().join("framework"))?.digest()
        );
        Ok(Self {
            released,
            tag: tag.to_string(),
            framework_tag,
        })
    }

    /// The options of the handout, or with `grading` of the grading tree.
    fn options(&self, grading: bool) -> TreeOptions {
        let tag = &self.tag;
        TreeOptions {
            released: self.released.clone(),
            answer_key: grading,
            version_tag: grading.then(|| format!("grading.{tag}")),
            // The framework by its content: gradings from the same framework share its build.
            framework_tag: grading.then(|| self.framework_tag.clone()),
        }
    }
}

/// The grading tree as built, and what the submissions share built from it.
struct GradingTree {
    /// The tree's hashes, to find what a submission changed.
    pristine: Manifest,
    /// The graded programs and the build jail.
    shared: Shared,
}

/// A class being graded, once its inputs are read and its workspace is prepared.
struct ClassRun<'a> {
    /// The options of `raylab grade`.
    args: &'a GradeArgs,
    /// The graded labs.
    labs: &'a [LabId],
    /// The students, one per submission.
    students: &'a [String],
    /// The course's terms.
    terms: Option<&'a term::CourseTerms>,
    /// The submission times given.
    times: &'a term::SubmissionTimes,
    /// Gradescope's submission metadata.
    gradescope: Option<&'a term::GradescopeSubmission>,
    /// The handout the submissions started from.
    handout: &'a Path,
    /// The grading tree and its builds.
    workspace: &'a Workspace,
    /// How the grading tree is built.
    trees: &'a TreeSetup,
    /// The progress shown while grading.
    bar: &'a Progress,
}

impl ClassRun<'_> {
    /// Builds the grading tree with the handout's stubs, and what every submission shares.
    fn make_tree(&self) -> Result<(Manifest, Shared), Error> {
        let workspace = self.workspace;
        if workspace.tree.exists() {
            fs::remove_dir_all(&workspace.tree).map_err(io(&workspace.tree))?;
        }
        build_tree(
            &repository_root(),
            &workspace.tree,
            &self.trees.options(true),
        )?;
        workspace.prepare()?;
        let shared = workspace.build_shared(self.labs)?;
        Ok((Manifest::of(&workspace.tree)?, shared))
    }

    /// Builds the grading tree before the first submission, on no submission's clock.
    fn build_shared(&self) -> Result<GradingTree, Error> {
        // The grading tree with the handout's stubs, and everything the submissions share built
        // from it: before the first submission's clock starts, so that no student pays for it.
        self.bar.doing(
            "building what every submission shares: the framework, the checks and the build jail"
                .into(),
            true,
        );
        let preparing = std::time::Instant::now();
        let (pristine, shared) = self.make_tree()?;
        self.bar.line(&format!(
            "built what every submission shares in {:.0} s (no submission's time)",
            preparing.elapsed().as_secs_f64()
        ));
        Ok(GradingTree { pristine, shared })
    }

    /// Grades the `k`th submission, adds its terms and writes its report.
    fn grade_student(
        &self,
        k: usize,
        submission: &Path,
        student: &str,
        manual: &mut std::collections::BTreeMap<String, Vec<term::ManualPoints>>,
        tree: &mut GradingTree,
    ) -> Result<StudentGrade, Error> {
        self.bar.doing(
            format!("grading {student} ({} of {})", k + 1, self.students.len()),
            true,
        );
        let dir = self.args.out.join(student);
        if dir.exists() {
            fs::remove_dir_all(&dir).map_err(io(&dir))?;
        }
        let mut grade = self.grade_or_ungraded(submission, student, &dir, &tree.shared);
        grade.sandbox = self.workspace.sandbox.describe();
        grade.manual = manual.remove(student).unwrap_or_default();
        grade.deadlines = term::deadlines(
            student,
            self.labs,
            self.terms,
            &|lab| self.times.of(student, submission, lab),
            self.gradescope,
        );
        self.verify_tree(&mut grade, tree)?;
        self.write_student_report(student, &mut grade, &dir)?;
        Ok(grade)
    }

    /// Grades one submission into `dir`, or as not graded when the grader fails on it.
    fn grade_or_ungraded(
        &self,
        submission: &Path,
        student: &str,
        dir: &Path,
        shared: &Shared,
    ) -> StudentGrade {
        let bar = self.bar;
        // One submission that cannot be graded costs that submission, not the class.
        let class = ClassGrading {
            handout: self.handout,
            workspace: self.workspace,
            shared,
            labs: self.labs,
            timeout: Duration::from_secs(self.args.timeout),
            scan: !self.args.no_scan,
            bar,
        };
        grade_submission(submission, student, dir, &class).unwrap_or_else(|e| {
            // The details, which may name places of this machine, are the instructor's.
            bar.warn(&format!("{student}: not graded: {e}"));
            StudentGrade::ungraded(
                student,
                self.labs,
                "the grader failed on it (the grader's output says why); this is no mark of the code",
            )
        })
    }

    /// Checks the grading tree after a submission, and rebuilds it if it changed.
    fn verify_tree(&self, grade: &mut StudentGrade, tree: &mut GradingTree) -> Result<(), Error> {
        // The sandbox keeps the tree read-only; should it change all the same (unsandboxed),
        // the submission is named and the next one gets a fresh tree.
        let changes = tree.pristine.changes(&self.workspace.tree)?;
        if !changes.is_empty() {
            grade.notes.push(format!(
                "the grading tree was changed while this submission ran ({}); it was rebuilt for the next submission",
                changes.join(", ")
            ));
            (tree.pristine, tree.shared) = self.make_tree()?;
        }
        Ok(())
    }

    /// Writes the student's reports into `dir` and shows the student's points.
    fn write_student_report(
        &self,
        student: &str,
        grade: &mut StudentGrade,
        dir: &Path,
    ) -> Result<(), Error> {
        let started = std::time::Instant::now();
        reports::write_student(grade, dir)?;
        grade.timings.report = started.elapsed().as_secs_f64();
        self.bar.line(&format!(
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
        Ok(())
    }

    /// Ends the progress, prints the summary and writes the class's reports.
    fn write_reports(
        &self,
        grades: &[StudentGrade],
        started: std::time::Instant,
    ) -> Result<(), Error> {
        let (args, bar) = (self.args, self.bar);
        bar.finish();
        println!("{}", summary(grades, started.elapsed()));
        reports::write_class(grades, &args.out, self.terms)?;
        println!(
            "reports in {}: index.html, gradebook.csv, canvas.csv, junit.xml, timings.csv, and per student report.md, report.html, results.json",
            args.out.display()
        );
        Ok(())
    }
}

/// The line that ends a grading run: how many submissions in how long, their mean points, and
/// how many exercises ended in each status.
fn summary(grades: &[StudentGrade], took: Duration) -> String {
    let mut counts = std::collections::BTreeMap::<String, usize>::new();
    for e in grades.iter().flat_map(|g| &g.exercises) {
        *counts.entry(e.status.label()).or_default() += 1;
    }
    let mean = grades.iter().map(StudentGrade::score).sum::<f64>() / grades.len().max(1) as f64;
    let max = grades.first().map_or(0.0, StudentGrade::max_score);
    let total = grades.iter().fold(Timings::default(), |sum, g| Timings {
        build: sum.build + g.timings.build,
        run: sum.run + g.timings.run,
        timed_out: sum.timed_out + g.timings.timed_out,
        report: sum.report + g.timings.report,
    });
    let labs = grades
        .first()
        .map_or(0, |g| {
            let mut labs: Vec<LabId> = g.exercises.iter().map(|e| e.info.lab).collect();
            labs.dedup();
            labs.len()
        })
        .max(1);
    let per = (grades.len().max(1) * labs) as f64;
    format!(
        "graded {} submission(s) in {:.0} s: mean {mean:.1}/{max} points; exercises {}\n\
         per submission and lab: {:.1} s of grading (build {:.1} s, run {:.1} s, reports {:.2} s) and {:.1} s in time-outs",
        grades.len(),
        took.as_secs_f64(),
        counts
            .iter()
            .map(|(label, n)| format!("{label} {n}"))
            .collect::<Vec<_>>()
            .join(", "),
        total.machine() / per,
        total.build / per,
        total.run / per,
        total.report / per,
        total.timed_out / per,
    )
}

/// 32-bit FNV-1a hash of `text`: stable across runs and toolchains.
fn fnv1a(text: &str) -> u32 {
    text.bytes().fold(0x811c_9dc5, |h, b| {
        (h ^ u32::from(b)).wrapping_mul(0x0100_0193)
    })
}

/// What every submission of a class is graded with.
#[derive(Clone, Copy)]
struct ClassGrading<'a> {
    /// The handout the submissions started from.
    handout: &'a Path,
    /// The grading tree and its builds.
    workspace: &'a Workspace,
    /// What the submissions share: the graded programs, the build jail.
    shared: &'a Shared,
    /// The graded labs.
    labs: &'a [LabId],
    /// The time limit of one exercise.
    timeout: Duration,
    /// Whether the sources are scanned (a warning for what the build could not read anyway,
    /// and the framework items that answer an exercise).
    scan: bool,
    /// The progress shown while grading.
    bar: &'a Progress,
}

/// Grades one submission into `dir` (its images go to `dir/images/`).
fn grade_submission(
    submission: &Path,
    student: &str,
    dir: &Path,
    class: &ClassGrading,
) -> Result<StudentGrade, Error> {
    let mut record = SubmissionRecord::default();
    let changed_files = submission::changed_files(submission, class.handout)?;
    let grading = SubmissionGrading {
        submission,
        student,
        dir,
        runs: class.workspace.runs.join(student),
        class: *class,
    };
    grading.compile_labs(&mut record)?;
    let exercises = grading.run_exercises(&mut record)?;
    // The student's sources, modules and runs: nothing is left behind.
    let runs = &grading.runs;
    if runs.exists() {
        fs::remove_dir_all(runs).map_err(io(runs))?;
    }
    Ok(StudentGrade {
        student: student.to_string(),
        exercises,
        changed_files,
        notes: record.notes,
        rejected: record.rejected,
        flagged: record.flagged,
        sandbox: String::new(),
        timings: record.timings,
        answers: record.written,
        deadlines: Vec::new(),
        manual: Vec::new(),
    })
}

/// One submission being graded: whose it is, and where its files go.
struct SubmissionGrading<'a> {
    /// The submission directory.
    submission: &'a Path,
    /// The student's name.
    student: &'a str,
    /// The student's report directory.
    dir: &'a Path,
    /// The student's sources, modules and runs in the grading directory.
    runs: PathBuf,
    /// What every submission of the class is graded with.
    class: ClassGrading<'a>,
}

/// What grading one submission gathers on its way to the report.
#[derive(Default)]
struct SubmissionRecord {
    /// Other remarks (a lab's sources missing).
    notes: Vec<String>,
    /// Entries of the sources and answers that were not taken.
    rejected: Vec<String>,
    /// Source lines the scan warns of.
    flagged: Vec<String>,
    /// Where the grading spent its time.
    timings: Timings,
    /// The labs whose exercises cannot run, with their status and why.
    broken: std::collections::BTreeMap<LabId, (Status, String)>,
    /// Exercises whose answer the code takes from the framework, with where.
    answered: std::collections::BTreeMap<String, Vec<String>>,
    /// The written answers of the graded labs.
    written: Vec<answers::LabAnswers>,
}

/// A lab's graded program, ready to run the lab's exercises on the student's module.
struct LabProgram<'a> {
    /// The lab's graded program.
    executable: &'a Path,
    /// The student's code of the lab, compiled for the graded program.
    module: PathBuf,
    /// The lab's directory in the grading tree.
    lab_dir: PathBuf,
    /// The graded program's test names.
    tests: Vec<String>,
}

impl SubmissionGrading<'_> {
    /// Takes each graded lab's sources and answers and compiles its code in the build jail.
    fn compile_labs(&self, record: &mut SubmissionRecord) -> Result<(), Error> {
        let ClassGrading {
            workspace,
            shared,
            labs,
            ..
        } = self.class;
        // Only the graded labs' code is built: every other slot of every check is the answer
        // key, so one lab's code never costs points in another. Each lab is compiled in the
        // build jail, which holds its sources and nothing else of this machine's.
        let private = [
            workspace.sandbox.cargo_home().to_path_buf(),
            workspace.runs.clone(),
            workspace.jail.clone(),
        ];
        let builder = LabBuild {
            sandbox: &workspace.sandbox,
            jail: &shared.jail,
            host: HostPaths {
                tree: &workspace.tree,
                target: &workspace.target,
                private: &private,
            },
            timeout: workspace.build_timeout,
            memory: workspace.sandbox.build_memory_limit(),
        };
        for &lab in labs {
            let staged = self.runs.join("sources");
            self.take_lab(lab, &staged, record)?;
            self.compile_lab(&builder, lab, &staged, record)?;
        }
        Ok(())
    }

    /// Stages the lab's sources in `staged`, reads its answers, and scans its sources.
    fn take_lab(
        &self,
        lab: LabId,
        staged: &Path,
        record: &mut SubmissionRecord,
    ) -> Result<(), Error> {
        let (submission, handout) = (self.submission, self.class.handout);
        let intake = submission::install_lab_code(Some(submission), handout, staged, lab)?;
        record.notes.extend(intake.missing);
        record.rejected.extend(intake.rejected);
        match submission::read_answers(submission, lab) {
            Ok(Some(text)) => {
                let mut lab_answers = answers::LabAnswers::read(lab, &text);
                record
                    .rejected
                    .extend(lab_answers.take_images(submission, self.dir)?);
                record.written.push(lab_answers);
            }
            Ok(None) => {}
            Err(line) => record.rejected.push(line),
        }
        if self.class.scan {
            // A warning: the build could not read such a file anyway.
            let scan::LabScan { flags, denied } =
                scan::scan_lab(staged, lab, course::lab(lab).map_or(&[][..], |l| &l.denied));
            record.flagged.extend(flags);
            for denied in denied {
                for id in denied.exercises {
                    record
                        .answered
                        .entry(id.clone())
                        .or_default()
                        .push(denied.line.clone());
                }
                record.flagged.push(denied.line);
            }
        }
        Ok(())
    }

    /// Compiles the lab's staged sources to a module; a lab that does not build is noted broken.
    fn compile_lab(
        &self,
        builder: &LabBuild,
        lab: LabId,
        staged: &Path,
        record: &mut SubmissionRecord,
    ) -> Result<(), Error> {
        let (student, bar, shared) = (self.student, self.class.bar, self.class.shared);
        bar.doing(format!("{student}: compiling labs/{lab}/src"), false);
        let started = std::time::Instant::now();
        let module = self.runs.join(format!("{lab}.wasm"));
        let calls = shared.calls.get(&lab).ok_or_else(|| Error::Failed {
            what: format!("lab {lab}"),
            reason: "the shared build has no compiler record of it".into(),
        })?;
        let built = builder.build(lab, calls, &staged.join(format!("labs/{lab}/src")), &module)?;
        let took = started.elapsed().as_secs_f64();
        record.timings.build += took;
        bar.logged(|| {
            let outcome = match &built {
                Built::Module => "compiled",
                Built::DoesNotCompile(_) => "does not compile: its exercises fail",
                Built::NotGraded(_) => "not graded (the grader's limit): its exercises score 0",
            };
            format!("{student}: labs/{lab}/src {outcome} ({})", seconds(took))
        });
        match built {
            Built::Module => {}
            Built::DoesNotCompile(errors) => {
                record.broken.insert(
                    lab,
                    (
                        Status::DoesNotCompile,
                        format!("labs/{lab}/src does not compile:\n{errors}"),
                    ),
                );
            }
            Built::NotGraded(why) => {
                record.broken.insert(
                    lab,
                    (
                        Status::NotGraded,
                        format!("labs/{lab}/src was not graded: {why}"),
                    ),
                );
            }
        }
        Ok(())
    }

    /// Grades every exercise of the graded labs, lab by lab.
    fn run_exercises(&self, record: &mut SubmissionRecord) -> Result<Vec<ExerciseGrade>, Error> {
        let mut exercises = Vec::new();
        for &lab in self.class.labs {
            exercises.extend(self.grade_lab(lab, record)?);
        }
        Ok(exercises)
    }

    /// Grades the exercises of one lab: all failed when its code did not build.
    fn grade_lab(
        &self,
        lab: LabId,
        record: &mut SubmissionRecord,
    ) -> Result<Vec<ExerciseGrade>, Error> {
        let shared = self.class.shared;
        let infos = crate::labs::exercises(lab);
        let executable = match (record.broken.get(&lab), shared.programs.get(&lab)) {
            (Some((status, why)), _) => {
                return Ok(infos
                    .into_iter()
                    .map(|i| ExerciseGrade::failed(i, status.clone(), why.clone()))
                    .collect());
            }
            (None, None) => {
                return Err(Error::Failed {
                    what: format!("lab {lab}"),
                    reason: "the shared build has no graded program of it".into(),
                });
            }
            (None, Some(executable)) => executable,
        };
        let program = self.prepare_lab(lab, executable, &mut record.timings)?;
        let mut exercises = Vec::new();
        for info in infos {
            exercises.push(self.grade_exercise(lab, &program, info, record)?);
        }
        Ok(exercises)
    }

    /// Lists the graded program's tests and compiles the student's module for it.
    fn prepare_lab<'p>(
        &self,
        lab: LabId,
        executable: &'p Path,
        timings: &mut Timings,
    ) -> Result<LabProgram<'p>, Error> {
        let (workspace, runs) = (self.class.workspace, &self.runs);
        let lab_dir = workspace.tree.join(format!("labs/{lab}"));
        let started = std::time::Instant::now();
        let tests = runner::list_tests(
            &workspace.sandbox,
            executable,
            &lab_dir,
            &runs.join(format!("list-{lab}")),
        )?;
        let listing = runs.join(format!("list-{lab}"));
        fs::remove_dir_all(&listing).map_err(io(&listing))?;
        let module = runner::precompile(
            &workspace.sandbox,
            executable,
            &lab_dir,
            &runs.join(format!("compile-{lab}")),
            &runs.join(format!("{lab}.wasm")),
        )?;
        timings.run += started.elapsed().as_secs_f64();
        Ok(LabProgram {
            executable,
            module,
            lab_dir,
            tests,
        })
    }

    /// Grades one exercise: flagged or not graded without running, else by its check's run.
    fn grade_exercise(
        &self,
        lab: LabId,
        program: &LabProgram,
        info: ExerciseInfo,
        record: &mut SubmissionRecord,
    ) -> Result<ExerciseGrade, Error> {
        let (student, bar) = (self.student, self.class.bar);
        if let Some(lines) = record.answered.get(info.id.as_str()) {
            let why = format!(
                "no points: the code names framework items that compute what Exercise {} asks, instead of computing it:\n{}",
                info.id,
                lines.join("\n")
            );
            bar.logged(|| format!("{student}: Exercise {} flagged (not run)", info.id));
            return Ok(ExerciseGrade::failed(info, Status::Flagged, why));
        }
        let Some(test) = program
            .tests
            .iter()
            .find(|t| t.starts_with(&info.test_prefix()))
        else {
            let why = format!(
                "the checks have no test {}… for Exercise {}",
                info.test_prefix(),
                info.id
            );
            bar.logged(|| format!("{student}: Exercise {} not graded: {why}", info.id));
            return Ok(ExerciseGrade::failed(info, Status::NotGraded, why));
        };
        self.run_exercise(lab, program, test, info, &mut record.timings)
    }

    /// Runs the exercise's test in the sandbox and keeps the images its check wrote.
    fn run_exercise(
        &self,
        lab: LabId,
        program: &LabProgram,
        test: &str,
        info: ExerciseInfo,
        timings: &mut Timings,
    ) -> Result<ExerciseGrade, Error> {
        let (student, bar, workspace) = (self.student, self.class.bar, self.class.workspace);
        let scratch = self.runs.join(&info.id);
        if scratch.exists() {
            fs::remove_dir_all(&scratch).map_err(io(&scratch))?;
        }
        let how = ExerciseRun {
            sandbox: &workspace.sandbox,
            executable: program.executable,
            module: &program.module,
            lab_dir: &program.lab_dir,
            scratch: &scratch,
            timeout: self.class.timeout,
            memory_limit: workspace.sandbox.memory_limit(),
        };
        bar.doing(format!("{student}: Exercise {}", info.id), false);
        let run = runner::run_exercise(&how, test, &info)?;
        bar.logged(|| {
            format!(
                "{student}: Exercise {} {} ({})",
                info.id,
                run.status.label(),
                seconds(run.seconds)
            )
        });
        timings.timed_out += run.stopped_seconds;
        timings.run += run.seconds - run.stopped_seconds;
        let images = self.keep_images(lab, &info, &run.images)?;
        // Nothing of a run outlives it but what the report keeps.
        fs::remove_dir_all(&scratch).map_err(io(&scratch))?;
        Ok(ExerciseGrade {
            score: if run.status == Status::Passed {
                info.points
            } else {
                0
            },
            info,
            status: run.status,
            output: run.output,
            program_output: run.program_output,
            images,
            seconds: run.seconds,
            key_for: run.key_for,
        })
    }

    /// Copies an exercise's images into the report's `images/` directory, named by exercise.
    fn keep_images(
        &self,
        lab: LabId,
        info: &ExerciseInfo,
        run_images: &[PathBuf],
    ) -> Result<Vec<PathBuf>, Error> {
        let mut images = Vec::new();
        for image in run_images {
            let name = format!(
                "{}-{}",
                info.id,
                image.file_name().unwrap_or_default().to_string_lossy()
            );
            let relative = PathBuf::from("images").join(format!("{lab}")).join(name);
            crate::handout::copy_file(image, &self.dir.join(&relative))?;
            images.push(relative);
        }
        Ok(images)
    }
}
