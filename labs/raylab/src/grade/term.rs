//! The course's term as `raylab grade` applies it: the course file (`--course`: due dates, late
//! penalties, grace periods, caps, per-student extensions, the students' Canvas identities),
//! each submission's time (given, a git commit's, or Gradescope's), and what lateness costs.
//!
//! A lab submitted after its due date (the student's extension, if any) loses
//! `penalty_per_day` of the lab's points for every day or part of a day late, counted from the
//! due date; a submission within the grace period after the due date loses nothing; one more
//! than `cap_days` days late is not accepted and scores 0 for the lab. A lab the student never
//! submitted — their clone of the handout has no commit of theirs that changes the lab, and its
//! files are as committed — is "no submission": not late, and no penalty.

use std::collections::BTreeMap;
use std::path::Path;

use chrono::{DateTime, FixedOffset};
use course::LabId;
use raylab_core::Error;

use crate::reset::line_of;
use serde::Deserialize;
use toml::Spanned;

use super::submission::{Refusal, read_regular};

/// The largest course file, roster or metadata file read (bytes).
const FILE_LIMIT: u64 = 4 << 20;

/// A point in time with the UTC offset it was given in.
pub type Time = DateTime<FixedOffset>;

/// Seconds in a day.
const DAY: i64 = 86_400;

/// How lateness costs points in one lab.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LatePolicy {
    /// Fraction of the lab's points lost per day or started day late (0–1).
    pub penalty_per_day: f64,
    /// Minutes after the due date in which a submission is on time.
    pub grace_minutes: u32,
    /// Days late after which the lab is not accepted (scores 0); `None`: no cap.
    pub cap_days: Option<u32>,
}

impl Default for LatePolicy {
    fn default() -> Self {
        Self {
            penalty_per_day: 0.0,
            grace_minutes: 0,
            cap_days: None,
        }
    }
}

/// When one lab was submitted, as far as the submission tells.
#[derive(Clone, Debug, PartialEq)]
pub enum Submitted {
    /// At this time, known from this source ("given", "git commit", "Gradescope").
    At(Time, String),
    /// Not at all: the submission is a git repository in which no commit after the handout's
    /// changed the lab's sources or answers (every commit that did is the handout's own, or
    /// there is none), and the lab's files are as its last commit holds them.
    Nothing,
    /// Not known: no time given and no git history to take it from, or, with the reason, a
    /// lab whose files were changed and never committed.
    Unknown(Option<String>),
}

/// How late a submission was for one lab.
#[derive(Clone, Debug, PartialEq)]
pub enum Lateness {
    /// The submission's time is not known: no penalty.
    Unknown,
    /// Nothing was submitted: not late, no penalty.
    NoSubmission,
    /// At or before the due date.
    OnTime,
    /// After the due date, within the grace period: no penalty.
    InGrace {
        /// Seconds after the due date.
        seconds: i64,
    },
    /// Late: `days` days or started days, costing `fraction` of the lab's points.
    Late {
        /// Seconds after the due date.
        seconds: i64,
        /// Days late, each started day counting as one.
        days: u32,
        /// Fraction of the lab's points lost (at most 1).
        fraction: f64,
    },
    /// Later than the cap: not accepted, the lab scores 0.
    PastCap {
        /// Seconds after the due date.
        seconds: i64,
        /// The cap, days.
        cap_days: u32,
    },
}

impl Lateness {
    /// Judges a submission made as `submitted` says against `due` under `policy`.
    pub fn assess(due: &Time, submitted: &Submitted, policy: &LatePolicy) -> Self {
        let submitted = match submitted {
            Submitted::At(time, _) => time,
            Submitted::Nothing => return Self::NoSubmission,
            Submitted::Unknown(_) => return Self::Unknown,
        };
        let seconds = (*submitted - *due).num_seconds();
        if seconds <= 0 {
            return Self::OnTime;
        }
        if seconds <= i64::from(policy.grace_minutes) * 60 {
            return Self::InGrace { seconds };
        }
        if let Some(cap_days) = policy.cap_days
            && seconds > i64::from(cap_days) * DAY
        {
            return Self::PastCap { seconds, cap_days };
        }
        let days = u32::try_from((seconds + DAY - 1) / DAY).unwrap_or(u32::MAX);
        let fraction = (f64::from(days) * policy.penalty_per_day).min(1.0);
        Self::Late {
            seconds,
            days,
            fraction,
        }
    }

    /// The fraction of the lab's points it costs (0–1).
    pub fn fraction(&self) -> f64 {
        match self {
            Self::Late { fraction, .. } => *fraction,
            Self::PastCap { .. } => 1.0,
            _ => 0.0,
        }
    }

    /// In words, for the reports: "on time", "1 day 12 h late (2 started days)", ….
    pub fn describe(&self) -> String {
        match self {
            Self::Unknown => "unknown (no submission time): no penalty".into(),
            Self::NoSubmission => "not late: no penalty".into(),
            Self::OnTime => "on time".into(),
            Self::InGrace { seconds } => {
                format!(
                    "{} late, within the grace period: no penalty",
                    span(*seconds)
                )
            }
            Self::Late { seconds, days, .. } => format!(
                "{} late ({days} started day{})",
                span(*seconds),
                if *days == 1 { "" } else { "s" }
            ),
            Self::PastCap { seconds, cap_days } => format!(
                "{} late, past the cap of {cap_days} day{}: not accepted",
                span(*seconds),
                if *cap_days == 1 { "" } else { "s" }
            ),
        }
    }

    /// Days late (fractional; 0 when on time or unknown), for the gradebook.
    pub fn days_late(&self) -> f64 {
        match self {
            Self::InGrace { seconds }
            | Self::Late { seconds, .. }
            | Self::PastCap { seconds, .. } => *seconds as f64 / DAY as f64,
            Self::Unknown | Self::NoSubmission | Self::OnTime => 0.0,
        }
    }
}

/// `seconds` as days, hours and minutes: "1 day 12 h", "3 h 05 min", "40 s".
fn span(seconds: i64) -> String {
    let (days, hours, minutes) = (seconds / DAY, seconds % DAY / 3600, seconds % 3600 / 60);
    match (days, hours, minutes) {
        (0, 0, 0) => format!("{seconds} s"),
        (0, 0, m) => format!("{m} min"),
        (0, h, m) => format!("{h} h {m:02} min"),
        (d, h, _) => format!("{d} day{} {h} h", if d == 1 { "" } else { "s" }),
    }
}

/// One lab's deadline for one submission, and how late it was.
#[derive(Clone, Debug, PartialEq)]
pub struct LabDeadline {
    /// The lab.
    pub lab: LabId,
    /// When it was due for this student (the extension's date if there is one).
    pub due: Time,
    /// Whether `due` is an extension's.
    pub extended: bool,
    /// When it was submitted, and where that comes from.
    pub submitted: Submitted,
    /// How late, and what it costs.
    pub lateness: Lateness,
}

/// `time` as RFC 3339 to the second, with its offset.
pub fn rfc3339(time: &Time) -> String {
    time.to_rfc3339_opts(chrono::SecondsFormat::Secs, true)
}

/// A student's identity in Canvas's gradebook (the course file's `[students.NAME]`).
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CanvasStudent {
    /// The name Canvas shows ("Student" column).
    #[serde(default)]
    pub name: Option<String>,
    /// Canvas's user id ("ID").
    #[serde(default)]
    pub canvas_id: Option<String>,
    /// "SIS User ID".
    #[serde(default)]
    pub sis_user_id: Option<String>,
    /// "SIS Login ID".
    #[serde(default)]
    pub sis_login_id: Option<String>,
    /// "Section".
    #[serde(default)]
    pub section: Option<String>,
}

/// One lab's terms in the course file.
#[derive(Clone, Debug, PartialEq)]
pub struct LabTerms {
    /// When it is due.
    pub due: Time,
    /// What lateness costs.
    pub policy: LatePolicy,
    /// Its assignment column in Canvas ("Lab 01 (4411)"), if named.
    pub canvas_assignment: Option<String>,
}

/// A per-student extension.
#[derive(Clone, Debug, PartialEq)]
pub struct Extension {
    /// The student (submission folder name).
    pub student: String,
    /// The lab.
    pub lab: LabId,
    /// The new due date.
    pub due: Time,
}

/// The course file of `raylab grade --course`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CourseTerms {
    /// Each lab with a due date.
    pub labs: BTreeMap<LabId, LabTerms>,
    /// Per-student extensions.
    pub extensions: Vec<Extension>,
    /// Students' Canvas identities, by submission folder name.
    pub students: BTreeMap<String, CanvasStudent>,
    /// The roster CSV the file names (`roster = "FILE"`, relative to the course file), with
    /// the line of the file that names it; [`CourseTerms::load`] reads it into `students`.
    pub roster: Option<(String, usize)>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCourse {
    #[serde(default)]
    late: Option<RawPolicy>,
    #[serde(default)]
    labs: BTreeMap<Spanned<String>, RawLab>,
    #[serde(default)]
    extensions: Vec<RawExtension>,
    #[serde(default)]
    students: BTreeMap<String, CanvasStudent>,
    #[serde(default)]
    roster: Option<Spanned<String>>,
}

#[derive(Deserialize, Default, Clone)]
#[serde(deny_unknown_fields)]
struct RawPolicy {
    penalty_per_day: Option<Spanned<f64>>,
    grace_minutes: Option<u32>,
    cap_days: Option<u32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLab {
    due: Spanned<toml::Value>,
    penalty_per_day: Option<Spanned<f64>>,
    grace_minutes: Option<u32>,
    cap_days: Option<u32>,
    canvas_assignment: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawExtension {
    student: Spanned<String>,
    lab: Spanned<toml::Value>,
    due: Option<Spanned<toml::Value>>,
    days: Option<Spanned<u32>>,
}

/// An error about the file at `path`.
fn invalid(path: &Path, reason: String) -> Error {
    Error::Invalid {
        what: format!("file {}", path.display()),
        reason,
    }
}

/// Reads a file of at most [`FILE_LIMIT`] bytes as UTF-8 text, refusing links and special files.
pub fn read_text(path: &Path) -> Result<String, Error> {
    let bytes = read_regular(path, FILE_LIMIT).map_err(|refusal| match refusal {
        Refusal::Unreadable(source) => Error::io(path, source),
        Refusal::Link => invalid(path, "a symbolic link (not followed)".into()),
        Refusal::Special(kind) => invalid(path, format!("{kind}, not a regular file")),
        Refusal::TooLarge(_) => invalid(path, format!("larger than {} MiB", FILE_LIMIT >> 20)),
    })?;
    String::from_utf8(bytes).map_err(|_| Error::Parse {
        path: path.to_path_buf(),
        line: 0,
        reason: "not UTF-8 text".into(),
    })
}

impl CourseTerms {
    /// Reads and checks the course file at `path`: every lab a lab of the course, every date
    /// RFC 3339 with an offset, every penalty in 0–1, every extension's student among
    /// `students` (when given) and lab among the file's.
    pub fn load(path: &Path, students: Option<&[String]>) -> Result<Self, Error> {
        let text = read_text(path)?;
        let mut terms = Self::parse(path, &text, students)?;
        if let Some((roster, line)) = &terms.roster {
            let file = path.parent().unwrap_or(Path::new("")).join(roster);
            let text = read_text(&file).map_err(|e| Error::Parse {
                path: path.to_path_buf(),
                line: *line,
                reason: format!("roster = {roster:?}: {e}"),
            })?;
            for (student, who) in parse_roster(&file, &text)? {
                if terms.students.contains_key(&student) {
                    return Err(Error::Parse {
                        path: path.to_path_buf(),
                        line: *line,
                        reason: format!(
                            "student {student:?} is both in [students] and in the roster {roster:?}"
                        ),
                    });
                }
                terms.students.insert(student, who);
            }
        }
        Ok(terms)
    }

    /// [`CourseTerms::load`] of `text`, named `path` in errors.
    pub fn parse(path: &Path, text: &str, students: Option<&[String]>) -> Result<Self, Error> {
        let fail = |offset: usize, reason: String| Error::Parse {
            path: path.to_path_buf(),
            line: line_of(text, offset),
            reason,
        };
        let raw: RawCourse = toml::from_str(text).map_err(|e| Error::Parse {
            path: path.to_path_buf(),
            line: e.span().map_or(0, |s| line_of(text, s.start)),
            reason: e.message().to_string(),
        })?;
        let fraction = |value: &Option<Spanned<f64>>, default: f64| -> Result<f64, Error> {
            match value {
                None => Ok(default),
                Some(v) if (0.0..=1.0).contains(v.get_ref()) => Ok(*v.get_ref()),
                Some(v) => Err(fail(
                    v.span().start,
                    format!(
                        "penalty_per_day = {}: expected a fraction of the lab's points from 0 to 1 (0.1 is 10% a day)",
                        v.get_ref()
                    ),
                )),
            }
        };
        let defaults = raw.late.clone().unwrap_or_default();
        let default_policy = LatePolicy {
            penalty_per_day: fraction(&defaults.penalty_per_day, 0.0)?,
            grace_minutes: defaults.grace_minutes.unwrap_or(0),
            cap_days: defaults.cap_days,
        };
        let mut labs = BTreeMap::new();
        for (key, lab) in &raw.labs {
            let id = lab_of(key.get_ref()).map_err(|why| fail(key.span().start, why))?;
            if labs.contains_key(&id) {
                return Err(fail(
                    key.span().start,
                    format!("lab {id} is given twice (as [labs.{}])", key.get_ref()),
                ));
            }
            let due = time_of(&lab.due).map_err(|why| fail(lab.due.span().start, why))?;
            let policy = LatePolicy {
                penalty_per_day: fraction(&lab.penalty_per_day, default_policy.penalty_per_day)?,
                grace_minutes: lab.grace_minutes.unwrap_or(default_policy.grace_minutes),
                cap_days: lab.cap_days.or(default_policy.cap_days),
            };
            labs.insert(
                id,
                LabTerms {
                    due,
                    policy,
                    canvas_assignment: lab.canvas_assignment.clone(),
                },
            );
        }
        let mut extensions = Vec::new();
        for ext in &raw.extensions {
            let student = ext.student.get_ref().clone();
            if let Some(known) = students
                && !known.contains(&student)
            {
                return Err(fail(
                    ext.student.span().start,
                    format!("extension for student {student:?}, who is not among the submissions"),
                ));
            }
            let lab_text = match ext.lab.get_ref() {
                toml::Value::Integer(n) => n.to_string(),
                toml::Value::String(s) => s.clone(),
                other => other.to_string(),
            };
            let lab = lab_of(&lab_text).map_err(|why| fail(ext.lab.span().start, why))?;
            let Some(terms) = labs.get(&lab) else {
                return Err(fail(
                    ext.lab.span().start,
                    format!(
                        "extension for {lab}, which has no [labs.{}] with a due date",
                        lab.number()
                    ),
                ));
            };
            let due = match (&ext.due, &ext.days) {
                (Some(due), None) => time_of(due).map_err(|why| fail(due.span().start, why))?,
                (None, Some(days)) => {
                    terms.due + chrono::TimeDelta::days(i64::from(*days.get_ref()))
                }
                _ => {
                    return Err(fail(
                        ext.student.span().start,
                        "an extension gives either `due` (a new due date) or `days` (days added to the lab's), not both or neither".into(),
                    ));
                }
            };
            if extensions
                .iter()
                .any(|e: &Extension| e.student == student && e.lab == lab)
            {
                return Err(fail(
                    ext.student.span().start,
                    format!("a second extension for {student:?} in lab {lab}"),
                ));
            }
            extensions.push(Extension { student, lab, due });
        }
        Ok(Self {
            labs,
            extensions,
            students: raw.students,
            roster: raw
                .roster
                .map(|r| (r.get_ref().clone(), line_of(text, r.span().start))),
        })
    }

    /// The due date of `lab` for `student`, and whether it is an extension's.
    pub fn due(&self, student: &str, lab: LabId) -> Option<(Time, bool)> {
        let terms = self.labs.get(&lab)?;
        Some(
            self.extensions
                .iter()
                .find(|e| e.student == student && e.lab == lab)
                .map_or((terms.due, false), |e| (e.due, true)),
        )
    }

    /// The late policy of `lab` (no penalty for a lab the file does not name).
    pub fn policy(&self, lab: LabId) -> LatePolicy {
        self.labs.get(&lab).map(|t| t.policy).unwrap_or_default()
    }
}

/// The students of a roster CSV (columns `student,name,canvas_id,sis_user_id,sis_login_id,section`;
/// `student` is the submission folder's name, the others may be empty), by student.
pub fn parse_roster(path: &Path, text: &str) -> Result<BTreeMap<String, CanvasStudent>, Error> {
    const HEADER: [&str; 6] = [
        "student",
        "name",
        "canvas_id",
        "sis_user_id",
        "sis_login_id",
        "section",
    ];
    let fail = |line: u64, reason: String| Error::Parse {
        path: path.to_path_buf(),
        line: line as usize,
        reason,
    };
    let mut reader = csv_with_header(path, text, &HEADER)?;
    let mut students = BTreeMap::new();
    for record in reader.records() {
        let record =
            record.map_err(|e| fail(e.position().map_or(0, |p| p.line()), e.to_string()))?;
        let line = record.position().map_or(0, |p| p.line());
        let field = |k: usize| {
            Some(record.get(k).unwrap_or_default().trim().to_string()).filter(|f| !f.is_empty())
        };
        let Some(student) = field(0) else {
            return Err(fail(
                line,
                "the student (submission folder name) is empty".into(),
            ));
        };
        let who = CanvasStudent {
            name: field(1),
            canvas_id: field(2),
            sis_user_id: field(3),
            sis_login_id: field(4),
            section: field(5),
        };
        if students.insert(student.clone(), who).is_some() {
            return Err(fail(line, format!("a second row for student {student:?}")));
        }
    }
    Ok(students)
}

/// A lab of the course, from a course file's key or value ("1", "01", "lab01").
fn lab_of(text: &str) -> Result<LabId, String> {
    let lab: LabId = text.parse()?;
    crate::labs::check_lab(lab).map_err(|e| format!("lab {text:?}: {e}"))?;
    Ok(lab)
}

/// A due date: a TOML offset date-time or an RFC 3339 string, with its UTC offset.
fn time_of(value: &Spanned<toml::Value>) -> Result<Time, String> {
    let text = match value.get_ref() {
        toml::Value::Datetime(d) => d.to_string(),
        toml::Value::String(s) => s.clone(),
        other => {
            return Err(format!(
                "expected a date such as 2026-10-05T23:59:00+02:00, found {other}"
            ));
        }
    };
    parse_time(&text)
}

/// An RFC 3339 time with an offset ("2026-10-05T23:59:00+02:00", "…Z").
pub fn parse_time(text: &str) -> Result<Time, String> {
    DateTime::parse_from_rfc3339(text.trim()).map_err(|e| {
        format!(
            "{text:?} is not an RFC 3339 date and time with a UTC offset, such as 2026-10-05T23:59:00+02:00 ({e})"
        )
    })
}

/// Where each submission's time comes from, in order: given (`--submitted-at`, a CSV), the
/// submission's last git commit, none.
#[derive(Default)]
pub struct SubmissionTimes {
    /// Times given by student.
    pub given: BTreeMap<String, Time>,
}

impl SubmissionTimes {
    /// The times of `--submitted-at STUDENT=TIME` arguments and a `--submission-times` CSV
    /// (columns `student,submitted_at`), every student among `students`.
    pub fn new(pairs: &[String], csv: Option<&Path>, students: &[String]) -> Result<Self, Error> {
        let mut given = BTreeMap::new();
        let unknown = |student: &str| {
            format!(
                "student {student:?} is not among the submissions ({})",
                students.join(", ")
            )
        };
        for pair in pairs {
            let invalid = |reason: String| Error::Invalid {
                what: format!("--submitted-at {pair}"),
                reason,
            };
            let (student, time) = pair.split_once('=').ok_or_else(|| {
                invalid("expected STUDENT=TIME, such as ada=2026-10-05T23:59:00+02:00".into())
            })?;
            if !students.iter().any(|s| s == student) {
                return Err(invalid(unknown(student)));
            }
            given.insert(student.to_string(), parse_time(time).map_err(invalid)?);
        }
        if let Some(path) = csv {
            let text = read_text(path)?;
            let fail = |line: u64, reason: String| Error::Parse {
                path: path.to_path_buf(),
                line: line as usize,
                reason,
            };
            let mut reader = csv_with_header(path, &text, &["student", "submitted_at"])?;
            for record in reader.records() {
                let record = record
                    .map_err(|e| fail(e.position().map_or(0, |p| p.line()), e.to_string()))?;
                let line = record.position().map_or(0, |p| p.line());
                let student = record.get(0).unwrap_or_default().trim();
                if !students.iter().any(|s| s == student) {
                    return Err(fail(line, unknown(student)));
                }
                let time =
                    parse_time(record.get(1).unwrap_or_default()).map_err(|why| fail(line, why))?;
                given.insert(student.to_string(), time);
            }
        }
        Ok(Self { given })
    }

    /// When `student` submitted `lab` at `dir`: at the time given; else, in a git repository,
    /// at the committer time of the last commit that changed the lab's sources or answers and
    /// is not the handout's own (a release pulled later is no new submission, and neither is
    /// the handout: a clone with no commit of the student's own for the lab submitted nothing,
    /// unless its files of the lab differ from that commit — changed and never committed, when
    /// is not known); else not known.
    pub fn of(&self, student: &str, dir: &Path, lab: LabId) -> Submitted {
        if let Some(time) = self.given.get(student) {
            return Submitted::At(*time, "given".into());
        }
        let (sources, answers) = (format!("{}/src", lab.folder()), lab.answers());
        match last_commit(dir, &[sources.clone(), answers.clone()]) {
            History::Unreadable => Submitted::Unknown(None),
            History::Own(time) => Submitted::At(time, "git commit".into()),
            History::HandoutOnly if as_committed(dir, lab) => Submitted::Nothing,
            History::HandoutOnly => Submitted::Unknown(Some(format!(
                "{sources}/ or {answers} changed since the last commit, which is the handout's"
            ))),
        }
    }
}

/// A CSV reader of `text`, the file `path`, whose header must be `header`: otherwise an error
/// naming line 1 and the header found.
fn csv_with_header<'a>(
    path: &Path,
    text: &'a str,
    header: &[&str],
) -> Result<csv::Reader<&'a [u8]>, Error> {
    let mut reader = csv::ReaderBuilder::new().from_reader(text.as_bytes());
    let found = reader.headers().map_err(|e| Error::Parse {
        path: path.to_path_buf(),
        line: 1,
        reason: e.to_string(),
    })?;
    if found.iter().map(str::trim).collect::<Vec<_>>() != header {
        return Err(Error::Parse {
            path: path.to_path_buf(),
            line: 1,
            reason: format!(
                "expected the header {}, found {}",
                header.join(","),
                found.iter().collect::<Vec<_>>().join(",")
            ),
        });
    }
    Ok(reader)
}

/// The standard output of `git ARGS` in the git repository at `dir` (only when `dir` is the
/// repository's root), run without the repository's hooks, pager, signature checks or
/// file-system monitor, and only with commands that run no filter or diff program of its
/// configuration; `None` when git fails.
fn submission_git(dir: &Path, args: &[&str]) -> Option<Vec<u8>> {
    if !dir.join(".git").exists() {
        return None;
    }
    let absolute = std::path::absolute(dir).ok()?;
    let output = std::process::Command::new("git")
        .arg("--no-pager")
        .args([
            "-c",
            "core.hooksPath=/dev/null",
            "-c",
            "core.fsmonitor=false",
        ])
        .args(["-c", "log.showSignature=false"])
        .arg("-c")
        .arg(format!("safe.directory={}", absolute.display()))
        .arg("-C")
        .arg(&absolute)
        .args(args)
        .env("GIT_TERMINAL_PROMPT", "0")
        .stdin(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .output()
        .ok()?;
    output.status.success().then_some(output.stdout)
}

/// What a submission's git history says of the commits that changed some of its files.
#[derive(Clone, Debug, PartialEq)]
enum History {
    /// No history to read: not the root of a git repository, or git fails.
    Unreadable,
    /// The committer time of the last one that is not the handout's own.
    Own(Time),
    /// Every one is the handout's own (committed by `raylab handout` as
    /// [`crate::git::HANDOUT_EMAIL`]), or there is none.
    HandoutOnly,
}

/// The commits the history of one submission is read back through, at most, for a commit of
/// the student's own (a clone of the handout has the handout's first commit and one per
/// release before it).
const HISTORY_LIMIT: &str = "--max-count=10000";

/// What the git repository at `dir` says of the commits that changed `paths`.
fn last_commit(dir: &Path, paths: &[String]) -> History {
    let Some(output) = submission_git(
        dir,
        &[
            &["log", HISTORY_LIMIT, "--format=%ae%x00%cI", "--"][..],
            &paths.iter().map(String::as_str).collect::<Vec<_>>(),
        ]
        .concat(),
    ) else {
        return History::Unreadable;
    };
    let text = String::from_utf8_lossy(&output);
    let own = text
        .lines()
        .filter_map(|line| line.split_once('\0'))
        .find(|(author, _)| *author != crate::git::HANDOUT_EMAIL);
    match own.map(|(_, time)| parse_time(time)) {
        Some(Ok(time)) => History::Own(time),
        Some(Err(_)) => History::Unreadable,
        None => History::HandoutOnly,
    }
}

/// Whether lab `lab`'s files in the submission at `dir` — the regular files of its `src/` as
/// grading takes them, and its answers — are the ones the repository's last commit holds.
fn as_committed(dir: &Path, lab: LabId) -> bool {
    use std::collections::BTreeMap;
    let (sources, answers) = (format!("{}/src", lab.folder()), lab.answers());
    let Some(listing) = submission_git(
        dir,
        &[
            "ls-tree", "-r", "-l", "-z", "HEAD", "--", &sources, &answers,
        ],
    ) else {
        return false;
    };
    // `<mode> blob <object> <size>\t<path>` for each file.
    let mut committed = BTreeMap::new();
    for entry in listing.split(|&b| b == 0).filter(|e| !e.is_empty()) {
        let entry = String::from_utf8_lossy(entry);
        let Some((info, path)) = entry.split_once('\t') else {
            return false;
        };
        let fields: Vec<&str> = info.split_whitespace().collect();
        let [mode, "blob", object, size] = fields[..] else {
            return false;
        };
        let regular = mode == "100644" || mode == "100755";
        if !regular
            || size
                .parse::<u64>()
                .is_ok_and(|s| s > super::submission::MAX_FILE_BYTES)
        {
            return false;
        }
        let Some(contents) = submission_git(dir, &["cat-file", "blob", object]) else {
            return false;
        };
        committed.insert(path.to_string(), contents);
    }
    let taken = super::submission::lab_sources(dir, lab);
    if !taken.rejected.is_empty() {
        return false;
    }
    let mut present: BTreeMap<String, Vec<u8>> = BTreeMap::new();
    for (relative, contents) in taken.files.unwrap_or_default() {
        present.insert(
            format!("{sources}/{}", relative.to_string_lossy()),
            contents,
        );
    }
    match super::submission::read_answers(dir, lab) {
        Ok(Some(text)) => {
            present.insert(answers, text.into_bytes());
        }
        Ok(None) => {}
        Err(_) => return false,
    }
    present == committed
}

/// What Gradescope's `/autograder/submission_metadata.json` says of one submission's time.
#[derive(Clone, Debug, PartialEq)]
pub struct GradescopeSubmission {
    /// `created_at`: when it was submitted.
    pub submitted: Time,
    /// The assignment's `due_date`, or the submitter's own (an extension) when it has one.
    pub due: Option<Time>,
    /// Whether `due` is the submitter's own.
    pub extended: bool,
}

impl GradescopeSubmission {
    /// Reads Gradescope's submission metadata at `path`.
    pub fn load(path: &Path) -> Result<Self, Error> {
        let text = read_text(path)?;
        Self::parse(path, &text)
    }

    /// [`GradescopeSubmission::load`] of `text`, named `path` in errors.
    pub fn parse(path: &Path, text: &str) -> Result<Self, Error> {
        let fail = |reason: String| Error::Parse {
            path: path.to_path_buf(),
            line: 0,
            reason,
        };
        let json: serde_json::Value = serde_json::from_str(text).map_err(|e| Error::Parse {
            path: path.to_path_buf(),
            line: e.line(),
            reason: e.to_string(),
        })?;
        let time = |value: &serde_json::Value, field: &str| -> Result<Option<Time>, Error> {
            match value {
                serde_json::Value::Null => Ok(None),
                serde_json::Value::String(s) => parse_time(s)
                    .map(Some)
                    .map_err(|why| fail(format!("{field}: {why}"))),
                other => Err(fail(format!("{field}: expected a date, found {other}"))),
            }
        };
        let submitted = time(&json["created_at"], "created_at")?
            .ok_or_else(|| fail("created_at: missing (the submission's time)".into()))?;
        let assignment_due = time(&json["assignment"]["due_date"], "assignment.due_date")?;
        // A group's submission: the latest of its members' own due dates.
        let mut own: Option<Time> = None;
        if let Some(users) = json["users"].as_array() {
            for (k, user) in users.iter().enumerate() {
                let field = format!("users[{k}].assignment.due_date");
                if let Some(due) = time(&user["assignment"]["due_date"], &field)? {
                    own = Some(own.map_or(due, |o| o.max(due)));
                }
            }
        }
        let extended = matches!((own, assignment_due), (Some(o), Some(a)) if o != a)
            || (own.is_some() && assignment_due.is_none());
        Ok(Self {
            submitted,
            due: own.or(assignment_due),
            extended,
        })
    }
}

/// The deadlines of `labs` for one submission: from Gradescope's metadata when given (its due
/// date for every graded lab, the course file's policy), otherwise from the course file; labs
/// with no due date are left out.
pub fn deadlines(
    student: &str,
    labs: &[LabId],
    terms: Option<&CourseTerms>,
    submitted: &dyn Fn(LabId) -> Submitted,
    gradescope: Option<&GradescopeSubmission>,
) -> Vec<LabDeadline> {
    let mut out = Vec::new();
    for &lab in labs {
        let policy = terms.map(|t| t.policy(lab)).unwrap_or_default();
        let (due, extended, submitted) = match gradescope {
            Some(g) => match g.due {
                Some(due) => (
                    due,
                    g.extended,
                    Submitted::At(g.submitted, "Gradescope".to_string()),
                ),
                None => continue,
            },
            None => match terms.and_then(|t| t.due(student, lab)) {
                Some((due, extended)) => (due, extended, submitted(lab)),
                None => continue,
            },
        };
        let lateness = Lateness::assess(&due, &submitted, &policy);
        out.push(LabDeadline {
            lab,
            due,
            extended,
            submitted,
            lateness,
        });
    }
    out
}

/// Points graded by hand for one question of one lab (a row of `--manual-points`).
#[derive(Clone, Debug, PartialEq)]
pub struct ManualPoints {
    /// The lab.
    pub lab: LabId,
    /// The question's id, as the instructor wrote it ("Q1").
    pub question: String,
    /// Points given.
    pub points: f64,
    /// Points available.
    pub max_points: f64,
    /// The grader's comment.
    pub comment: String,
}

/// Reads `--manual-points FILE` (columns `student,lab,question,points,max_points,comment`):
/// every student among `students`, every lab among `labs`, points from 0 to `max_points`, one
/// row per student, lab and question. The rows by student, in file order.
pub fn manual_points(
    path: &Path,
    students: &[String],
    labs: &[LabId],
) -> Result<BTreeMap<String, Vec<ManualPoints>>, Error> {
    let text = read_text(path)?;
    parse_manual_points(path, &text, students, labs)
}

/// [`manual_points`] of `text`, named `path` in errors.
pub fn parse_manual_points(
    path: &Path,
    text: &str,
    students: &[String],
    labs: &[LabId],
) -> Result<BTreeMap<String, Vec<ManualPoints>>, Error> {
    const HEADER: [&str; 6] = [
        "student",
        "lab",
        "question",
        "points",
        "max_points",
        "comment",
    ];
    let fail = |line: u64, reason: String| Error::Parse {
        path: path.to_path_buf(),
        line: line as usize,
        reason,
    };
    let mut reader = csv_with_header(path, text, &HEADER)?;
    let mut out: BTreeMap<String, Vec<ManualPoints>> = BTreeMap::new();
    for record in reader.records() {
        let record =
            record.map_err(|e| fail(e.position().map_or(0, |p| p.line()), e.to_string()))?;
        let line = record.position().map_or(0, |p| p.line());
        let field = |k: usize| record.get(k).unwrap_or_default().trim();
        let student = field(0);
        if !students.iter().any(|s| s == student) {
            return Err(fail(
                line,
                format!(
                    "student {student:?} is not among the submissions ({})",
                    students.join(", ")
                ),
            ));
        }
        let lab: LabId = field(1).parse().map_err(|why| fail(line, why))?;
        if !labs.contains(&lab) {
            return Err(fail(
                line,
                format!("lab {:?} is not among the graded labs", field(1)),
            ));
        }
        let question = field(2);
        if question.is_empty() {
            return Err(fail(
                line,
                "the question is empty (an id such as Q1)".into(),
            ));
        }
        let number = |k: usize, name: &str| -> Result<f64, Error> {
            field(k)
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v >= 0.0)
                .ok_or_else(|| {
                    fail(
                        line,
                        format!(
                            "{name} {:?} is not a number of points (0 or more)",
                            field(k)
                        ),
                    )
                })
        };
        let points = number(3, "points")?;
        let max_points = number(4, "max_points")?;
        if points > max_points {
            return Err(fail(
                line,
                format!("points {points} are more than max_points {max_points}"),
            ));
        }
        let rows = out.entry(student.to_string()).or_default();
        if rows.iter().any(|r| r.lab == lab && r.question == question) {
            return Err(fail(
                line,
                format!("a second row for {student:?}, lab {lab}, question {question:?}"),
            ));
        }
        rows.push(ManualPoints {
            lab,
            question: question.to_string(),
            points,
            max_points,
            comment: field(5).to_string(),
        });
    }
    Ok(out)
}

/// `points` rounded to hundredths (what the reports and the gradebooks write).
pub fn round_points(points: f64) -> f64 {
    (points * 100.0).round() / 100.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn time(text: &str) -> Time {
        parse_time(text).unwrap()
    }

    const POLICY: LatePolicy = LatePolicy {
        penalty_per_day: 0.1,
        grace_minutes: 15,
        cap_days: Some(3),
    };

    #[test]
    fn lateness_on_time_in_grace_late_and_past_the_cap() {
        let due = time("2026-10-05T23:59:00+02:00");
        let at = |t: &str| Lateness::assess(&due, &Submitted::At(time(t), "given".into()), &POLICY);
        assert_eq!(at("2026-10-05T23:59:00+02:00"), Lateness::OnTime);
        // The same instant in another offset.
        assert_eq!(at("2026-10-05T21:59:00Z"), Lateness::OnTime);
        assert_eq!(
            at("2026-10-06T00:10:00+02:00"),
            Lateness::InGrace { seconds: 660 }
        );
        // 1.5 days late: two started days, 20%.
        let late = at("2026-10-07T11:59:00+02:00");
        assert_eq!(
            late,
            Lateness::Late {
                seconds: 129_600,
                days: 2,
                fraction: 0.2
            }
        );
        assert_eq!(late.describe(), "1 day 12 h late (2 started days)");
        // Just past the grace period: one started day.
        assert_eq!(at("2026-10-06T00:15:01+02:00").fraction(), 0.1);
        // Exactly 3 days late is within the cap; a second more is not.
        assert!((at("2026-10-08T23:59:00+02:00").fraction() - 0.3).abs() < 1e-12);
        assert_eq!(
            at("2026-10-08T23:59:01+02:00"),
            Lateness::PastCap {
                seconds: 3 * DAY + 1,
                cap_days: 3
            }
        );
        assert_eq!(at("2026-10-09T00:00:00+02:00").fraction(), 1.0);
        assert_eq!(
            Lateness::assess(&due, &Submitted::Unknown(None), &POLICY),
            Lateness::Unknown
        );
        assert_eq!(Lateness::Unknown.fraction(), 0.0);
        // Nothing submitted is not late, however long after the due date it is graded.
        let none = Lateness::assess(&due, &Submitted::Nothing, &POLICY);
        assert_eq!(none, Lateness::NoSubmission);
        assert_eq!((none.fraction(), none.days_late()), (0.0, 0.0));
    }

    #[test]
    fn the_penalty_is_at_most_the_lab() {
        let due = time("2026-10-05T00:00:00Z");
        let policy = LatePolicy {
            penalty_per_day: 0.4,
            grace_minutes: 0,
            cap_days: None,
        };
        let submitted = Submitted::At(time("2026-10-09T00:00:00Z"), "given".into());
        let late = Lateness::assess(&due, &submitted, &policy);
        assert_eq!(late.fraction(), 1.0);
    }

    const COURSE: &str = r#"
[late]
penalty_per_day = 0.1
grace_minutes = 15
cap_days = 3

[labs.1]
due = 2026-10-05T23:59:00+02:00
canvas_assignment = "Lab 01 (4411)"

[labs.lab02]
due = "2026-10-12T23:59:00Z"
penalty_per_day = 0.25
cap_days = 1

[[extensions]]
student = "ada"
lab = 1
days = 2

[[extensions]]
student = "grace"
lab = "02"
due = 2026-10-20T12:00:00Z

[students.ada]
name = "Ada Lovelace"
canvas_id = "1001"
sis_login_id = "ada@uni.example"
"#;

    fn students() -> Vec<String> {
        vec!["ada".into(), "grace".into(), "roe".into()]
    }

    #[test]
    fn a_course_file_with_defaults_overrides_and_extensions() {
        let terms =
            CourseTerms::parse(Path::new("course.toml"), COURSE, Some(&students())).unwrap();
        let (one, two) = (LabId::of(1), LabId::of(2));
        assert_eq!(terms.policy(one), POLICY);
        assert_eq!(
            terms.policy(two),
            LatePolicy {
                penalty_per_day: 0.25,
                grace_minutes: 15,
                cap_days: Some(1)
            }
        );
        assert_eq!(terms.policy(LabId::of(3)), LatePolicy::default());
        assert_eq!(
            terms.due("roe", one),
            Some((time("2026-10-05T23:59:00+02:00"), false))
        );
        // An extension of two days.
        assert_eq!(
            terms.due("ada", one),
            Some((time("2026-10-07T23:59:00+02:00"), true))
        );
        assert_eq!(
            terms.due("grace", two),
            Some((time("2026-10-20T12:00:00Z"), true))
        );
        assert_eq!(terms.due("ada", LabId::of(3)), None);
        assert_eq!(
            terms.labs[&one].canvas_assignment.as_deref(),
            Some("Lab 01 (4411)")
        );
        assert_eq!(terms.students["ada"].canvas_id.as_deref(), Some("1001"));
        // With the extension, 1.5 days after the lab's due date is on time.
        let ds = deadlines(
            "ada",
            &[one, LabId::of(3)],
            Some(&terms),
            &|_| Submitted::At(time("2026-10-07T11:59:00+02:00"), "given".into()),
            None,
        );
        assert_eq!(ds.len(), 1);
        assert_eq!(ds[0].lateness, Lateness::OnTime);
        assert!(ds[0].extended);
    }

    #[test]
    fn the_documented_example_course_file_is_valid() {
        let text = include_str!("../../../../docs/course-term.example.toml");
        let terms = CourseTerms::parse(
            Path::new("course-term.example.toml"),
            text,
            Some(&students()),
        )
        .unwrap();
        assert_eq!(terms.labs.len(), 2);
        assert_eq!(terms.extensions.len(), 2);
    }

    #[test]
    fn a_roster_names_students_for_canvas() {
        let dir = std::env::temp_dir().join(format!("raylab-roster-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("course.toml"),
            "roster = \"roster.csv\"\n[students.ada]\ncanvas_id = \"1001\"\n",
        )
        .unwrap();
        std::fs::write(
            dir.join("roster.csv"),
            "student,name,canvas_id,sis_user_id,sis_login_id,section\ngrace,\"Hopper, Grace\",1002,,gh@uni.example,B\n",
        )
        .unwrap();
        let terms = CourseTerms::load(&dir.join("course.toml"), None).unwrap();
        assert_eq!(
            terms.students["grace"].name.as_deref(),
            Some("Hopper, Grace")
        );
        assert_eq!(terms.students["grace"].sis_user_id, None);
        assert_eq!(terms.students["ada"].canvas_id.as_deref(), Some("1001"));
        std::fs::write(
            dir.join("roster.csv"),
            "student,name,canvas_id,sis_user_id,sis_login_id,section\nada,Ada,1001,,,\n",
        )
        .unwrap();
        let e = CourseTerms::load(&dir.join("course.toml"), None)
            .unwrap_err()
            .to_string();
        assert!(e.ends_with("course.toml:1: student \"ada\" is both in [students] and in the roster \"roster.csv\""), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
        let e = parse_roster(
            Path::new("r.csv"),
            "student,name,canvas_id,sis_user_id,sis_login_id,section\na,,,,,\na,,,,,\n",
        )
        .unwrap_err()
        .to_string();
        assert_eq!(e, "r.csv:3: a second row for student \"a\"");
    }

    #[test]
    fn a_submission_repository_gives_the_time_of_the_students_last_commit() {
        let dir = std::env::temp_dir().join(format!("raylab-commit-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let times =
            SubmissionTimes::new(&["ada=2026-10-05T10:00:00Z".into()], None, &students()).unwrap();
        let (one, two) = (LabId::of(1), LabId::of(2));
        assert_eq!(
            times.of("grace", &dir, one),
            Submitted::Unknown(None),
            "not a repository"
        );
        // git as `email`, committing at `date`.
        let git = |args: &[&str], email: &str, date: &str| {
            let status = std::process::Command::new("git")
                .args(["-c", "user.name=t", "-c", "commit.gpgsign=false", "-c"])
                .arg(format!("user.email={email}"))
                .args(args)
                .current_dir(&dir)
                .env("GIT_AUTHOR_DATE", date)
                .env("GIT_COMMITTER_DATE", date)
                .status()
                .unwrap();
            assert!(status.success());
        };
        let put = |file: &str, text: &str| {
            let path = dir.join(file);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(path, text).unwrap();
        };
        let (handout, student) = (crate::git::HANDOUT_EMAIL, "grace@uni.example");
        let (handed_out, worked, released) = (
            "2026-09-28T09:00:00+02:00",
            "2026-10-07T11:59:00+02:00",
            "2026-10-20T09:00:00+02:00",
        );
        git(&["init", "-q"], handout, handed_out);
        put("labs/lab01/src/lib.rs", "stub");
        put("labs/lab01/answers.md", "questions");
        put("labs/lab02/src/lib.rs", "stub");
        git(&["add", "."], handout, handed_out);
        git(&["commit", "-qm", "raylab handout"], handout, handed_out);
        // The handout as it was handed out: no submission (not one at the handout's time).
        assert_eq!(times.of("grace", &dir, one), Submitted::Nothing);
        // Changed and never committed: when is not known.
        put("labs/lab01/answers.md", "questions, answered");
        let Submitted::Unknown(Some(why)) = times.of("grace", &dir, one) else {
            panic!("{:?}", times.of("grace", &dir, one));
        };
        assert!(
            why.contains("labs/lab01/src/ or labs/lab01/answers.md"),
            "{why}"
        );
        // Committed: the commit's time.
        put("labs/lab01/src/lib.rs", "work");
        git(&["commit", "-qam", "lab 1"], student, worked);
        assert_eq!(
            times.of("grace", &dir, one),
            Submitted::At(time(worked), "git commit".into())
        );
        // A release pulled later, even one that changes lab 1's files (forced), is the
        // handout's: no new submission of lab 1, and still none of lab 2.
        put("README.md", "release");
        put("labs/lab01/src/fixed.rs", "a fixed stub");
        git(&["add", "."], handout, released);
        git(&["commit", "-qm", "release"], handout, released);
        assert_eq!(
            times.of("grace", &dir, one),
            Submitted::At(time(worked), "git commit".into())
        );
        assert_eq!(times.of("grace", &dir, two), Submitted::Nothing);
        // A file of lab 2 never committed is a change too.
        put("labs/lab02/src/extra.rs", "mine");
        assert!(matches!(
            times.of("grace", &dir, two),
            Submitted::Unknown(Some(_))
        ));
        // A time given comes first.
        assert_eq!(
            times.of("ada", &dir, two),
            Submitted::At(time("2026-10-05T10:00:00Z"), "given".into())
        );
        std::fs::remove_dir_all(&dir).unwrap();
        let e = SubmissionTimes::new(&["zed=2026-10-05T10:00:00Z".into()], None, &students())
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.starts_with("invalid --submitted-at zed=2026-10-05T10:00:00Z: student \"zed\""),
            "{e}"
        );
    }

    /// The error of `text` as a course file.
    fn error(text: &str) -> String {
        CourseTerms::parse(Path::new("course.toml"), text, Some(&students()))
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn course_file_errors_name_the_line_and_the_value() {
        assert_eq!(
            error("[labs.1]\ndue = 2026-10-05T23:59:00+02:00\npenalty = 0.1\n"),
            "course.toml:3: unknown field `penalty`, expected one of `due`, `penalty_per_day`, `grace_minutes`, `cap_days`, `canvas_assignment`"
        );
        let e = error(
            "[labs.1]\ndue = 2026-10-05T23:59:00+02:00\n\n[labs.99]\ndue = 2026-10-05T23:59:00Z\n",
        );
        assert!(e.starts_with("course.toml:4: lab \"99\""), "{e}");
        let e = error("[labs.1]\ndue = 2026-10-05T23:59:00\n");
        assert!(
            e.starts_with("course.toml:2: \"2026-10-05T23:59:00\" is not an RFC 3339"),
            "{e}"
        );
        let e = error("[labs.1]\ndue = \"next monday\"\n");
        assert!(e.starts_with("course.toml:2: \"next monday\""), "{e}");
        let e = error("[labs.1]\ndue = 2026-10-05T23:59:00Z\npenalty_per_day = 10\n");
        assert!(e.starts_with("course.toml:3: penalty_per_day = 10"), "{e}");
        let e = error(
            "[labs.1]\ndue = 2026-10-05T23:59:00Z\n[[extensions]]\nstudent = \"zed\"\nlab = 1\ndays = 1\n",
        );
        assert!(
            e.starts_with("course.toml:4: extension for student \"zed\""),
            "{e}"
        );
        let e = error(
            "[labs.1]\ndue = 2026-10-05T23:59:00Z\n[[extensions]]\nstudent = \"ada\"\nlab = 2\ndays = 1\n",
        );
        assert!(
            e.starts_with("course.toml:5: extension for lab02, which has no [labs.2]"),
            "{e}"
        );
        let e = error(
            "[labs.1]\ndue = 2026-10-05T23:59:00Z\n[[extensions]]\nstudent = \"ada\"\nlab = 1\n",
        );
        assert!(
            e.starts_with("course.toml:4: an extension gives either"),
            "{e}"
        );
        let e = error("[students.ada]\nemail = \"a@b\"\n");
        assert!(e.starts_with("course.toml:2: unknown field `email`"), "{e}");
    }

    #[test]
    fn gradescope_metadata_with_and_without_an_extension() {
        let path = Path::new("submission_metadata.json");
        let plain = r#"{"id": 1, "created_at": "2026-10-07T11:59:00.365935+02:00",
            "assignment": {"due_date": "2026-10-05T23:59:00.000000+02:00", "late_due_date": null, "title": "Lab 1"},
            "users": [{"email": "a@b", "id": 5, "name": "Ada"}]}"#;
        let g = GradescopeSubmission::parse(path, plain).unwrap();
        assert_eq!(g.due, Some(time("2026-10-05T23:59:00+02:00")));
        assert!(!g.extended);
        // Gradescope's time, whatever the submission's history says.
        let late = deadlines(
            "ada",
            &[LabId::of(1)],
            None,
            &|_| Submitted::Nothing,
            Some(&g),
        );
        // Late, but with no course file no penalty.
        assert_eq!(late[0].lateness.fraction(), 0.0);
        assert!(matches!(late[0].lateness, Lateness::Late { days: 2, .. }));
        assert_eq!(
            late[0].submitted,
            Submitted::At(
                time("2026-10-07T11:59:00.365935+02:00"),
                "Gradescope".into()
            )
        );
        let extended = plain.replace(
            r#""name": "Ada"}"#,
            r#""name": "Ada", "assignment": {"due_date": "2026-10-08T23:59:00+02:00"}}"#,
        );
        let g = GradescopeSubmission::parse(path, &extended).unwrap();
        assert_eq!(g.due, Some(time("2026-10-08T23:59:00+02:00")));
        assert!(g.extended);
        let e = GradescopeSubmission::parse(path, r#"{"created_at": "yesterday"}"#).unwrap_err();
        assert!(e.to_string().contains("created_at: \"yesterday\""), "{e}");
    }

    #[test]
    fn manual_points_are_checked_row_by_row() {
        let path = Path::new("manual.csv");
        let labs = [LabId::of(1)];
        let read = |rows: &str| {
            parse_manual_points(
                path,
                &format!("student,lab,question,points,max_points,comment\n{rows}"),
                &students(),
                &labs,
            )
        };
        let ok = read("ada,1,Q1,1.5,2,\"clear, but no units\"\nada,lab01,Q2,3,3,\n").unwrap();
        assert_eq!(ok["ada"].len(), 2);
        assert_eq!(ok["ada"][0].points, 1.5);
        assert_eq!(ok["ada"][0].comment, "clear, but no units");
        let err = |rows: &str| read(rows).unwrap_err().to_string();
        assert!(err("ada,1,Q1,1,2,\nzed,1,Q1,1,2,\n").starts_with("manual.csv:3: student \"zed\""));
        assert!(err("ada,2,Q1,1,2,\n").starts_with("manual.csv:2: lab \"2\" is not among"));
        assert!(
            err("ada,1,Q1,3,2,\n").starts_with("manual.csv:2: points 3 are more than max_points 2")
        );
        assert!(err("ada,1,Q1,two,2,\n").starts_with("manual.csv:2: points \"two\""));
        assert!(err("ada,1,Q1,NaN,2,\n").starts_with("manual.csv:2: points \"NaN\""));
        assert!(err("ada,1,Q1,1,2,\nada,1,Q1,1,2,\n").starts_with("manual.csv:3: a second row"));
        let e = parse_manual_points(path, "student,lab,points\n", &students(), &labs)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("manual.csv:1: expected the header"), "{e}");
    }
}
