//! The grade reports: per student a Markdown and an HTML report and a Gradescope
//! `results.json`; per class a CSV gradebook, a JUnit XML file and an HTML index.

use course::LabId;
use std::fmt::Write as _;
use std::fs;
use std::path::Path;
use std::time::Duration;

use grading::Visibility;
use maud::{Markup, html};
use raylab_core::Error;

use crate::bench::median;

use super::feedback;
use super::grades::{ExerciseGrade, Status, StudentGrade, image_caption};
use super::markdown::{code_span, fenced, table_cell};
use super::term::{CourseTerms, LabDeadline, Lateness, ManualPoints, Submitted, rfc3339};
use crate::handout::io;
use crate::html::{SORT_SCRIPT, page, section_list, stamp};
use crate::similar_pairs::link_for_class_page;

/// Writes `report.md`, `report.html` and `results.json` of `grade` into `dir`. Nothing in a
/// grade names a place of the grader's machine: the student's code could read none (its build
/// sees the jail, its run names files relative to its own directory), and the grader's own
/// failures are told the student as such, their details on the grader's output.
pub fn write_student(grade: &StudentGrade, dir: &Path) -> Result<(), Error> {
    fs::create_dir_all(dir).map_err(io(dir))?;
    write(&dir.join("report.md"), &markdown(grade))?;
    let page = html(grade);
    write(&dir.join("report.html"), &page)?;
    // The same page with its images inlined, one file per student for an LMS.
    if let Some(class_dir) = dir.parent() {
        let pages = class_dir.join("pages");
        fs::create_dir_all(&pages).map_err(io(&pages))?;
        write(
            &pages.join(feedback::page_name(grade)),
            &feedback::standalone(&page, dir),
        )?;
    }
    let results = serde_json::to_string_pretty(&gradescope(grade, dir)).unwrap_or_default();
    write(&dir.join("results.json"), &results)
}

/// Writes `gradebook.csv`, `canvas.csv`, `junit.xml`, `timings.csv` and `index.html` of the
/// class into `dir`; `terms` names the students and the labs as Canvas knows them.
pub fn write_class(
    grades: &[StudentGrade],
    dir: &Path,
    terms: Option<&CourseTerms>,
) -> Result<(), Error> {
    fs::create_dir_all(dir).map_err(io(dir))?;
    write(&dir.join("gradebook.csv"), &gradebook(grades))?;
    write(&dir.join("canvas.csv"), &canvas(grades, terms))?;
    write(&dir.join("junit.xml"), &junit(grades))?;
    write(&dir.join("timings.csv"), &timings(grades))?;
    write(
        &dir.join("index.html"),
        &index(grades, link_for_class_page(dir)),
    )
}

fn write(path: &Path, text: &str) -> Result<(), Error> {
    fs::write(path, text).map_err(io(path))
}

/// The labs of a grade, in order, each with its exercises.
fn by_lab(grade: &StudentGrade) -> Vec<(LabId, Vec<&ExerciseGrade>)> {
    let mut labs: Vec<(LabId, Vec<&ExerciseGrade>)> = Vec::new();
    for e in &grade.exercises {
        match labs.last_mut() {
            Some((lab, list)) if *lab == e.info.lab => list.push(e),
            _ => labs.push((e.info.lab, vec![e])),
        }
    }
    labs
}

fn lab_title(lab: LabId) -> &'static str {
    course::title(lab).unwrap_or_default()
}

/// Points as the reports write them: "7", "7.5", "7.25".
fn pts(points: f64) -> String {
    let rounded = super::term::round_points(points);
    // No "-0" for a penalty of nothing.
    format!("{}", rounded + 0.0)
}

/// Points as a JSON number: an integer when whole.
fn json_points(points: f64) -> serde_json::Value {
    let rounded = super::term::round_points(points);
    if rounded.fract() == 0.0 && rounded.abs() < 1e15 {
        serde_json::Value::from(rounded as i64)
    } else {
        serde_json::Value::from(rounded)
    }
}

/// A lab's deadline in one line: due date (and whether extended), submission time and where it
/// comes from (or that there is no submission), lateness, and the points it cost.
fn deadline_line(grade: &StudentGrade, deadline: &LabDeadline) -> String {
    let lab = deadline.lab;
    let submitted = match &deadline.submitted {
        Submitted::At(time, source) => format!("submitted {} ({source})", rfc3339(time)),
        Submitted::Nothing => format!(
            "no submission (no commit but the handout's own changed {}/src/ or {})",
            lab.folder(),
            lab.answers()
        ),
        Submitted::Unknown(None) => "submitted not known".into(),
        Submitted::Unknown(Some(why)) => format!("submitted not known ({why})"),
    };
    let penalty = grade.lab_penalty(deadline.lab);
    let cost = match &deadline.lateness {
        Lateness::Late { fraction, .. } => format!(
            "; late penalty {}% of the lab's points: −{} points",
            pts(fraction * 100.0),
            pts(penalty)
        ),
        Lateness::PastCap { .. } => format!("; the lab scores 0: −{} points", pts(penalty)),
        _ => String::new(),
    };
    format!(
        "due {}{}; {submitted}; {}{cost}",
        rfc3339(&deadline.due),
        if deadline.extended { " (extended)" } else { "" },
        deadline.lateness.describe()
    )
}

/// The questions of `lab` graded by hand.
fn manual_of(grade: &StudentGrade, lab: LabId) -> Vec<&ManualPoints> {
    grade.manual.iter().filter(|m| m.lab == lab).collect()
}

/// The heading of the questions graded by hand.
const MANUAL_HEADING: &str = "Graded by hand";

/// The CSS class of an exercise's status.
fn class(e: &ExerciseGrade) -> &'static str {
    if e.passed() { "passed" } else { "failed" }
}

/// The message every exercise of a lab shares when the lab failed as a whole (its code does not
/// compile, or it could not be graded): shown once, under the lab's heading.
fn lab_wide_failure<'a>(exercises: &[&'a ExerciseGrade]) -> Option<&'a str> {
    let first = exercises.first()?;
    let whole = matches!(first.status, Status::DoesNotCompile | Status::NotGraded);
    (whole
        && exercises
            .iter()
            .all(|e| e.status == first.status && e.output == first.output))
    .then_some(first.output.as_str())
}

/// Whether the report has a section of its own for `e` (its failure or its output), which the
/// table links to.
fn has_section(e: &ExerciseGrade, lab_wide: bool) -> bool {
    shows_output(e, lab_wide) || !e.program_output.is_empty() || !e.images.is_empty()
}

/// Whether the report shows `e`'s output: why it failed, or, passed or not, that the answer
/// key's code stood in for some of the student's functions.
fn shows_output(e: &ExerciseGrade, lab_wide: bool) -> bool {
    !lab_wide && (!e.passed() || !e.key_for.is_empty())
}

/// `e`'s status as the reports' tables show it: with the exercises whose functions were the
/// answer key's in the run that decided it.
fn result_label(e: &ExerciseGrade) -> String {
    if e.key_for.is_empty() {
        e.status.label()
    } else {
        format!(
            "{} (with the key's code for {})",
            e.status.label(),
            e.key_for.join(", ")
        )
    }
}

fn markdown(grade: &StudentGrade) -> String {
    let mut md = format!(
        "# Grade report: {}\n\n**{}/{} points**\n\n",
        grade.student,
        pts(grade.score()),
        pts(grade.max_score())
    );
    if !grade.changed_files.is_empty() {
        md.push_str("## Files changed outside `labs/labNN/src/` (not used for grading)\n\n");
        for change in &grade.changed_files {
            let _ = writeln!(md, "- {}", code_span(change));
        }
        md.push('\n');
    }
    if !grade.notes.is_empty() {
        md.push_str("## Notes\n\n");
        for note in &grade.notes {
            let _ = writeln!(md, "- {note}");
        }
        md.push('\n');
    }
    if !grade.rejected.is_empty() {
        md.push_str("## Files not taken from the submission\n\n");
        for line in &grade.rejected {
            let _ = writeln!(md, "- {}", code_span(line));
        }
        md.push('\n');
    }
    if !grade.flagged.is_empty() {
        md.push_str("## Flagged: sources that name files outside their lab at compile time (which the build cannot read: it sees the submission alone), or framework code that answers an exercise\n\n");
        for line in &grade.flagged {
            let _ = writeln!(md, "- flagged: {}", code_span(line));
        }
        md.push('\n');
    }
    if !grade.sandbox.is_empty() {
        let _ = writeln!(md, "Student code was {}.\n", grade.sandbox);
    }
    for (lab, exercises) in by_lab(grade) {
        let _ = writeln!(
            md,
            "## Lab {:02} — {} ({}/{})\n",
            lab.number(),
            lab_title(lab),
            pts(grade.lab_score(lab)),
            pts(grade.lab_max(lab))
        );
        if let Some(deadline) = grade.deadline(lab) {
            let _ = writeln!(md, "Deadline: {}.\n", deadline_line(grade, deadline));
        }
        md.push_str("| exercise | function | result | points |\n| --- | --- | --- | --- |\n");
        for e in &exercises {
            let _ = writeln!(
                md,
                "| {} {} | `{}` | {} | {}/{} |",
                e.info.id,
                e.info.title,
                e.info.function,
                result_label(e),
                e.score,
                e.info.points
            );
        }
        md.push('\n');
        let manual = manual_of(grade, lab);
        if !manual.is_empty() {
            let _ = writeln!(
                md,
                "### {MANUAL_HEADING}\n\n| question | points | comment |\n| --- | --- | --- |"
            );
            for m in &manual {
                let _ = writeln!(
                    md,
                    "| {} | {}/{} | {} |",
                    table_cell(&m.question),
                    pts(m.points),
                    pts(m.max_points),
                    table_cell(&m.comment)
                );
            }
            md.push('\n');
        }
        let lab_wide = lab_wide_failure(&exercises);
        if let Some(why) = lab_wide {
            let _ = writeln!(md, "Every exercise of this lab:\n\n{}", fenced(why));
        }
        for e in exercises
            .iter()
            .filter(|e| has_section(e, lab_wide.is_some()))
        {
            let _ = writeln!(
                md,
                "### Exercise {} — `{}`: {}\n\n{}",
                e.info.id,
                e.info.function,
                e.status.label(),
                if shows_output(e, lab_wide.is_some()) {
                    fenced(&e.output)
                } else {
                    String::new()
                }
            );
            if !e.program_output.is_empty() {
                let _ = writeln!(md, "{PROGRAM_OUTPUT}:\n\n{}", fenced(&e.program_output));
            }
            for image in &e.images {
                let _ = writeln!(md, "![{}]({})", image_caption(image), image.display());
            }
            if !e.images.is_empty() {
                md.push('\n');
            }
        }
        if let Some(answers) = grade.answers.iter().find(|a| a.lab == lab) {
            md.push_str(&answers.markdown());
        }
    }
    let _ = writeln!(md, "---\n\n{}", stamp());
    md
}

/// The heading of what the student's code printed, set apart from the verdict.
const PROGRAM_OUTPUT: &str = "Output of your code (as it printed it; not part of the verdict)";

fn html(grade: &StudentGrade) -> String {
    let body = html! {
        h1 { "Grade report: " (grade.student) }
        p { strong { (pts(grade.score())) "/" (pts(grade.max_score())) " points" } }
        (section_list(
            html! { "Files changed outside " code { "labs/labNN/src/" } " (not used for grading)" },
            &grade.changed_files,
        ))
        (section_list(html! { "Notes" }, &grade.notes))
        (section_list(html! { "Files not taken from the submission" }, &grade.rejected))
        (section_list(
            html! { "Flagged: sources that name files outside their lab at compile time (which the build cannot read: it sees the submission alone), or framework code that answers an exercise" },
            &grade.flagged,
        ))
        @if !grade.sandbox.is_empty() {
            p { "Student code was " (grade.sandbox) "." }
        }
        @for (lab, exercises) in by_lab(grade) {
            @let lab_wide = lab_wide_failure(&exercises);
            @let manual = manual_of(grade, lab);
            h2 { "Lab " (format!("{:02}", lab.number())) " — " (lab_title(lab)) " (" (pts(grade.lab_score(lab))) "/" (pts(grade.lab_max(lab))) ")" }
            @if let Some(deadline) = grade.deadline(lab) {
                p class="deadline" { "Deadline: " (deadline_line(grade, deadline)) "." }
            }
            table {
                tr { th { "exercise" } th { "function" } th { "result" } th { "points" } }
                @for e in &exercises {
                    tr {
                        td {
                            @if has_section(e, lab_wide.is_some()) {
                                a href={ "#ex-" (e.info.id) } { (e.info.id) }
                            } @else {
                                (e.info.id)
                            }
                            " " (e.info.title)
                        }
                        td { code { (e.info.function) } }
                        td class=(class(e)) { (result_label(e)) }
                        td { (e.score) "/" (e.info.points) }
                    }
                }
            }
            @if !manual.is_empty() {
                h3 { (MANUAL_HEADING) }
                table {
                    tr { th { "question" } th { "points" } th { "comment" } }
                    @for m in &manual {
                        tr {
                            td { (m.question) }
                            td { (pts(m.points)) "/" (pts(m.max_points)) }
                            td { (m.comment) }
                        }
                    }
                }
            }
            @if let Some(why) = lab_wide {
                p { "Every exercise of this lab:" }
                pre { (why) }
            }
            @for e in exercises.iter().filter(|e| has_section(e, lab_wide.is_some())) {
                h3 id={ "ex-" (e.info.id) } {
                    "Exercise " (e.info.id) " — " code { (e.info.function) } ": " (e.status.label())
                }
                @if shows_output(e, lab_wide.is_some()) {
                    pre { (e.output) }
                }
                @if !e.program_output.is_empty() {
                    p { (PROGRAM_OUTPUT) ":" }
                    pre class="program" { (e.program_output) }
                }
                @if !e.images.is_empty() {
                    div class="images" {
                        @for image in &e.images {
                            figure {
                                img src=(image.to_string_lossy().replace('\\', "/")) alt=(image_caption(image));
                                figcaption { (image_caption(image)) }
                            }
                        }
                    }
                }
            }
            @if let Some(answers) = grade.answers.iter().find(|a| a.lab == lab) {
                (answers.html())
            }
        }
    };
    page(&format!("{}: grade report", grade.student), body, None)
}

/// An exercise's status, why, and what its code printed, as one text.
fn exercise_output(e: &ExerciseGrade) -> String {
    let verdict = format!("{}.\n{}", e.status.label(), e.output);
    if e.program_output.is_empty() {
        verdict
    } else {
        format!("{verdict}\n\n{PROGRAM_OUTPUT}:\n{}", e.program_output)
    }
}

/// Gradescope results for a submission that could not be graded at all: 0 points and why.
pub fn ungraded_results(why: &str) -> String {
    let results = serde_json::json!({
        "score": 0,
        "output": format!("The autograder could not grade this submission: {why}\n{}", stamp()),
        "tests": [],
    });
    serde_json::to_string_pretty(&results).unwrap_or_default()
}

/// Gradescope's `results.json` of `grade`, whose report directory is `dir`: a failed exercise
/// with images shows them inline (its output in Gradescope's `html` format).
fn gradescope(grade: &StudentGrade, dir: &Path) -> serde_json::Value {
    let mut budget = feedback::RESULTS_IMAGE_BUDGET;
    let mut tests: Vec<serde_json::Value> = grade
        .exercises
        .iter()
        .map(|e| {
            let output = exercise_output(e);
            let (output, format) = if e.passed() || e.images.is_empty() {
                (output, "text")
            } else {
                (
                    feedback::gradescope_html(e, &output, dir, &mut budget),
                    "html",
                )
            };
            serde_json::json!({
                "name": format!("Exercise {} — {} ({})", e.info.id, e.info.title, e.info.function),
                "number": e.info.id,
                "score": e.score,
                "max_score": e.info.points,
                "status": class(e),
                "output": output,
                "output_format": format,
                "visibility": match e.info.visibility {
                    Visibility::Visible => "visible",
                    // Shown once the due date has passed (Gradescope's own, extensions included).
                    Visibility::Hidden => "after_due_date",
                },
            })
        })
        .chain(grade.manual.iter().map(|m| {
            serde_json::json!({
                "name": format!("Lab {:02} {} — {}", m.lab.number(), MANUAL_HEADING.to_lowercase(), m.question),
                "score": json_points(m.points),
                "max_score": json_points(m.max_points),
                "output": m.comment,
                "visibility": "visible",
            })
        }))
        .collect();
    // After the exercises, whose images take the budget first; no points: the answers' points
    // are the tests graded by hand.
    let written = grade.answers.iter().map(|answers| {
        let (answered, total) = answers.counts();
        serde_json::json!({
            "name": format!(
                "Lab {:02} written answers ({answered} of {total} answered)",
                answers.lab.number()
            ),
            "score": 0,
            "max_score": 0,
            "output": feedback::gradescope_answers(answers, dir, &mut budget),
            "output_format": "html",
            "visibility": "visible",
        })
    });
    let at = grade.exercises.len();
    tests.splice(at..at, written);
    let mut output = String::new();
    for deadline in &grade.deadlines {
        let _ = writeln!(
            output,
            "Lab {:02}: {}.",
            deadline.lab.number(),
            deadline_line(grade, deadline)
        );
    }
    for line in grade.notes.iter().chain(&grade.changed_files) {
        let _ = writeln!(output, "{line}");
    }
    for line in &grade.rejected {
        let _ = writeln!(output, "not taken: {line}");
    }
    for line in &grade.flagged {
        let _ = writeln!(output, "flagged: {line}");
    }
    if !grade.sandbox.is_empty() {
        let _ = writeln!(output, "Student code was {}.", grade.sandbox);
    }
    let _ = writeln!(output, "{}", stamp());
    serde_json::json!({
        "score": json_points(grade.score()),
        "max_score": json_points(grade.max_score()),
        // Gradescope's optional field: the seconds the grading took (builds and runs).
        "execution_time": (grade.timings.build + grade.timings.run + grade.timings.timed_out).round() as u64,
        "output": output,
        "tests": tests,
    })
}

/// The labs of the class with a due date or questions graded by hand for anyone: the labs
/// the gradebook has columns of deadlines or hand-graded points for.
fn class_labs(grades: &[StudentGrade]) -> (Vec<LabId>, Vec<LabId>) {
    let mut dated: Vec<LabId> = grades
        .iter()
        .flat_map(|g| g.deadlines.iter().map(|d| d.lab))
        .collect();
    dated.sort_unstable();
    dated.dedup();
    let mut manual: Vec<LabId> = grades
        .iter()
        .flat_map(|g| g.manual.iter().map(|m| m.lab))
        .collect();
    manual.sort_unstable();
    manual.dedup();
    (dated, manual)
}

/// One row per student: the points of each exercise, the total (after late penalties, with
/// the points graded by hand), the maximum, and how many files outside the lab sources were
/// changed; then, for each lab with a due date, the due date, submission time, days late and
/// penalty, and for each lab with questions graded by hand, their points.
fn gradebook(grades: &[StudentGrade]) -> String {
    let mut csv = csv::Writer::from_writer(Vec::new());
    let mut header = vec!["student".to_string()];
    if let Some(first) = grades.first() {
        header.extend(first.exercises.iter().map(|e| e.info.id.to_string()));
    }
    header.extend(["total", "max_score", "changed_files"].map(String::from));
    let (dated, manual) = class_labs(grades);
    for lab in &dated {
        header.extend(["due", "submitted", "days_late", "penalty"].map(|c| format!("{lab}_{c}")));
    }
    header.extend(manual.iter().map(|lab| format!("{lab}_manual")));
    // Writing to memory cannot fail.
    let _ = csv.write_record(&header);
    for grade in grades {
        let mut row = vec![grade.student.clone()];
        row.extend(grade.exercises.iter().map(|e| e.score.to_string()));
        row.extend([
            pts(grade.score()),
            pts(grade.max_score()),
            grade.changed_files.len().to_string(),
        ]);
        for &lab in &dated {
            match grade.deadline(lab) {
                Some(d) => row.extend([
                    rfc3339(&d.due),
                    match &d.submitted {
                        Submitted::At(time, _) => rfc3339(time),
                        Submitted::Nothing => "no submission".into(),
                        Submitted::Unknown(_) => String::new(),
                    },
                    match d.lateness {
                        Lateness::Unknown | Lateness::NoSubmission => String::new(),
                        _ => format!("{:.2}", d.lateness.days_late()),
                    },
                    pts(grade.lab_penalty(lab)),
                ]),
                None => row.extend([String::new(), String::new(), String::new(), String::new()]),
            }
        }
        for &lab in &manual {
            row.push(pts(manual_of(grade, lab).iter().map(|m| m.points).sum()));
        }
        let _ = csv.write_record(&row);
    }
    String::from_utf8(csv.into_inner().unwrap_or_default()).unwrap_or_default()
}

/// `canvas.csv`: the gradebook as Canvas imports it (Grades → Import): the columns Student,
/// ID, SIS User ID, SIS Login ID, Section, then one per lab, named as the course file's
/// `canvas_assignment` ("Lab 01 (4411)": an existing assignment by its id) or "Lab 01 — Title"
/// (a new assignment); a "Points Possible" row; a row per student with each lab's points after
/// its late penalty. Students are named as the course file's `[students]` says, or by their
/// submission folder's name.
fn canvas(grades: &[StudentGrade], terms: Option<&CourseTerms>) -> String {
    let mut csv = csv::Writer::from_writer(Vec::new());
    let labs = grades.first().map(StudentGrade::labs).unwrap_or_default();
    let mut header: Vec<String> = ["Student", "ID", "SIS User ID", "SIS Login ID", "Section"]
        .map(String::from)
        .to_vec();
    header.extend(labs.iter().map(|&lab| {
        terms
            .and_then(|t| t.labs.get(&lab))
            .and_then(|l| l.canvas_assignment.clone())
            .unwrap_or_else(|| format!("Lab {:02} — {}", lab.number(), lab_title(lab)))
    }));
    let _ = csv.write_record(&header);
    let mut possible = vec!["Points Possible".to_string()];
    possible.extend(std::iter::repeat_n(String::new(), 4));
    // A question graded by hand for some students only still counts for the class.
    possible.extend(
        labs.iter()
            .map(|&lab| pts(grades.iter().map(|g| g.lab_max(lab)).fold(0.0, f64::max))),
    );
    let _ = csv.write_record(&possible);
    for grade in grades {
        let who = terms
            .and_then(|t| t.students.get(&grade.student))
            .cloned()
            .unwrap_or_default();
        let mut row = vec![
            who.name.unwrap_or_else(|| grade.student.clone()),
            who.canvas_id.unwrap_or_default(),
            who.sis_user_id.unwrap_or_default(),
            who.sis_login_id.unwrap_or_default(),
            who.section.unwrap_or_default(),
        ];
        row.extend(labs.iter().map(|&lab| pts(grade.lab_score(lab))));
        let _ = csv.write_record(&row);
    }
    String::from_utf8(csv.into_inner().unwrap_or_default()).unwrap_or_default()
}

/// `timings.csv`: where the grading of each submission spent its time, seconds.
fn timings(grades: &[StudentGrade]) -> String {
    let mut csv = csv::Writer::from_writer(Vec::new());
    let _ = csv.write_record(["student", "build", "run", "timed_out", "report"]);
    for g in grades {
        let t = g.timings;
        let _ = csv.write_record([
            g.student.clone(),
            format!("{:.3}", t.build),
            format!("{:.3}", t.run),
            format!("{:.3}", t.timed_out),
            format!("{:.3}", t.report),
        ]);
    }
    String::from_utf8(csv.into_inner().unwrap_or_default()).unwrap_or_default()
}

/// JUnit XML: a test suite per student, a test case per exercise; a failure's type is its
/// status.
fn junit(grades: &[StudentGrade]) -> String {
    use quick_junit::{NonSuccessKind, Report, TestCase, TestCaseStatus, TestSuite};
    let mut report = Report::new("raylab grade");
    for grade in grades {
        let mut suite = TestSuite::new(grade.student.as_str());
        for e in &grade.exercises {
            let status = if e.passed() {
                TestCaseStatus::success()
            } else {
                let mut status = TestCaseStatus::non_success(NonSuccessKind::Failure);
                status
                    .set_type(e.status.label())
                    .set_message(e.output.lines().next().unwrap_or("failed"))
                    .set_description(e.output.as_str());
                status
            };
            let mut case = TestCase::new(
                format!("Exercise {} {}", e.info.id, e.info.function),
                status,
            );
            case.set_classname(format!("{}.{}", grade.student, e.info.lab))
                .set_time(Duration::from_secs_f64(e.seconds.max(0.0)));
            if !e.program_output.is_empty() {
                case.set_system_out(e.program_output.as_str());
            }
            suite.add_test_case(case);
        }
        report.add_test_suite(suite);
    }
    report.to_string().unwrap_or_default()
}

/// Mean and median of `values`, as table cells.
fn mean_median(values: &mut [f64]) -> Markup {
    let mean = values.iter().sum::<f64>() / values.len().max(1) as f64;
    let median = median(values);
    html! {
        td data-v=(mean) { (format!("{mean:.1}")) }
        td data-v=(median) { (format!("{median:.1}")) }
    }
}

/// The class page: each student's points per lab and total, linking to their report; per lab
/// and per exercise the mean and median points and how many passed; the tables sort by any
/// column; and `similarity`, the section on similar submissions when `raylab similarity` wrote
/// into the same directory.
fn index(grades: &[StudentGrade], similarity: Option<Markup>) -> String {
    let labs: Vec<(LabId, Vec<&ExerciseGrade>)> = grades.first().map(by_lab).unwrap_or_default();
    let any_deadline = grades.iter().any(|g| !g.deadlines.is_empty());
    let body = html! {
        h1 { "Grades" }
        p { (grades.len()) " submissions." }
        h2 { "Students" }
        table class="sortable" {
            thead {
                tr {
                    th { "student" }
                    @for (lab, _) in &labs { th { "lab " (format!("{:02}", lab.number())) } }
                    th { "points" }
                    th { "files changed outside labs/*/src" }
                    @if any_deadline { th { "lateness" } }
                }
            }
            tbody {
                @for g in grades {
                    tr {
                        td { a href={ (g.student) "/report.html" } { (g.student) } }
                        @for (lab, _) in by_lab(g) {
                            td data-v=(g.lab_score(lab)) { (pts(g.lab_score(lab))) "/" (pts(g.lab_max(lab))) }
                        }
                        td data-v=(g.score()) { (pts(g.score())) "/" (pts(g.max_score())) }
                        td { (g.changed_files.len()) }
                        @if any_deadline {
                            td data-v=(g.deadlines.iter().map(|d| g.lab_penalty(d.lab)).sum::<f64>()) {
                                @for d in &g.deadlines {
                                    div { "lab " (format!("{:02}", d.lab.number())) ": " (deadline_line(g, d)) }
                                }
                            }
                        }
                    }
                }
            }
        }
        @if !labs.is_empty() {
            h2 { "Labs" }
            table class="sortable" {
                thead { tr { th { "lab" } th { "points" } th { "mean" } th { "median" } th { "all passed" } } }
                tbody {
                    @for (k, (lab, _)) in labs.iter().enumerate() {
                        @let (mut earned, complete) = lab_statistics(grades, k);
                        tr {
                            td data-v=(lab) { (format!("{:02}", lab.number())) " " (lab_title(*lab)) }
                            td { (pts(grades[0].lab_max(*lab))) }
                            (mean_median(&mut earned))
                            td data-v=(complete) { (complete) "/" (grades.len()) }
                        }
                    }
                }
            }
            h2 { "Exercises" }
            table class="sortable" {
                thead {
                    tr {
                        th { "exercise" } th { "function" } th { "points" } th { "mean" }
                        th { "median" } th { "passed" } th { "most common failure" }
                    }
                }
                tbody {
                    @for (k, e) in grades[0].exercises.iter().enumerate() {
                        @let (mut earned, passed, common) = exercise_statistics(grades, k);
                        tr {
                            td data-v=(k) { (e.info.id) }
                            td { code { (e.info.function) } }
                            td { (e.info.points) }
                            (mean_median(&mut earned))
                            td data-v=(passed) { (passed) "/" (grades.len()) }
                            td { (common) }
                        }
                    }
                }
            }
        }
        (class_table(grades))
        @if let Some(similarity) = similarity { (similarity) }
        p { "Also: gradebook.csv, canvas.csv (for Canvas's gradebook import), junit.xml, each student's results.json (Gradescope), and in "
            code { "pages/" } " each student's report as one file with its images inlined." }
    };
    page("Grades", body, Some(SORT_SCRIPT))
}

/// The points each student earned in the `k`-th lab, and how many passed all of it.
fn lab_statistics(grades: &[StudentGrade], k: usize) -> (Vec<f64>, usize) {
    let mut earned = Vec::new();
    let mut complete = 0;
    for g in grades {
        if let Some((lab, es)) = by_lab(g).get(k) {
            earned.push(g.lab_score(*lab));
            complete += usize::from(es.iter().all(|e| e.passed()));
        }
    }
    (earned, complete)
}

/// The points each student earned in the `k`-th exercise, how many passed it, and its most
/// common failure with its count.
fn exercise_statistics(grades: &[StudentGrade], k: usize) -> (Vec<f64>, usize, String) {
    let mut earned = Vec::new();
    let mut passed = 0;
    let mut failures = std::collections::BTreeMap::<String, usize>::new();
    for x in grades.iter().filter_map(|g| g.exercises.get(k)) {
        earned.push(f64::from(x.score));
        if x.passed() {
            passed += 1;
        } else {
            *failures.entry(x.status.label()).or_default() += 1;
        }
    }
    let common = failures
        .iter()
        .max_by_key(|(_, n)| **n)
        .map_or(String::new(), |(label, n)| format!("{label} ({n})"));
    (earned, passed, common)
}

/// The class page's table of written answers: per student and lab, how many questions are
/// answered, linking to the answers in the student's report. Nothing when no one wrote any.
fn class_table(grades: &[StudentGrade]) -> Markup {
    let labs: Vec<LabId> = {
        let mut labs: Vec<LabId> = grades
            .iter()
            .flat_map(|g| g.answers.iter().map(|a| a.lab))
            .collect();
        labs.sort();
        labs.dedup();
        labs
    };
    html! {
        @if !labs.is_empty() {
            h2 { "Written answers" }
            p { "Questions answered in each lab's " code { "answers.md" } ", to grade by hand." }
            table class="sortable" {
                thead { tr { th { "student" } @for lab in &labs { th { "lab " (format!("{:02}", lab.number())) } } } }
                tbody {
                    @for g in grades {
                        tr {
                            td { (g.student) }
                            @for lab in &labs {
                                @match g.answers.iter().find(|a| a.lab == *lab) {
                                    Some(a) => {
                                        @let (answered, total) = a.counts();
                                        td data-v=(answered) {
                                            a href={ (g.student) "/report.html#answers-" (lab) } {
                                                (answered) "/" (total)
                                            }
                                        }
                                    }
                                    None => td data-v="-1" { "none" },
                                }
                            }
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use base64::Engine as _;
    use course::ExerciseInfo;
    use std::path::PathBuf;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&mut [4.0, 1.0, 2.0, 3.0]), 2.5);
        assert_eq!(median(&mut []), 0.0);
    }

    fn grade_of(student: &str, status: Status) -> StudentGrade {
        let info = ExerciseInfo {
            lab: LabId::of(1),
            id: "1.1".into(),
            function: "image_plane_coords".into(),
            title: "pixel to image plane".into(),
            points: 2,
            visibility: Visibility::Visible,
            hint: String::new(),
        };
        StudentGrade {
            student: student.into(),
            exercises: vec![ExerciseGrade {
                score: if status == Status::Passed { 2 } else { 0 },
                info,
                status,
                output: "Exercise 1.1 — … timed out\nsecond line <&>".into(),
                program_output: String::new(),
                images: Vec::new(),
                seconds: 1.5,
                key_for: Vec::new(),
            }],
            changed_files: Vec::new(),
            notes: Vec::new(),
            rejected: Vec::new(),
            flagged: Vec::new(),
            sandbox: String::new(),
            timings: Default::default(),
            answers: Vec::new(),
            deadlines: Vec::new(),
            manual: Vec::new(),
        }
    }

    #[test]
    fn the_gradebook_quotes_names_and_junit_types_failures_by_status() {
        let grades = [
            grade_of("doe, \"jane\"", Status::TimedOut),
            grade_of("roe", Status::Passed),
        ];
        let csv = gradebook(&grades);
        assert_eq!(
            csv,
            "student,1.1,total,max_score,changed_files\n\"doe, \"\"jane\"\"\",0,0,2,0\nroe,2,2,2,0\n"
        );
        let xml = junit(&grades);
        assert!(xml.contains("type=\"timed out\""), "{xml}");
        assert!(xml.contains("second line &lt;&amp;&gt;"), "{xml}");
        assert_eq!(xml.matches("<testcase").count(), 2, "{xml}");
        assert_eq!(xml.matches("<failure").count(), 1, "{xml}");
    }

    /// The targets of a page's in-page links, and its element ids.
    fn anchors(page: &str) -> (Vec<&str>, Vec<&str>) {
        let grab = |marker: &str| -> Vec<&str> {
            page.split(marker)
                .skip(1)
                .filter_map(|rest| rest.split('"').next())
                .collect()
        };
        (grab("href=\"#"), grab("id=\""))
    }

    #[test]
    fn pages_escape_names_and_link_only_to_sections_that_exist() {
        let failed = grade_of("<b>&", Status::TimedOut);
        let passed = grade_of("roe", Status::Passed);
        let page = html(&failed);
        assert!(
            page.contains("&lt;b&gt;&amp;") && !page.contains("<b>&"),
            "{page}"
        );
        let (links, ids) = anchors(&page);
        assert_eq!(links, ["ex-1.1"]);
        assert!(ids.contains(&"ex-1.1"), "{page}");
        assert!(page.contains("timed out"), "{page}");
        // A passed exercise with nothing to show has no section and no link.
        let page = html(&passed);
        let (links, _) = anchors(&page);
        assert!(links.is_empty(), "{links:?}");
        let class = index(&[failed, passed], None);
        assert!(class.contains("&lt;b&gt;&amp;/report.html"), "{class}");
        assert!(class.contains("class=\"sortable\""), "{class}");
        assert!(
            class.contains("raylab ") && class.contains(" UTC"),
            "{class}"
        );
    }

    #[test]
    fn the_class_page_has_the_similar_pairs_when_similarity_wrote_them() {
        let dir = std::env::temp_dir().join(format!("raylab-index-similar-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let grades = [
            grade_of("ann", Status::Passed),
            grade_of("ben", Status::Wrong),
        ];
        write_class(&grades, &dir, None).unwrap();
        let class = fs::read_to_string(dir.join("index.html")).unwrap();
        assert!(!class.contains("similarity.html"), "{class}");
        fs::write(
            dir.join(crate::similar_pairs::CSV),
            "lab,student_a,student_b,similarity,longest_fragment,fragment_a,fragment_b\n\
             lab01,ann,ben,0.912,40,labs/lab01/src/lib.rs:1–9,labs/lab01/src/lib.rs:3–11\n",
        )
        .unwrap();
        write_class(&grades, &dir, None).unwrap();
        let class = fs::read_to_string(dir.join("index.html")).unwrap();
        assert!(
            class.contains("href=\"similarity.html\"")
                && class.contains("<td>ann</td><td>ben</td><td>0.912</td>"),
            "{class}"
        );
        fs::remove_dir_all(&dir).ok();
    }

    /// `text` with the grader's version and the time of every stamp replaced, so that a
    /// snapshot does not change with either.
    fn unstamped(text: &str) -> String {
        let marker = format!("raylab {} (grader), ", env!("CARGO_PKG_VERSION"));
        let mut out = String::new();
        let mut rest = text;
        while let Some(at) = rest.find(&marker) {
            out.push_str(&rest[..at]);
            out.push_str("raylab <version> (grader), <time>");
            // The time is `YYYY-MM-DD HH:MM UTC`, 20 characters.
            rest = rest[at + marker.len()..].get(20..).unwrap_or("");
        }
        out.push_str(rest);
        out
    }

    /// A class of two: one submission that meets every kind of failure in labs 01 and 02, one
    /// whose lab 02 does not compile.
    fn fixed_class() -> Vec<StudentGrade> {
        let infos = |lab| crate::labs::exercises(LabId::of(lab));
        let (lab01, lab02) = (infos(1), infos(2));
        let exercise = |info: &ExerciseInfo, status: Status, output: &str| ExerciseGrade {
            score: if status == Status::Passed {
                info.points
            } else {
                0
            },
            info: info.clone(),
            status,
            output: output.into(),
            program_output: String::new(),
            images: Vec::new(),
            seconds: 0.25,
            key_for: Vec::new(),
        };
        let statuses = [
            (Status::Passed, ""),
            (
                Status::Wrong,
                "Exercise 1.2 — wrong answer\n  for input: width 4, height 3\n  expected 0.25, got 0.5",
            ),
            (
                Status::NotStarted,
                "Exercise 1.3 is not implemented yet (`todo!()` in labs/lab01/src/lib.rs)",
            ),
            (
                Status::BlockedBy("1.3".into()),
                "the check reached the unfinished stub of Exercise 1.3",
            ),
            (
                Status::Crashed,
                "panicked at labs/lab01/src/lib.rs:42:9: index out of bounds\n  for input: …",
            ),
            (
                Status::TimedOut,
                "Exercise 1.6 — ran past its time limit of 20 s",
            ),
        ];
        let mut first: Vec<ExerciseGrade> = lab01
            .iter()
            .enumerate()
            .map(|(k, info)| {
                let (status, output) = &statuses[k % statuses.len()];
                exercise(info, status.clone(), output)
            })
            .collect();
        first[0].program_output = "debug: 4 × 3 pixels <&>".into();
        first[1].images = vec![PathBuf::from(
            "images/lab01/default-base-colour-difference.png",
        )];
        first.extend(lab02.iter().map(|info| exercise(info, Status::Passed, "")));
        let mut second: Vec<ExerciseGrade> = lab01
            .iter()
            .map(|info| exercise(info, Status::Passed, ""))
            .collect();
        second[1] = exercise(
            &lab01[1],
            Status::Flagged,
            "labs/lab01/src/lib.rs:7 names `look_at_rh`, which answers Exercise 1.2",
        );
        // Passed with the key's code for the flagged part, which is charged to its own.
        second[5].output = "This check was judged with the answer key's `camera_basis` in place of yours (Exercise 1.2 fails on its own, and is charged there).".into();
        second[5].key_for = vec!["1.2".into()];
        second.extend(lab02.iter().map(|info| {
            exercise(
                info,
                Status::DoesNotCompile,
                "error[E0425]: cannot find value `hit` in this scope\n --> labs/lab02/src/lib.rs:88:16",
            )
        }));
        let grade = |student: &str, exercises| StudentGrade {
            student: student.into(),
            exercises,
            changed_files: Vec::new(),
            notes: Vec::new(),
            rejected: Vec::new(),
            flagged: Vec::new(),
            sandbox: "run in bubblewrap".into(),
            timings: Default::default(),
            answers: Vec::new(),
            deadlines: Vec::new(),
            manual: Vec::new(),
        };
        let mut class = vec![grade("ada", first), grade("grace, \"g\"", second)];
        // Questions of its own, so that the snapshot does not follow the docs' wording.
        let questions = course::answers::questions(
            "## Questions\n\n1. **Render time.** How does the time grow?\n2. Why flip y?\n",
        );
        let answers = course::answers::parse(
            "## Q1 — Render time\n\n> (the question)\n\nLinear in the pixels: 4× for twice the width and height. <&>\n\
             ![The times](figures/times.png)\n![gone](../../out/gone.png)\n\n## Q2\n\n<!-- Your answer here. -->\n",
        );
        // The answer's images: one taken, one not.
        let mut links = course::answers::image_links(&answers[0].text).into_iter();
        let images = vec![
            super::super::answers::AnswerImage {
                answer: 0,
                link: links.next().unwrap(),
                taken: Ok("images/lab01/answers-1.png".into()),
            },
            super::super::answers::AnswerImage {
                answer: 0,
                link: links.next().unwrap(),
                taken: Err("not in the submission".into()),
            },
        ];
        class[0].answers = vec![super::super::answers::LabAnswers {
            lab: LabId::of(1),
            questions,
            answers,
            images,
        }];
        class[0].changed_files = vec!["changed: Cargo.toml".into()];
        // Ada: lab 01 a day and a half late at 10% a day, and two questions graded by hand.
        let time = |t: &str| crate::grade::term::parse_time(t).unwrap();
        let policy = crate::grade::term::LatePolicy {
            penalty_per_day: 0.1,
            grace_minutes: 15,
            cap_days: Some(3),
        };
        let due = time("2026-10-05T23:59:00+02:00");
        let submitted = time("2026-10-07T11:59:00+02:00");
        class[0].deadlines = vec![LabDeadline {
            lab: LabId::of(1),
            due,
            extended: false,
            submitted: Submitted::At(submitted, "git commit".into()),
            lateness: Lateness::assess(
                &due,
                &Submitted::At(submitted, "git commit".into()),
                &policy,
            ),
        }];
        class[0].manual = vec![
            ManualPoints {
                lab: LabId::of(1),
                question: "Q1".into(),
                points: 1.5,
                max_points: 2.0,
                comment: "right idea | no units <b>".into(),
            },
            ManualPoints {
                lab: LabId::of(1),
                question: "Q2".into(),
                points: 3.0,
                max_points: 3.0,
                comment: String::new(),
            },
        ];
        // Grace: lab 01's time unknown, lab 02 due later by an extension.
        class[1].deadlines = vec![
            LabDeadline {
                lab: LabId::of(1),
                due,
                extended: false,
                submitted: Submitted::Unknown(None),
                lateness: Lateness::Unknown,
            },
            LabDeadline {
                lab: LabId::of(2),
                due: time("2026-10-14T23:59:00+02:00"),
                extended: true,
                submitted: Submitted::At(submitted, "given".into()),
                lateness: Lateness::OnTime,
            },
        ];
        class[1].flagged =
            vec!["labs/lab01/src/lib.rs:7: `look_at_rh` answers Exercise 1.2".into()];
        class[1].rejected = vec!["labs/lab02/src/big.bin: not a source file".into()];
        class
    }

    /// The files a class's grading writes, for a fixed class: any change to what an
    /// instructor's tools or a student read shows here (`cargo insta review`).
    #[test]
    fn the_grade_files_of_a_fixed_class_stay_the_same() {
        let class = fixed_class();
        insta::assert_snapshot!("gradebook.csv", gradebook(&class));
        let terms = CourseTerms::parse(
            Path::new("course.toml"),
            "[labs.1]\ndue = 2026-10-05T23:59:00+02:00\ncanvas_assignment = \"Lab 1 (4411)\"\n\n\
             [students.ada]\nname = \"Lovelace, Ada\"\ncanvas_id = \"1001\"\nsis_user_id = \"s1\"\n\
             sis_login_id = \"ada@uni.example\"\nsection = \"A\"\n",
            None,
        )
        .unwrap();
        insta::assert_snapshot!("canvas.csv", canvas(&class, Some(&terms)));
        insta::assert_snapshot!("junit.xml", junit(&class));
        // The failure image of ada's 1.2, which her results carry inline.
        let dir = std::env::temp_dir().join(format!("raylab-fixed-class-{}", std::process::id()));
        fs::create_dir_all(dir.join("images/lab01")).unwrap();
        fs::write(
            dir.join("images/lab01/default-base-colour-difference.png"),
            b"\x89PNG\r\n\x1a\n",
        )
        .unwrap();
        // And the figure of ada's answer.
        fs::write(dir.join("images/lab01/answers-1.png"), b"\x89PNG answer").unwrap();
        for (k, grade) in class.iter().enumerate() {
            let results =
                serde_json::to_string_pretty(&gradescope(grade, &dir)).unwrap_or_default();
            insta::assert_snapshot!(format!("results-{k}.json"), unstamped(&results));
            insta::assert_snapshot!(format!("report-{k}.md"), unstamped(&markdown(grade)));
        }
        // The pages show the same lateness and points graded by hand, escaped.
        let page = html(&class[0]);
        assert!(page.contains("<strong>18.5/29 points</strong>"), "{page}");
        assert!(
            page.contains(
                "1 day 12 h late (2 started days); late penalty 20% of the lab's points: −3 points."
            ),
            "{page}"
        );
        assert!(page.contains("<h3>Graded by hand</h3>"), "{page}");
        assert!(page.contains("right idea | no units &lt;b&gt;"), "{page}");
        assert!(
            page.contains("<img src=\"images/lab01/answers-1.png\" alt=\"The times\">"),
            "{page}"
        );
        assert!(
            page.contains(
                "The image <code>../../out/gone.png</code> was not taken: not in the submission"
            ),
            "{page}"
        );
        let results = serde_json::to_string(&gradescope(&class[0], &dir)).unwrap();
        assert!(
            results.contains(&format!(
                "<img src=\\\"data:image/png;base64,{}\\\" alt=\\\"The times\\\"",
                base64::engine::general_purpose::STANDARD.encode(b"\x89PNG answer")
            )),
            "{results}"
        );
        let class_page = index(&class, None);
        assert!(class_page.contains("<th>lateness</th>"), "{class_page}");
        assert!(
            class_page.contains("unknown (no submission time): no penalty"),
            "{class_page}"
        );
        assert!(class_page.contains("4.5/15"), "{class_page}");
        fs::remove_dir_all(&dir).unwrap();
        let ungraded = ungraded_results("labs/ holds no lab's sources");
        insta::assert_snapshot!("results-ungraded.json", unstamped(&ungraded));
    }

    /// A lab not submitted (its files as the handout's commits left them) is "no submission" in
    /// every file a grading writes, and costs nothing, where a submission at the handout's
    /// time would be a week late at half the lab a day.
    #[test]
    fn no_submission_is_never_late_in_any_grade_file() {
        let mut class = fixed_class();
        let terms = CourseTerms::parse(
            Path::new("course.toml"),
            "[late]\npenalty_per_day = 0.5\n\n[labs.1]\ndue = 2026-09-21T23:59:00+02:00\n",
            None,
        )
        .unwrap();
        let lab = LabId::of(1);
        class[1].deadlines = super::super::term::deadlines(
            &class[1].student.clone(),
            &[lab],
            Some(&terms),
            &|_| Submitted::Nothing,
            None,
        );
        let grace = &class[1];
        assert_eq!(grace.deadlines[0].lateness, Lateness::NoSubmission);
        assert_eq!((grace.lab_penalty(lab), grace.lab_score(lab)), (0.0, 7.0));
        let line = "due 2026-09-21T23:59:00+02:00; no submission (no commit but the handout's own changed labs/lab01/src/ or labs/lab01/answers.md); not late: no penalty";
        let report = markdown(grace);
        assert!(report.contains(&format!("Deadline: {line}.")), "{report}");
        let page = html(grace);
        assert!(page.contains(line), "{page}");
        let class_page = index(&class, None);
        assert!(class_page.contains(line), "{class_page}");
        // (The class page has Ada's late lab beside it.)
        for text in [&report, &page] {
            assert!(!text.contains(" late (") && !text.contains("penalty 50%"));
        }
        let dir = std::env::temp_dir().join(format!("raylab-no-submission-{}", std::process::id()));
        let results = gradescope(grace, &dir);
        let output = results["output"].as_str().unwrap();
        assert!(output.contains(&format!("Lab 01: {line}.")), "{output}");
        let tests: f64 = results["tests"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| t["score"].as_f64().unwrap())
            .sum();
        assert_eq!(results["score"].as_f64(), Some(tests), "{results}");
        let gradebook = gradebook(&class);
        let mut rows = csv::Reader::from_reader(gradebook.as_bytes());
        let header = rows.headers().unwrap().clone();
        let row = rows.records().nth(1).unwrap().unwrap();
        let field = |name: &str| &row[header.iter().position(|h| h == name).unwrap()];
        assert_eq!(
            (
                field("lab01_submitted"),
                field("lab01_days_late"),
                field("lab01_penalty"),
                field("total")
            ),
            ("no submission", "", "0", "7"),
            "{gradebook}"
        );
        let canvas = canvas(&class, Some(&terms));
        assert!(
            canvas
                .lines()
                .any(|l| l.starts_with("\"grace, \"\"g\"\"\",") && l.ends_with(",7,0")),
            "{canvas}"
        );
    }
}
