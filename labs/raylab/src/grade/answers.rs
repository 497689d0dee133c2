//! The written answers of a submission (`labs/labNN/answers.md`), collected for the student's
//! report and the class page: graded by hand, with points from a CSV of the instructor's. The
//! images the answers show (`![caption](figures/NAME.png)`) are taken from the submission as
//! every intake takes a file ([`super::submission::read_answer_image`]) and shown with them.

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use course::LabId;
use course::answers::{Answer, ImageLink, Question};
use maud::{Markup, html};
use raylab_core::Error;

use super::markdown::code_span;
use super::submission::{self, MAX_ANSWER_IMAGE_BYTES, MAX_ANSWER_IMAGES_BYTES};
use crate::handout::io;

/// An image one answer shows.
pub struct AnswerImage {
    /// The answer that shows it: its index in [`LabAnswers::answers`].
    pub answer: usize,
    /// Where the answer's text shows it, and what it names.
    pub link: ImageLink,
    /// The image as the reports have it (relative to the student's report directory), or why
    /// it was not taken.
    pub taken: Result<PathBuf, String>,
}

/// One lab's written answers as a submission holds them.
pub struct LabAnswers {
    /// The lab.
    pub lab: LabId,
    /// The lab's questions, as its docs page in the course's repository states them.
    pub questions: Vec<Question>,
    /// The student's answers, by question id.
    pub answers: Vec<Answer>,
    /// The images the answers show, in the order of the answers file.
    pub images: Vec<AnswerImage>,
}

impl LabAnswers {
    /// Lab `lab`'s answers file `text`, read against the lab's questions.
    pub fn read(lab: LabId, text: &str) -> Self {
        let docs = crate::handout::repository_root().join(lab.docs());
        let questions = std::fs::read_to_string(docs)
            .map(|docs| course::answers::questions(&docs))
            .unwrap_or_default();
        Self {
            lab,
            questions,
            answers: course::answers::parse(text),
            images: Vec::new(),
        }
    }

    /// Takes the images the answers show from `submission` into `dir` (the student's report
    /// directory), as `images/labNN/answers-K.png` (or `.jpg`): each named by a path inside the
    /// submission, resolved from `labs/labNN/`, a PNG or JPEG regular file of at most 1 MiB and
    /// 4096 pixels a side; at most 16 images and 4 MiB per lab. An image shown twice is taken
    /// once. Returns a line for each image not taken, and why; an `Err` is a failure to write
    /// the report directory.
    pub fn take_images(&mut self, submission: &Path, dir: &Path) -> Result<Vec<String>, Error> {
        let lab = self.lab;
        let mut refused = Vec::new();
        let mut taken: Vec<(String, Result<PathBuf, String>)> = Vec::new();
        let mut total = 0u64;
        let mut images = Vec::new();
        for (index, answer) in self.answers.iter().enumerate() {
            for link in course::answers::image_links(&answer.text) {
                let result = match taken.iter().find(|(target, _)| *target == link.target) {
                    Some((_, result)) => result.clone(),
                    None => {
                        let result = if taken.len() == course::answers::MAX_IMAGES {
                            Err(format!(
                                "more than {} images in one lab's answers (not taken)",
                                course::answers::MAX_IMAGES
                            ))
                        } else {
                            let budget =
                                MAX_ANSWER_IMAGE_BYTES.min(MAX_ANSWER_IMAGES_BYTES - total);
                            self.take_one(submission, dir, &link.target, taken.len() + 1, budget)?
                        };
                        if let Ok(path) = &result {
                            total += fs::metadata(dir.join(path)).map_or(0, |m| m.len());
                        }
                        if let Err(why) = &result {
                            refused.push(format!(
                                "{}: the image {}: {why}",
                                lab.answers(),
                                submission::shown(Path::new(&link.target))
                            ));
                        }
                        taken.push((link.target.clone(), result.clone()));
                        result
                    }
                };
                images.push(AnswerImage {
                    answer: index,
                    link,
                    taken: result,
                });
            }
        }
        self.images = images;
        Ok(refused)
    }

    /// Takes the image `target` of the answers as the `index`th image, at most `budget` bytes:
    /// its path relative to `dir`, or why it was not taken.
    fn take_one(
        &self,
        submission: &Path,
        dir: &Path,
        target: &str,
        index: usize,
        budget: u64,
    ) -> Result<Result<PathBuf, String>, Error> {
        let relative = match submission::answer_image_path(self.lab, target) {
            Ok(relative) => relative,
            Err(why) => return Ok(Err(why)),
        };
        let image = match submission::read_answer_image(submission, &relative, budget) {
            Ok(image) => image,
            Err(why) if budget < MAX_ANSWER_IMAGE_BYTES && why.starts_with("over") => {
                return Ok(Err(format!(
                    "over the 4 MiB limit of one lab's images in total (not taken): {why}"
                )));
            }
            Err(why) => return Ok(Err(why)),
        };
        let path = PathBuf::from("images")
            .join(self.lab.to_string())
            .join(format!("answers-{index}.{}", image.kind.extension()));
        let file = dir.join(&path);
        if let Some(parent) = file.parent() {
            fs::create_dir_all(parent).map_err(io(parent))?;
        }
        fs::write(&file, &image.bytes).map_err(io(&file))?;
        Ok(Ok(path))
    }

    /// The images the answer to `question` shows (the first answer to it, as
    /// [`Self::answer`]).
    pub fn images_of<'a>(&'a self, question: &Question) -> impl Iterator<Item = &'a AnswerImage> {
        let index = self.answers.iter().position(|a| a.id == question.id);
        self.images.iter().filter(move |i| Some(i.answer) == index)
    }

    /// The answer to `question` as Markdown for the report beside `images/`: each image it
    /// shows pointed at the grader's copy, or replaced by why it was not taken.
    fn answer_markdown(&self, question: &Question) -> String {
        let text = self.answer(question);
        let mut out = String::with_capacity(text.len());
        let mut at = 0;
        // The links in the order of the text, as `take_images` found them.
        for image in self.images_of(question) {
            let range = image.link.range.clone();
            let Some(before) = text.get(at..range.start) else {
                continue;
            };
            out.push_str(before);
            match &image.taken {
                Ok(path) => {
                    let _ = write!(out, "![{}]({})", image.link.alt, path.display());
                }
                Err(why) => {
                    let _ = write!(
                        out,
                        "*(the image {} was not taken: {why})*",
                        code_span(&image.link.target)
                    );
                }
            }
            at = range.end;
        }
        out.push_str(&text[at..]);
        out
    }

    /// The answer to `question`, empty when there is none.
    fn answer(&self, question: &Question) -> &str {
        self.answers
            .iter()
            .find(|a| a.id == question.id)
            .map_or("", |a| a.text.as_str())
    }

    /// How many questions are answered, and how many there are.
    pub fn counts(&self) -> (usize, usize) {
        let answered = self
            .questions
            .iter()
            .filter(|q| !self.answer(q).is_empty())
            .count();
        (answered, self.questions.len())
    }

    /// The answers' section of the report's Markdown.
    pub fn markdown(&self) -> String {
        let (answered, total) = self.counts();
        let mut md =
            format!("### Written answers ({answered} of {total} answered; graded by hand)\n\n");
        for q in &self.questions {
            let answer = self.answer(q);
            let _ = writeln!(
                md,
                "**{}{}** {}\n\n{}\n",
                q.id,
                q.title
                    .as_ref()
                    .map_or(String::new(), |t| format!(" — {t}")),
                q.body(),
                if answer.is_empty() {
                    "*(no answer)*".to_string()
                } else {
                    self.answer_markdown(q)
                        .lines()
                        .map(|l| format!("> {l}"))
                        .collect::<Vec<_>>()
                        .join("\n")
                }
            );
        }
        md
    }

    /// The answers' section of the report's page.
    pub fn html(&self) -> Markup {
        let (answered, total) = self.counts();
        html! {
            h3 id={ "answers-" (self.lab) } {
                "Written answers (" (answered) " of " (total) " answered; graded by hand)"
            }
            @for q in &self.questions {
                @let answer = self.answer(q);
                p {
                    strong { (q.id) @if let Some(title) = &q.title { " — " (title) } }
                    " " (q.body())
                }
                @if answer.is_empty() {
                    p { em { "(no answer)" } }
                } @else {
                    pre class="answer" { (answer) }
                    (self.figures(q))
                }
            }
        }
    }

    /// The images of the answer to `question` as the report's page shows them: each image
    /// taken, and why each other one was not.
    pub fn figures(&self, question: &Question) -> Markup {
        html! {
            @let images: Vec<&AnswerImage> = self.images_of(question).collect();
            @if images.iter().any(|i| i.taken.is_ok()) {
                div class="images" {
                    @for image in &images {
                        @if let Ok(path) = &image.taken {
                            figure {
                                img src=(path.to_string_lossy().replace('\\', "/")) alt=(image.link.alt);
                                figcaption { (image.link.alt) }
                            }
                        }
                    }
                }
            }
            @for image in &images {
                @if let Err(why) = &image.taken {
                    p { "The image " code { (image.link.target) } " was not taken: " (why) }
                }
            }
        }
    }

    /// The questions with the answer of each, for Gradescope's page: `(question, answer)`.
    pub fn questions_and_answers(&self) -> impl Iterator<Item = (&Question, &str)> {
        self.questions.iter().map(|q| (q, self.answer(q)))
    }
}
