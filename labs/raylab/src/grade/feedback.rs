//! Feedback that stands alone: the failure images inlined as `data:` URLs, in Gradescope's
//! test output (its `html` format; Gradescope serves no file of the autograder's, so an image
//! must travel inside `results.json`) and in one self-contained page per student for an LMS.

use std::fs;
use std::path::Path;

use base64::Engine as _;
use maud::html;

use super::answers::LabAnswers;
use super::grades::{ExerciseGrade, StudentGrade, image_caption};

/// The most image bytes (before encoding) one `results.json` carries: Gradescope stores the
/// file with the submission, and a page of megabytes loads slowly. Images past it are named,
/// and the per-student page has them all.
pub const RESULTS_IMAGE_BUDGET: u64 = 768 * 1024;

/// The largest image inlined at all.
const IMAGE_LIMIT: u64 = 512 * 1024;

/// `path` (a PNG, or a JPEG named `.jpg`, that the grader wrote) as a `data:` URL, when it is a
/// regular file within [`IMAGE_LIMIT`].
fn data_url(path: &Path) -> Option<String> {
    let meta = fs::symlink_metadata(path).ok()?;
    if !meta.is_file() || meta.len() > IMAGE_LIMIT {
        return None;
    }
    let bytes = fs::read(path).ok()?;
    let kind = match path.extension().and_then(|e| e.to_str()) {
        Some("jpg") => "jpeg",
        _ => "png",
    };
    Some(format!(
        "data:image/{kind};base64,{}",
        base64::engine::general_purpose::STANDARD.encode(bytes)
    ))
}

/// `path` (relative to `dir`) as a `data:` URL while `budget` lasts, which it uses up.
fn budgeted_data_url(dir: &Path, path: &Path, budget: &mut u64) -> Option<String> {
    let path = dir.join(path);
    let size = fs::symlink_metadata(&path).ok()?.len();
    if size > *budget {
        return None;
    }
    let url = data_url(&path)?;
    *budget -= size;
    Some(url)
}

/// Gradescope's output of lab `answers`' written answers, in its `html` format: each question
/// with the student's answer and the images it shows (relative to `dir`) while `budget` lasts,
/// which they use up.
pub fn gradescope_answers(answers: &LabAnswers, dir: &Path, budget: &mut u64) -> String {
    let mut left_out = 0;
    let mut shown = Vec::new();
    for (question, answer) in answers.questions_and_answers() {
        let images: Vec<(String, String)> = answers
            .images_of(question)
            .filter_map(|image| {
                let path = image.taken.as_ref().ok()?;
                let url = budgeted_data_url(dir, path, budget);
                left_out += usize::from(url.is_none());
                Some((image.link.alt.clone(), url?))
            })
            .collect();
        shown.push((question, answer, images));
    }
    html! {
        @for (question, answer, images) in &shown {
            p { strong { (question.id) @if let Some(title) = &question.title { " — " (title) } } " " (question.body()) }
            @if answer.is_empty() {
                p { em { "(no answer)" } }
            } @else {
                pre { (answer) }
            }
            @for (caption, url) in images {
                figure style="display:inline-block;margin:0 1em 1em 0" {
                    img src=(url) alt=(caption) style="max-width:480px";
                    figcaption { (caption) }
                }
            }
            @for image in answers.images_of(question) {
                @if let Err(why) = &image.taken {
                    p { "The image " code { (image.link.target) } " was not taken: " (why) }
                }
            }
        }
        @if left_out > 0 {
            p { (left_out) " more image(s) of these answers are in your instructor's per-student report." }
        }
    }
    .into_string()
}

/// Gradescope's output of a failed exercise with images, in its `html` format: the text of
/// `output` (escaped) and the images of `e` (relative to `dir`, the student's report directory)
/// while `budget` lasts, which they use up.
pub fn gradescope_html(e: &ExerciseGrade, output: &str, dir: &Path, budget: &mut u64) -> String {
    let shown: Vec<(String, String)> = e
        .images
        .iter()
        .filter_map(|image| {
            let url = budgeted_data_url(dir, image, budget)?;
            Some((image_caption(image), url))
        })
        .collect();
    let left_out = e.images.len() - shown.len();
    html! {
        pre { (output) }
        @for (caption, url) in &shown {
            figure style="display:inline-block;margin:0 1em 1em 0" {
                img src=(url) alt=(caption) style="width:320px;image-rendering:pixelated";
                figcaption { (caption) }
            }
        }
        @if left_out > 0 {
            p { (left_out) " more image(s) of this check are in your instructor's per-student report." }
        }
    }
    .into_string()
}

/// `page` (a student's `report.html`, whose images are files relative to `dir`) with every
/// image that is there inlined: one file to upload to an LMS. An image that is not there keeps
/// its link.
pub fn standalone(page: &str, dir: &Path) -> String {
    let marker = "<img src=\"";
    let mut out = String::with_capacity(page.len());
    let mut rest = page;
    while let Some(at) = rest.find(marker) {
        let (before, after) = rest.split_at(at + marker.len());
        out.push_str(before);
        let end = after.find('"').unwrap_or(after.len());
        let link = &after[..end];
        let inlined = is_relative_file(link)
            .then(|| data_url(&dir.join(html_unescape(link))))
            .flatten();
        out.push_str(inlined.as_deref().unwrap_or(link));
        rest = &after[end..];
    }
    out.push_str(rest);
    out
}

/// Whether a link of a page is a plain relative path (no scheme, not absolute, no `..`).
fn is_relative_file(link: &str) -> bool {
    !link.contains(':')
        && !link.starts_with('/')
        && !link.split('/').any(|part| part == "..")
        && !link.is_empty()
}

/// The text of an attribute value as maud escapes it.
fn html_unescape(text: &str) -> String {
    text.replace("&quot;", "\"")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&")
}

/// The file name of `grade`'s page in the class's folder of pages (`DIR/pages/`).
pub fn page_name(grade: &StudentGrade) -> String {
    format!("{}.html", grade.student)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_page_stands_alone_with_its_images_inlined() {
        let dir = std::env::temp_dir().join(format!("raylab-feedback-{}", std::process::id()));
        fs::create_dir_all(dir.join("images/lab01")).unwrap();
        fs::write(dir.join("images/lab01/a-student.png"), b"\x89PNG fake").unwrap();
        let page = "<p>x</p><img src=\"images/lab01/a-student.png\" alt=\"student\">\
                    <img src=\"images/lab01/missing.png\"><img src=\"../secret.png\">";
        let out = standalone(page, &dir);
        assert!(
            out.contains("<img src=\"data:image/png;base64,iVBORyBmYWtl\""),
            "{out}"
        );
        assert!(
            out.contains("<img src=\"images/lab01/missing.png\">"),
            "{out}"
        );
        assert!(out.contains("<img src=\"../secret.png\">"), "{out}");
        fs::remove_dir_all(&dir).unwrap();
    }
}
