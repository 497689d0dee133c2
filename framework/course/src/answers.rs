//! A lab's written answers: the numbered questions of its docs page (the list under
//! `## Questions` in `docs/labNN.md`), the file `labs/labNN/answers.md` a student answers them
//! in (one `## Qn` heading per question), and that file read back for grading.

use crate::LabId;

/// The heading of the docs' section whose numbered list holds a lab's questions.
const SECTION: &str = "## Questions";

/// The line under each question of a fresh answers file, which an answer replaces.
pub const PLACEHOLDER: &str = "<!-- Your answer here. -->";

/// The largest answers file read (a submission's file may be anything).
pub const FILE_LIMIT: u64 = 256 * 1024;

/// The folder beside a lab's answers file (`labs/labNN/figures/`) that holds the figures the
/// answers show: `raylab report` copies there each figure of its own that the answers name as
/// `figures/NAME.png`, where git keeps it (git ignores `out/`).
pub const FIGURES: &str = "figures";

/// The most images of one lab's answers that grading takes.
pub const MAX_IMAGES: usize = 16;

/// The largest width or height, in pixels, of an image grading takes from the answers.
pub const MAX_SIDE: u32 = 4096;

/// An image shown in answers: Markdown's `![alt](target)` or `![alt](target "title")`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ImageLink {
    /// Where in the text it is: from its `!` to its closing `)`.
    pub range: std::ops::Range<usize>,
    /// Its text (the caption).
    pub alt: String,
    /// Where it points, as written (without `<…>` and the title).
    pub target: String,
}

/// The images `text` shows, in order: each inline Markdown image `![alt](target)` on one line
/// (with an optional title, or the target in `<…>`). Reference-style images and HTML `<img>`
/// are not read.
pub fn image_links(text: &str) -> Vec<ImageLink> {
    let mut links = Vec::new();
    let mut from = 0;
    while let Some(at) = text[from..].find("![").map(|i| from + i) {
        from = at + 2;
        let rest = &text[from..];
        // The alt text: up to the first `]` (nested brackets are not read).
        let Some(close) = rest.find(']') else { break };
        let alt = &rest[..close];
        let Some(inner) = rest[close + 1..].strip_prefix('(') else {
            continue;
        };
        let Some(end) = inner.find(')') else { continue };
        if alt.contains('\n') || inner[..end].contains('\n') {
            continue;
        }
        let inside = inner[..end].trim();
        let target = match inside.strip_prefix('<') {
            Some(bracketed) => match bracketed.split_once('>') {
                Some((target, _)) => target,
                None => continue,
            },
            None => inside.split_whitespace().next().unwrap_or_default(),
        };
        // `inner` starts after `](`.
        let start = from + close + 2;
        links.push(ImageLink {
            range: at..start + end + 1,
            alt: alt.trim().to_string(),
            target: target.to_string(),
        });
        from = start + end + 1;
    }
    links
}

/// One question of a lab's docs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Question {
    /// `Q1`, `Q2`, …: its number in the docs' list, as the answers file and the manual points
    /// name it.
    pub id: String,
    /// Its bold lead (`**Render time.**` gives "Render time"), if it has one.
    pub title: Option<String>,
    /// The whole question as the docs state it, on one line.
    pub text: String,
}

impl Question {
    /// The question without its bold lead (the [`Question::title`]).
    pub fn body(&self) -> &str {
        match &self.title {
            Some(_) => self
                .text
                .strip_prefix("**")
                .and_then(|rest| rest.split_once("**"))
                .map_or(self.text.as_str(), |(_, body)| body.trim_start()),
            None => &self.text,
        }
    }
}

/// One answer of a student's answers file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Answer {
    /// The question's id (`Q1`).
    pub id: String,
    /// The answer: the text under the heading without the quoted question and the placeholder;
    /// empty when not answered.
    pub text: String,
}

/// The questions of the docs page `docs`: each item of the numbered list of its
/// `## Questions` section (an item's continuation lines are indented). None when the page has
/// no such section or no list in it (its questions are answered in the page itself).
pub fn questions(docs: &str) -> Vec<Question> {
    let mut lines = docs.lines().skip_while(|l| l.trim_end() != SECTION);
    lines.next();
    let mut items: Vec<(u32, String)> = Vec::new();
    for line in lines.take_while(|l| !l.starts_with("## ")) {
        let number = line
            .split_once(". ")
            .and_then(|(n, _)| n.parse::<u32>().ok().filter(|_| !line.starts_with(' ')));
        match (number, items.last_mut()) {
            (Some(n), _) => items.push((n, line.split_once(". ").unwrap_or_default().1.into())),
            (None, Some((_, text))) if line.starts_with("   ") => {
                text.push(' ');
                text.push_str(line.trim());
            }
            _ => {}
        }
    }
    items
        .into_iter()
        .map(|(n, text)| {
            let title = text
                .strip_prefix("**")
                .and_then(|rest| rest.split_once("**"))
                .map(|(lead, _)| lead.trim_end_matches('.').to_string());
            Question {
                id: format!("Q{n}"),
                title,
                text: text.trim().to_string(),
            }
        })
        .collect()
}

/// A fresh answers file of lab `lab` (titled `title`) for `questions`.
pub fn template(lab: LabId, title: &str, questions: &[Question]) -> String {
    let mut out = format!(
        "# Lab {n:02} — {title}: written answers\n\n\
         Answer each question under its heading, in Markdown. Keep the `## Q…` headings as they\n\
         are: grading finds your answers by them. `raylab report --lab {n}` shows this file beside\n\
         the figures, and `raylab grade` collects it for your instructor.\n\n\
         To show a figure of your report, write `![caption]({FIGURES}/NAME.png)`, NAME being a\n\
         figure in `out/report/{lab}/`: `raylab report --lab {n}` copies each figure named so\n\
         into `labs/{lab}/{FIGURES}/`, which git keeps (it ignores `out/`), and `raylab grade`\n\
         collects it with this file (a PNG or JPEG of at most 1 MiB and {MAX_SIDE}×{MAX_SIDE}\n\
         pixels, at most {MAX_IMAGES} images per lab).\n",
        n = lab.number()
    );
    for q in questions {
        let heading = match &q.title {
            Some(t) => format!("{} — {t}", q.id),
            None => q.id.clone(),
        };
        out.push_str(&format!(
            "\n## {heading}\n\n> {}\n\n{PLACEHOLDER}\n",
            q.text
        ));
    }
    out
}

/// The answers of an answers file, in its order: each `## Qn` section's text without the
/// question quoted at its top and the placeholder.
pub fn parse(text: &str) -> Vec<Answer> {
    let mut answers: Vec<Answer> = Vec::new();
    let mut in_question = false;
    for line in text.lines() {
        if let Some(heading) = line.strip_prefix("## ") {
            let id = heading.split([' ', '—']).next().unwrap_or_default();
            if id.len() > 1 && id.starts_with('Q') && id[1..].parse::<u32>().is_ok() {
                answers.push(Answer {
                    id: id.to_string(),
                    text: String::new(),
                });
                in_question = true;
                continue;
            }
        }
        if in_question && (line.trim().is_empty() || line.starts_with('>')) {
            continue;
        }
        in_question = false;
        if let Some(answer) = answers.last_mut()
            && line.trim() != PLACEHOLDER
        {
            answer.text.push_str(line);
            answer.text.push('\n');
        }
    }
    for answer in &mut answers {
        answer.text = answer.text.trim().to_string();
    }
    answers
}

/// How many of `answers` are answered.
pub fn answered(answers: &[Answer]) -> usize {
    answers.iter().filter(|a| !a.text.is_empty()).count()
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOCS: &str = "# Lab\n\n## Questions\n\nAnswer these.\n\n\
        1. **Render time.** How long?\n   And why?\n2. Which focal distance?\n\n## Next\n\n3. not a question\n";

    #[test]
    fn the_numbered_list_of_the_questions_section_is_the_questions() {
        let qs = questions(DOCS);
        assert_eq!(qs.len(), 2);
        assert_eq!(qs[0].id, "Q1");
        assert_eq!(qs[0].title.as_deref(), Some("Render time"));
        assert_eq!(qs[0].text, "**Render time.** How long? And why?");
        assert_eq!(qs[0].body(), "How long? And why?");
        assert_eq!(qs[1].title, None);
        assert!(questions("# Lab\n\n## Questions\n\n**Why?** Because.\n").is_empty());
    }

    #[test]
    fn the_images_of_an_answer_are_its_inline_markdown_images() {
        let text = "See ![The rays](figures/rays.png) and ![fov]( <figures/my fov.jpg> \"t\" ).\n\
                    Not ![this] nor ![that](\nx.png) nor [a link](y.png); ![last](../../out/a.png)";
        let links = image_links(text);
        let targets: Vec<&str> = links.iter().map(|l| l.target.as_str()).collect();
        assert_eq!(
            targets,
            ["figures/rays.png", "figures/my fov.jpg", "../../out/a.png"]
        );
        assert_eq!(links[0].alt, "The rays");
        assert_eq!(
            &text[links[0].range.clone()],
            "![The rays](figures/rays.png)"
        );
        assert_eq!(&text[links[2].range.clone()], "![last](../../out/a.png)");
        assert!(image_links("![unclosed](x.png").is_empty());
    }

    #[test]
    fn answers_are_read_back_without_the_questions_and_placeholders() {
        let lab = LabId::of(1);
        let fresh = template(lab, "Camera", &questions(DOCS));
        let answers = parse(&fresh);
        assert_eq!(answers.len(), 2);
        assert!(answers.iter().all(|a| a.text.is_empty()), "{answers:?}");
        let filled = fresh.replacen(PLACEHOLDER, "About 2 s.\n\n> a quote of my own", 1);
        let answers = parse(&filled);
        assert_eq!(answers[0].id, "Q1");
        assert_eq!(answers[0].text, "About 2 s.\n\n> a quote of my own");
        assert_eq!(answers[1].text, "");
        assert_eq!(answered(&answers), 1);
    }
}
