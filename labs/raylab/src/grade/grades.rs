//! What grading found: each exercise's status, points and output, each submission's grades,
//! and where its grading spent its time.

use std::path::{Path, PathBuf};

use course::LabId;
use grading::{ExerciseInfo, FailureKind};

use super::answers;
use super::term;

/// What became of one exercise in grading.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Status {
    /// The check accepted the student's code.
    Passed,
    /// The check ran to its end and rejected the answer.
    Wrong,
    /// The exercise's stub is unfinished (`todo!()`).
    NotStarted,
    /// The check met the unfinished stub of another exercise, this one.
    BlockedBy(String),
    /// The student's code panicked, or the test process crashed, ran out of memory or ended
    /// without a verdict.
    Crashed,
    /// The test ran past its time limit (wall clock or CPU time).
    TimedOut,
    /// The lab's code does not compile (or not as the course's contract).
    DoesNotCompile,
    /// The exercise's code names framework code that answers it.
    Flagged,
    /// The submission or this lab could not be graded: the grader's failure (a build stopped at
    /// its time or resource limit, the sources missing), scored 0 and named as such, never as
    /// the student's mistake.
    NotGraded,
}

impl Status {
    /// The status as the reports write it.
    pub fn label(&self) -> String {
        match self {
            Self::Passed => "passed".into(),
            Self::Wrong => "wrong".into(),
            Self::NotStarted => "not started".into(),
            Self::BlockedBy(other) => format!("blocked by {other}"),
            Self::Crashed => "crashed".into(),
            Self::TimedOut => "timed out".into(),
            Self::DoesNotCompile => "does not compile".into(),
            Self::Flagged => "flagged".into(),
            Self::NotGraded => "not graded".into(),
        }
    }

    /// The status of a check that did not accept the student's code, by its record's kind.
    pub fn of_failure(kind: Option<&FailureKind>) -> Self {
        match kind {
            Some(FailureKind::NotStarted) => Self::NotStarted,
            Some(FailureKind::Blocked(other)) => Self::BlockedBy(other.clone()),
            Some(FailureKind::Waiting(lab)) => Self::BlockedBy(format!("lab {lab}'s solution")),
            Some(FailureKind::Crashed) => Self::Crashed,
            Some(FailureKind::TimedOut) => Self::TimedOut,
            Some(FailureKind::Wrong) | None => Self::Wrong,
        }
    }
}

/// The grade of one exercise.
pub struct ExerciseGrade {
    /// Which exercise.
    pub info: ExerciseInfo,
    /// What became of it.
    pub status: Status,
    /// Points earned.
    pub score: u32,
    /// Why it failed, or empty (the grader's words, or the check's).
    pub output: String,
    /// What the student's code printed while it ran (cut), apart from the verdict.
    pub program_output: String,
    /// Images of the failing check, relative to the student's report directory.
    pub images: Vec<PathBuf>,
    /// Wall time of its test.
    pub seconds: f64,
    /// The exercises whose functions were the answer key's, not the student's, in the run that
    /// decided it (their own exercises fail, and are charged there).
    pub key_for: Vec<String>,
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
    /// Entries of `labs/labNN/src/` that were not taken (links, special files, too large).
    pub rejected: Vec<String>,
    /// Source lines that read files outside their lab at compile time.
    pub flagged: Vec<String>,
    /// How the student's code was isolated (the sandbox and its limits).
    pub sandbox: String,
    /// Where the grading of this submission spent its time.
    pub timings: Timings,
    /// The written answers of the graded labs that have an answers file.
    pub answers: Vec<answers::LabAnswers>,
    /// The due date and lateness of each graded lab that has a due date.
    pub deadlines: Vec<term::LabDeadline>,
    /// Points graded by hand, per lab and question.
    pub manual: Vec<term::ManualPoints>,
}

/// Wall-clock seconds the grading of one submission spent, by kind of work.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timings {
    /// Compiling the student's labs and linking the checks.
    pub build: f64,
    /// Running the exercises that ended within the grader's time limits (and listing the tests).
    pub run: f64,
    /// Running the exercises that were stopped at the grader's time limits.
    pub timed_out: f64,
    /// Writing the submission's reports.
    pub report: f64,
}

impl Timings {
    /// The grader's own time: everything but the time-outs.
    pub fn machine(&self) -> f64 {
        self.build + self.run + self.report
    }
}

impl StudentGrade {
    /// Points earned: every lab's, after its late penalty.
    pub fn score(&self) -> f64 {
        term::round_points(self.labs().iter().map(|&lab| self.lab_score(lab)).sum())
    }

    /// Points available: the exercises' and the questions graded by hand.
    pub fn max_score(&self) -> f64 {
        self.labs().iter().map(|&lab| self.lab_max(lab)).sum()
    }

    /// The graded labs, in order.
    pub fn labs(&self) -> Vec<LabId> {
        let mut labs: Vec<LabId> = self.exercises.iter().map(|e| e.info.lab).collect();
        labs.extend(self.manual.iter().map(|m| m.lab));
        labs.sort_unstable();
        labs.dedup();
        labs
    }

    /// Points earned in `lab` before its late penalty: its exercises' and its questions'.
    pub fn lab_earned(&self, lab: LabId) -> f64 {
        let exercises: u32 = self
            .exercises
            .iter()
            .filter(|e| e.info.lab == lab)
            .map(|e| e.score)
            .sum();
        let manual: f64 = self
            .manual
            .iter()
            .filter(|m| m.lab == lab)
            .map(|m| m.points)
            .sum();
        f64::from(exercises) + manual
    }

    /// Points available in `lab`.
    pub fn lab_max(&self, lab: LabId) -> f64 {
        let exercises: u32 = self
            .exercises
            .iter()
            .filter(|e| e.info.lab == lab)
            .map(|e| e.info.points)
            .sum();
        let manual: f64 = self
            .manual
            .iter()
            .filter(|m| m.lab == lab)
            .map(|m| m.max_points)
            .sum();
        f64::from(exercises) + manual
    }

    /// `lab`'s due date and lateness, if it has a due date.
    pub fn deadline(&self, lab: LabId) -> Option<&term::LabDeadline> {
        self.deadlines.iter().find(|d| d.lab == lab)
    }

    /// Points `lab` loses for lateness: its penalty's fraction of the lab's points, at most
    /// what it earned.
    pub fn lab_penalty(&self, lab: LabId) -> f64 {
        let fraction = self.deadline(lab).map_or(0.0, |d| d.lateness.fraction());
        term::round_points((fraction * self.lab_max(lab)).min(self.lab_earned(lab)))
    }

    /// Points earned in `lab` after its late penalty.
    pub fn lab_score(&self, lab: LabId) -> f64 {
        term::round_points(self.lab_earned(lab) - self.lab_penalty(lab))
    }

    /// The grade of a submission that could not be graded: every exercise of `labs` failed,
    /// with `why`.
    pub(super) fn ungraded(student: &str, labs: &[LabId], why: &str) -> Self {
        let reason = format!("the submission could not be graded: {why}");
        let exercises = labs
            .iter()
            .flat_map(|&lab| crate::labs::exercises(lab))
            .map(|info| ExerciseGrade::failed(info, Status::NotGraded, reason.clone()))
            .collect();
        Self {
            student: student.to_string(),
            exercises,
            changed_files: Vec::new(),
            notes: vec![reason],
            rejected: Vec::new(),
            flagged: Vec::new(),
            sandbox: String::new(),
            timings: Timings::default(),
            answers: Vec::new(),
            deadlines: Vec::new(),
            manual: Vec::new(),
        }
    }
}

impl ExerciseGrade {
    /// Whether it passed.
    pub fn passed(&self) -> bool {
        self.status == Status::Passed
    }

    /// A failed exercise that did not run, with its status and `why`.
    pub(super) fn failed(info: ExerciseInfo, status: Status, why: String) -> Self {
        Self {
            info,
            status,
            score: 0,
            output: why,
            program_output: String::new(),
            images: Vec::new(),
            seconds: 0.0,
            key_for: Vec::new(),
        }
    }
}

/// "student", "reference" or "difference", from a failure image's file name.
pub(super) fn image_caption(image: &Path) -> String {
    let stem = image.file_stem().unwrap_or_default().to_string_lossy();
    stem.rsplit('-').next().unwrap_or_default().to_string()
}
