//! The grade reports: per student a Markdown and an HTML report and a Gradescope
//! `results.json`; per class a CSV gradebook, a JUnit XML file and an HTML index.

use std::fmt::Write as _;
use std::fs;
use std::path::Path;

use framework::Error;
use framework::grading::Visibility;

use super::{ExerciseGrade, StudentGrade};
use crate::handout::io;

/// Writes `report.md`, `report.html` and `results.json` of `grade` into `dir`.
pub fn write_student(grade: &StudentGrade, dir: &Path) -> Result<(), Error> {
    fs::create_dir_all(dir).map_err(io(dir))?;
    write(&dir.join("report.md"), &markdown(grade))?;
    write(&dir.join("report.html"), &html(grade))?;
    let results = serde_json::to_string_pretty(&gradescope(grade)).unwrap_or_default();
    write(&dir.join("results.json"), &results)
}

/// Writes `gradebook.csv`, `junit.xml` and `index.html` of the class into `dir`.
pub fn write_class(grades: &[StudentGrade], dir: &Path) -> Result<(), Error> {
    fs::create_dir_all(dir).map_err(io(dir))?;
    write(&dir.join("gradebook.csv"), &gradebook(grades))?;
    write(&dir.join("junit.xml"), &junit(grades))?;
    write(&dir.join("index.html"), &index(grades))
}

fn write(path: &Path, text: &str) -> Result<(), Error> {
    fs::write(path, text).map_err(io(path))
}

/// The labs of a grade, in order, each with its exercises.
fn by_lab(grade: &StudentGrade) -> Vec<(u32, Vec<&ExerciseGrade>)> {
    let mut labs: Vec<(u32, Vec<&ExerciseGrade>)> = Vec::new();
    for e in &grade.exercises {
        match labs.last_mut() {
            Some((lab, list)) if *lab == e.info.lab => list.push(e),
            _ => labs.push((e.info.lab, vec![e])),
        }
    }
    labs
}

/// Points earned and available in `exercises`.
fn points(exercises: &[&ExerciseGrade]) -> (u32, u32) {
    exercises
        .iter()
        .fold((0, 0), |(e, t), x| (e + x.score, t + x.info.points))
}

fn lab_title(lab: u32) -> &'static str {
    framework::labs::lab(lab).map_or("", |l| l.title)
}

fn verdict(e: &ExerciseGrade) -> &'static str {
    if e.passed { "passed" } else { "failed" }
}

fn markdown(grade: &StudentGrade) -> String {
    let mut md = format!(
        "# Grade report: {}\n\n**{}/{} points**\n\n",
        grade.student,
        grade.score(),
        grade.max_score()
    );
    if !grade.changed_files.is_empty() {
        md.push_str("## Files changed outside `labs/labNN/src/` (not used for grading)\n\n");
        for change in &grade.changed_files {
            let _ = writeln!(md, "- {change}");
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
            let _ = writeln!(md, "- {line}");
        }
        md.push('\n');
    }
    if !grade.flagged.is_empty() {
        md.push_str("## Flagged: sources that read files outside their lab at compile time, or name framework code that answers an exercise\n\n");
        for line in &grade.flagged {
            let _ = writeln!(md, "- flagged: {line}");
        }
        md.push('\n');
    }
    if !grade.sandbox.is_empty() {
        let _ = writeln!(md, "Student code was {}.\n", grade.sandbox);
    }
    for (lab, exercises) in by_lab(grade) {
        let (earned, total) = points(&exercises);
        let _ = writeln!(
            md,
            "## Lab {lab:02} — {} ({earned}/{total})\n\n| exercise | function | result | points |\n| --- | --- | --- | --- |",
            lab_title(lab)
        );
        for e in &exercises {
            let _ = writeln!(
                md,
                "| {} {} | `{}` | {} | {}/{} |",
                e.info.id,
                e.info.title,
                e.info.function,
                verdict(e),
                e.score,
                e.info.points
            );
        }
        md.push('\n');
        for e in exercises
            .iter()
            .filter(|e| !e.passed || !e.program_output.is_empty())
        {
            let _ = writeln!(
                md,
                "### Exercise {} — `{}`\n\n{}",
                e.info.id,
                e.info.function,
                if e.passed {
                    "Passed.\n".to_string()
                } else {
                    fenced(&e.output)
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
    }
    md
}

/// The heading of what the student's code printed, set apart from the verdict.
const PROGRAM_OUTPUT: &str = "Output of your code (as it printed it; not part of the verdict)";

/// `text` as a Markdown code block whose fence no line of `text` can close.
fn fenced(text: &str) -> String {
    let longest = text.split(|c| c != '`').map(str::len).max().unwrap_or(0);
    let fence = "`".repeat(longest.max(2) + 1);
    format!("{fence}text\n{text}\n{fence}\n")
}

/// "student", "reference" or "difference", from a failure image's file name.
fn image_caption(image: &Path) -> String {
    let stem = image.file_stem().unwrap_or_default().to_string_lossy();
    stem.rsplit('-').next().unwrap_or_default().to_string()
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

const STYLE: &str = "body{font-family:sans-serif;max-width:70em;margin:2em auto;padding:0 1em}\
table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:.3em .6em;text-align:left}\
.passed{color:#060}.failed{color:#a00}pre{background:#f4f4f4;padding:.6em;white-space:pre-wrap}\
pre.program{border-left:4px solid #c90}\
.images{display:flex;gap:1em;flex-wrap:wrap}figure{margin:0}img{image-rendering:pixelated;\
width:320px;border:1px solid #ccc}";

fn html(grade: &StudentGrade) -> String {
    let mut h = format!(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{0}: grade report</title><style>{STYLE}</style></head><body>\n<h1>Grade report: {0}</h1>\n<p><strong>{1}/{2} points</strong></p>\n",
        escape(&grade.student),
        grade.score(),
        grade.max_score()
    );
    if !grade.changed_files.is_empty() {
        h.push_str("<h2>Files changed outside <code>labs/labNN/src/</code> (not used for grading)</h2><ul>\n");
        for change in &grade.changed_files {
            let _ = writeln!(h, "<li>{}</li>", escape(change));
        }
        h.push_str("</ul>\n");
    }
    for (title, lines) in [
        ("Notes", &grade.notes),
        ("Files not taken from the submission", &grade.rejected),
        (
            "Flagged: sources that read files outside their lab at compile time, or name framework code that answers an exercise",
            &grade.flagged,
        ),
    ] {
        if lines.is_empty() {
            continue;
        }
        let _ = writeln!(h, "<h2>{title}</h2><ul>");
        for line in lines {
            let _ = writeln!(h, "<li>{}</li>", escape(line));
        }
        h.push_str("</ul>\n");
    }
    if !grade.sandbox.is_empty() {
        let _ = writeln!(h, "<p>Student code was {}.</p>", escape(&grade.sandbox));
    }
    for (lab, exercises) in by_lab(grade) {
        let (earned, total) = points(&exercises);
        let _ = writeln!(
            h,
            "<h2>Lab {lab:02} — {} ({earned}/{total})</h2>\n<table><tr><th>exercise</th><th>function</th><th>result</th><th>points</th></tr>",
            escape(lab_title(lab))
        );
        for e in &exercises {
            let _ = writeln!(
                h,
                "<tr><td><a href=\"#ex-{0}\">{0}</a> {1}</td><td><code>{2}</code></td><td class=\"{3}\">{3}</td><td>{4}/{5}</td></tr>",
                e.info.id,
                escape(e.info.title),
                escape(e.info.function),
                verdict(e),
                e.score,
                e.info.points
            );
        }
        h.push_str("</table>\n");
        for e in exercises
            .iter()
            .filter(|e| !e.passed || !e.program_output.is_empty())
        {
            let _ = writeln!(
                h,
                "<h3 id=\"ex-{0}\">Exercise {0} — <code>{1}</code></h3>\n{2}",
                e.info.id,
                escape(e.info.function),
                if e.passed {
                    "<p>Passed.</p>".to_string()
                } else {
                    format!("<pre>{}</pre>", escape(&e.output))
                }
            );
            if !e.program_output.is_empty() {
                let _ = writeln!(
                    h,
                    "<p>{PROGRAM_OUTPUT}:</p>\n<pre class=\"program\">{}</pre>",
                    escape(&e.program_output)
                );
            }
            if !e.images.is_empty() {
                h.push_str("<div class=\"images\">\n");
                for image in &e.images {
                    let src = image.to_string_lossy().replace('\\', "/");
                    let _ = writeln!(
                        h,
                        "<figure><img src=\"{}\" alt=\"{1}\"><figcaption>{1}</figcaption></figure>",
                        escape(&src),
                        escape(&image_caption(image))
                    );
                }
                h.push_str("</div>\n");
            }
        }
    }
    h.push_str("</body></html>\n");
    h
}

/// Gradescope's autograder `results.json` of one submission.
fn gradescope(grade: &StudentGrade) -> serde_json::Value {
    let tests: Vec<serde_json::Value> = grade
        .exercises
        .iter()
        .map(|e| {
            serde_json::json!({
                "name": format!("Exercise {} — {} ({})", e.info.id, e.info.title, e.info.function),
                "number": e.info.id,
                "score": e.score,
                "max_score": e.info.points,
                "status": verdict(e),
                "output": if e.program_output.is_empty() {
                    e.output.clone()
                } else {
                    format!("{}\n\n{PROGRAM_OUTPUT}:\n{}", e.output, e.program_output)
                },
                "visibility": match e.info.visibility {
                    Visibility::Visible => "visible",
                    Visibility::Hidden => "after_published",
                },
            })
        })
        .collect();
    let mut output = String::new();
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
    serde_json::json!({
        "score": grade.score(),
        "max_score": grade.max_score(),
        "output": output,
        "tests": tests,
    })
}

/// A CSV field, quoted when it needs to be.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// One row per student: the points of each exercise, the total, the maximum, and how many files
/// outside the lab sources were changed.
fn gradebook(grades: &[StudentGrade]) -> String {
    let mut csv = String::from("student");
    if let Some(first) = grades.first() {
        for e in &first.exercises {
            let _ = write!(csv, ",{}", e.info.id);
        }
    }
    csv.push_str(",total,max_score,changed_files\n");
    for grade in grades {
        csv.push_str(&csv_field(&grade.student));
        for e in &grade.exercises {
            let _ = write!(csv, ",{}", e.score);
        }
        let _ = writeln!(
            csv,
            ",{},{},{}",
            grade.score(),
            grade.max_score(),
            grade.changed_files.len()
        );
    }
    csv
}

/// JUnit XML: a test suite per student, a test case per exercise.
fn junit(grades: &[StudentGrade]) -> String {
    let failures = |g: &StudentGrade| g.exercises.iter().filter(|e| !e.passed).count();
    let mut xml = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"raylab grade\" tests=\"{}\" failures=\"{}\">\n",
        grades.iter().map(|g| g.exercises.len()).sum::<usize>(),
        grades.iter().map(failures).sum::<usize>()
    );
    for grade in grades {
        let _ = writeln!(
            xml,
            "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" time=\"{:.3}\">",
            escape(&grade.student),
            grade.exercises.len(),
            failures(grade),
            grade.exercises.iter().map(|e| e.seconds).sum::<f64>()
        );
        for e in &grade.exercises {
            let _ = write!(
                xml,
                "    <testcase classname=\"{}.lab{:02}\" name=\"Exercise {} {}\" time=\"{:.3}\"",
                escape(&grade.student),
                e.info.lab,
                e.info.id,
                escape(e.info.function),
                e.seconds
            );
            if e.passed && e.program_output.is_empty() {
                xml.push_str("/>\n");
                continue;
            }
            xml.push_str(">\n");
            if !e.passed {
                let first = e.output.lines().next().unwrap_or("failed");
                let _ = writeln!(
                    xml,
                    "      <failure message=\"{}\">{}</failure>",
                    escape(first),
                    escape(&e.output)
                );
            }
            if !e.program_output.is_empty() {
                let _ = writeln!(
                    xml,
                    "      <system-out>{}</system-out>",
                    escape(&e.program_output)
                );
            }
            xml.push_str("    </testcase>\n");
        }
        xml.push_str("  </testsuite>\n");
    }
    xml.push_str("</testsuites>\n");
    xml
}

/// The class page: each student's total, linking to their report.
fn index(grades: &[StudentGrade]) -> String {
    let mut h = format!(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Grades</title><style>{STYLE}</style></head><body>\n<h1>Grades</h1>\n<table><tr><th>student</th><th>points</th><th>files changed outside labs/*/src</th></tr>\n"
    );
    for g in grades {
        let _ = writeln!(
            h,
            "<tr><td><a href=\"{0}/report.html\">{0}</a></td><td>{1}/{2}</td><td>{3}</td></tr>",
            escape(&g.student),
            g.score(),
            g.max_score(),
            g.changed_files.len()
        );
    }
    h.push_str("</table>\n<p>Also: gradebook.csv, junit.xml, and each student's results.json (Gradescope).</p>\n</body></html>\n");
    h
}
