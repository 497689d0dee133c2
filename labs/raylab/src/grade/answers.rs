//! The written answers of a submission (`labs/labNN/answers.md`), collected for the student's
//! report and the class page: graded by hand, with points from a CSV of the instructor's.

use std::fmt::Write as _;

use course::LabId;
use course::answers::{Answer, Question};
use maud::{Markup, html};

use super::StudentGrade;

/// One lab's written answers as a submission holds them.
pub struct LabAnswers {
    /// The lab.
    pub lab: LabId,
    /// The lab's questions, as its docs page in the course's repository states them.
    pub questions: Vec<Question>,
    /// The student's answers, by question id.
    pub answers: Vec<Answer>,
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
        }
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
                    answer
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
                }
            }
        }
    }
}

/// The class page's table of written answers: per student and lab, how many questions are
/// answered, linking to the answers in the student's report. Nothing when no one wrote any.
pub fn class_table(grades: &[StudentGrade]) -> Markup {
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
