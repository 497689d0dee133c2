//! `raylab similarity SUBMISSION... --out DIR`: finds pairs of submissions whose code of a lab is
//! more alike than independent work would be, with Dolos, a plagiarism detector for source code.
//!
//! Per lab, each student's `labs/labNN/src/**/*.rs` — read as `raylab grade` reads them, regular
//! files only and within its limits — is joined into one file; the repository's own stubs
//! (`labs/labNN/src/`), joined the same way, are Dolos's template, so that starter code counts
//! for no pair. Dolos (installed by `labs/raylab/scripts/install-dolos.sh` into `target/dolos`)
//! compares the files with `compare.mjs` beside it and answers in JSON. The pairs at or above the
//! threshold go to [`PAGE`] and [`CSV`] in the output directory, most similar first, and onto the
//! class page of `raylab grade` ([`link_for_class_page`]).

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use clap::Args;
use course::LabId;
use maud::html;
use raylab_core::Error;

use crate::grade::class::{graded_labs, student_names};
use crate::grade::submission::{LabSources, lab_sources, read_regular, shown};
use crate::handout::{io, repository_root};
use crate::html::{SORT_SCRIPT, page, section_list};
use crate::similar_pairs::{CSV, MAX_CSV_BYTES, PAGE, link_for_class_page};

/// The files given to Dolos (each student's joined sources per lab), in the output directory.
const WORK: &str = ".similarity";
/// The command that installs Dolos, for the error that says it is missing.
const INSTALL: &str = "bash labs/raylab/scripts/install-dolos.sh";
/// The most lines of a shared fragment shown on the page, per side.
const MAX_FRAGMENT_LINES: usize = 80;
/// The most pairs whose fragments [`PAGE`] shows (the most similar ones; all are listed).
const MAX_FRAGMENT_PAIRS: usize = 200;
/// Options of `raylab similarity`.
#[derive(Args, Debug)]
pub struct SimilarityArgs {
    /// Submission directories, as given to `raylab grade`: each a copy of the handout with the
    /// student's work in it, named after the student.
    #[arg(required = true)]
    pub submissions: Vec<PathBuf>,
    /// Directory for similarity.html and similarity.csv; the `--out` of `raylab grade` puts the
    /// similar pairs on its class page too.
    #[arg(long)]
    pub out: PathBuf,
    /// Compare only this lab (repeatable; default: every lab).
    #[arg(long = "lab", value_name = "N")]
    pub labs: Vec<LabId>,
    /// The similarity (0 to 1: the share of both submissions' code fingerprints they have in
    /// common, the stubs' left out) at or above which a pair is listed.
    #[arg(long, default_value_t = 0.6, value_name = "T")]
    pub threshold: f64,
    /// The directory Dolos was installed in (default: `target/dolos` of the repository, where
    /// labs/raylab/scripts/install-dolos.sh installs it).
    #[arg(long, value_name = "DIR")]
    pub dolos: Option<PathBuf>,
}

/// One student's sources of one lab, joined into one text for Dolos.
struct Joined {
    /// The files, one after another.
    text: String,
    /// Each file's path (`labs/labNN/src/…`) and the line of `text` it starts on (1-based).
    starts: Vec<(String, usize)>,
}

impl Joined {
    /// The `.rs` files of `files` (paths relative to lab `lab`'s `src/`) in order of path.
    fn of(lab: LabId, files: &[(PathBuf, Vec<u8>)]) -> Joined {
        let mut rust: Vec<&(PathBuf, Vec<u8>)> = files
            .iter()
            .filter(|(path, _)| path.extension().is_some_and(|e| e == "rs"))
            .collect();
        rust.sort_by(|a, b| a.0.cmp(&b.0));
        let mut joined = Joined {
            text: String::new(),
            starts: Vec::new(),
        };
        for (path, contents) in rust {
            let line = joined.text.lines().count() + 1;
            let name = shown(
                &Path::new("labs")
                    .join(lab.to_string())
                    .join("src")
                    .join(path),
            );
            joined.starts.push((name, line));
            joined.text.push_str(&String::from_utf8_lossy(contents));
            if !joined.text.ends_with('\n') {
                joined.text.push('\n');
            }
        }
        joined
    }

    /// Where the lines `first` to `last` of the joined text are in the student's files:
    /// `labs/lab02/src/lib.rs:12–40`.
    fn locate(&self, first: usize, last: usize) -> String {
        let at = |line: usize| {
            self.starts
                .iter()
                .rev()
                .find(|(_, start)| *start <= line)
                .map(|(name, start)| (name.as_str(), line - start + 1))
                .unwrap_or(("?", line))
        };
        let (first_file, first_line) = at(first);
        let (last_file, last_line) = at(last);
        if first_file == last_file {
            format!("{first_file}:{first_line}–{last_line}")
        } else {
            format!("{first_file}:{first_line} – {last_file}:{last_line}")
        }
    }

    /// The lines `first` to `last` (1-based), at most [`MAX_FRAGMENT_LINES`] of them.
    fn excerpt(&self, first: usize, last: usize) -> String {
        let count = (last + 1).saturating_sub(first);
        let mut lines: Vec<&str> = self
            .text
            .lines()
            .skip(first.saturating_sub(1))
            .take(count.min(MAX_FRAGMENT_LINES))
            .collect();
        let more = format!(
            "… ({} more lines)",
            count.saturating_sub(MAX_FRAGMENT_LINES)
        );
        if count > MAX_FRAGMENT_LINES {
            lines.push(&more);
        }
        lines.join("\n")
    }
}

/// A pair of submissions of one lab, as Dolos compared them.
struct Pair {
    lab: LabId,
    /// The students, in the order the submissions were given.
    students: [String; 2],
    /// Dolos's similarity, 0 to 1.
    similarity: f64,
    /// The longest shared fragment, in k-grams.
    longest: u64,
    /// Where the longest shared fragment is in each, and its lines.
    fragments: [Option<(String, String)>; 2],
}

/// What was compared of one lab.
struct LabSummary {
    lab: LabId,
    /// Submissions compared.
    compared: usize,
    /// Pairs compared.
    pairs: usize,
    /// Pairs at or above the threshold.
    similar: usize,
    /// The most similar pair's similarity and students.
    highest: Option<(f64, String, String)>,
}

/// Runs `raylab similarity`.
pub fn run(args: &SimilarityArgs) -> Result<(), Error> {
    if !(0.0..=1.0).contains(&args.threshold) {
        return Err(Error::Invalid {
            what: format!("--threshold {}", args.threshold),
            reason: "expected a similarity from 0 to 1".into(),
        });
    }
    let labs = graded_labs(&args.labs)?;
    let students = student_names(&args.submissions)?;
    let dolos = dolos_dir(args.dolos.as_deref())?;
    let work = args.out.join(WORK);
    if work.exists() {
        fs::remove_dir_all(&work).map_err(io(&work))?;
    }
    let mut pairs = Vec::new();
    let mut summaries = Vec::new();
    let mut notes = Vec::new();
    let mut version = None;
    for &lab in &labs {
        let LabSources {
            files: stubs,
            rejected,
        } = lab_sources(&repository_root(), lab);
        let Some(stubs) = stubs.filter(|_| rejected.is_empty()) else {
            return Err(Error::Failed {
                what: format!("the repository's labs/{lab}/src"),
                reason: rejected
                    .into_iter()
                    .next()
                    .unwrap_or_else(|| "missing".into()),
            });
        };
        let template = Joined::of(lab, &stubs);
        let mut compared: Vec<(&str, Joined)> = Vec::new();
        for (submission, student) in args.submissions.iter().zip(&students) {
            let LabSources { files, rejected } = lab_sources(submission, lab);
            notes.extend(rejected.iter().map(|line| format!("{student}: {line}")));
            match files.map(|files| Joined::of(lab, &files)) {
                None => notes.push(format!("{student}: labs/{lab}/src is missing")),
                Some(joined) if joined.text.trim().is_empty() => {
                    notes.push(format!("{student}: labs/{lab}/src has no Rust source"));
                }
                Some(joined) if joined.text == template.text => {
                    notes.push(format!("{student}: labs/{lab}/src is the stubs, unchanged"));
                }
                Some(joined) => compared.push((student, joined)),
            }
        }
        let mut summary = LabSummary {
            lab,
            compared: compared.len(),
            pairs: compared.len() * compared.len().saturating_sub(1) / 2,
            similar: 0,
            highest: None,
        };
        if compared.len() >= 2 {
            let dir = work.join(lab.to_string());
            let answer = compare(&dolos, &dir, &template, &compared)?;
            version = Some(answer.version);
            for (i, j, found) in answer.pairs {
                // The students in the order of the submissions.
                let (a, b) = if i < j { (i, j) } else { (j, i) };
                if summary
                    .highest
                    .as_ref()
                    .is_none_or(|h| found.similarity > h.0)
                {
                    let names = (compared[a].0.to_string(), compared[b].0.to_string());
                    summary.highest = Some((found.similarity, names.0, names.1));
                }
                if found.similarity < args.threshold {
                    continue;
                }
                summary.similar += 1;
                let (lines_a, lines_b) = if i < j {
                    (found.lines[0], found.lines[1])
                } else {
                    (found.lines[1], found.lines[0])
                };
                let fragment = |k: usize, lines: Option<(usize, usize)>| {
                    lines.map(|(first, last)| {
                        let joined = &compared[k].1;
                        (joined.locate(first, last), joined.excerpt(first, last))
                    })
                };
                pairs.push(Pair {
                    lab,
                    students: [compared[a].0.to_string(), compared[b].0.to_string()],
                    similarity: found.similarity,
                    longest: found.longest,
                    fragments: [fragment(a, lines_a), fragment(b, lines_b)],
                });
            }
        }
        summaries.push(summary);
    }
    pairs.sort_by(|x, y| {
        y.similarity
            .total_cmp(&x.similarity)
            .then(x.lab.cmp(&y.lab))
            .then_with(|| x.students.cmp(&y.students))
    });
    fs::create_dir_all(&args.out).map_err(io(&args.out))?;
    let csv_path = args.out.join(CSV);
    fs::write(&csv_path, csv(&pairs)?).map_err(io(&csv_path))?;
    let page_path = args.out.join(PAGE);
    let html = similarity_page(
        &pairs,
        &summaries,
        &notes,
        args.threshold,
        version.as_deref(),
    );
    fs::write(&page_path, html).map_err(io(&page_path))?;
    let class_page = update_class_page(&args.out)?;
    for s in &summaries {
        let mut line = format!(
            "{}: {} submissions compared, {} of {} pairs at or above {}",
            s.lab, s.compared, s.similar, s.pairs, args.threshold
        );
        if let Some((similarity, a, b)) = &s.highest {
            let _ = write!(line, " (most similar: {a} and {b}, {similarity:.2})");
        }
        println!("{line}");
    }
    println!(
        "{} similar pairs in {} and {}{}",
        pairs.len(),
        page_path.display(),
        csv_path.display(),
        if class_page {
            " (linked from index.html)"
        } else {
            ""
        }
    );
    Ok(())
}

/// The directory Dolos is installed in: `given`, or `target/dolos` of the repository; an error
/// naming the install command when it holds no installation.
fn dolos_dir(given: Option<&Path>) -> Result<PathBuf, Error> {
    let dir = given.map_or_else(|| repository_root().join("target/dolos"), Path::to_path_buf);
    let installed = dir.join("compare.mjs").is_file()
        && dir
            .join("node_modules/@dodona/dolos-lib/package.json")
            .is_file();
    if !installed {
        return Err(Error::Failed {
            what: format!("Dolos directory {}", dir.display()),
            reason: format!(
                "Dolos, the plagiarism detector `raylab similarity` runs, is not installed there: run `{INSTALL}` (or pass --dolos DIR)"
            ),
        });
    }
    Ok(dir)
}

/// One pair as Dolos reported it.
struct Found {
    similarity: f64,
    longest: u64,
    /// The lines of the longest shared fragment in the left and the right file.
    lines: [Option<(usize, usize)>; 2],
}

/// What Dolos answered for one lab.
struct Answer {
    /// Dolos's version.
    version: String,
    /// Each pair by the indices of its two submissions.
    pairs: Vec<(usize, usize, Found)>,
}

/// Compares the `submissions` of one lab with Dolos (installed in `dolos`), with `template` as
/// the starter code; the files go to `dir`.
fn compare(
    dolos: &Path,
    dir: &Path,
    template: &Joined,
    submissions: &[(&str, Joined)],
) -> Result<Answer, Error> {
    fs::create_dir_all(dir).map_err(io(dir))?;
    let dir = std::path::absolute(dir).map_err(io(dir))?;
    let write = |name: String, text: &str| -> Result<String, Error> {
        let path = dir.join(name);
        fs::write(&path, text).map_err(io(&path))?;
        Ok(path.to_string_lossy().into_owned())
    };
    let template_path = write("stubs.rs".into(), &template.text)?;
    // Numbered, not named: a student's name never becomes a path Dolos reads.
    let files = submissions
        .iter()
        .enumerate()
        .map(|(k, (_, joined))| write(format!("{k:03}.rs"), &joined.text))
        .collect::<Result<Vec<_>, _>>()?;
    let manifest = serde_json::json!({
        "language": "rust",
        "template": template_path,
        "files": files,
    });
    let manifest_path = dir.join("manifest.json");
    fs::write(&manifest_path, manifest.to_string()).map_err(io(&manifest_path))?;
    let script = dolos.join("compare.mjs");
    let output = Command::new("node")
        .arg(&script)
        .arg(&manifest_path)
        .output()
        .map_err(|err| Error::Failed {
            what: "node".into(),
            reason: format!(
                "cannot run Node.js, which runs Dolos ({err}): install it (apt-get install nodejs npm) and run `{INSTALL}`"
            ),
        })?;
    let invalid = |reason: String| Error::Failed {
        what: format!(
            "Dolos's answer ({} {})",
            script.display(),
            manifest_path.display()
        ),
        reason,
    };
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let last: Vec<&str> = stderr.lines().rev().take(5).collect();
        let last: Vec<&str> = last.into_iter().rev().collect();
        return Err(invalid(format!("{}: {}", output.status, last.join(" / "))));
    }
    let answer: serde_json::Value = serde_json::from_slice(&output.stdout)
        .map_err(|err| invalid(format!("not JSON: {err}")))?;
    let version = answer["dolos"].as_str().unwrap_or("?").to_string();
    let lines = |value: &serde_json::Value| {
        let first = usize::try_from(value.get(0)?.as_u64()?).ok()?;
        let last = usize::try_from(value.get(1)?.as_u64()?).ok()?;
        (first <= last).then_some((first, last))
    };
    let mut pairs = Vec::new();
    for pair in answer["pairs"].as_array().into_iter().flatten() {
        let index = |key: &str| {
            pair[key]
                .as_u64()
                .and_then(|k| usize::try_from(k).ok())
                .filter(|&k| k < submissions.len())
                .ok_or_else(|| invalid(format!("a pair without a valid {key:?}: {pair}")))
        };
        let (left, right) = (index("left")?, index("right")?);
        let similarity = pair["similarity"]
            .as_f64()
            .filter(|s| s.is_finite())
            .ok_or_else(|| invalid(format!("a pair without a similarity: {pair}")))?;
        pairs.push((
            left,
            right,
            Found {
                similarity,
                longest: pair["longest"].as_u64().unwrap_or(0),
                lines: [lines(&pair["left_lines"]), lines(&pair["right_lines"])],
            },
        ));
    }
    Ok(Answer { version, pairs })
}

/// The CSV of the pairs (see [`CSV`]).
fn csv(pairs: &[Pair]) -> Result<String, Error> {
    let mut csv = csv::Writer::from_writer(Vec::new());
    let bad = |err: csv::Error| Error::Failed {
        what: CSV.into(),
        reason: err.to_string(),
    };
    csv.write_record([
        "lab",
        "student_a",
        "student_b",
        "similarity",
        "longest_fragment",
        "fragment_a",
        "fragment_b",
    ])
    .map_err(bad)?;
    for p in pairs {
        let place = |k: usize| p.fragments[k].as_ref().map_or("", |f| f.0.as_str());
        csv.write_record([
            p.lab.to_string().as_str(),
            &p.students[0],
            &p.students[1],
            &format!("{:.3}", p.similarity),
            &p.longest.to_string(),
            place(0),
            place(1),
        ])
        .map_err(bad)?;
    }
    let bytes = csv
        .into_inner()
        .map_err(|err| bad(err.into_error().into()))?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// [`PAGE`]: the pairs at or above `threshold`, what each lab compared, and each pair's longest
/// shared fragment side by side.
fn similarity_page(
    pairs: &[Pair],
    summaries: &[LabSummary],
    notes: &[String],
    threshold: f64,
    version: Option<&str>,
) -> String {
    let body = html! {
        h1 { "Similar submissions" }
        p {
            "Compared by Dolos" @if let Some(version) = version { " " (version) }
            ", lab by lab: each student's "
            code { "labs/labNN/src/**/*.rs" } " against every other's, with the handout's stubs as "
            "the base, so that starter code counts for no pair. Renamed variables, reordered "
            "functions, changed comments and layout do not hide a copy: Dolos compares the "
            "syntax tree's fingerprints, not the text. The similarity is the share of both "
            "submissions' fingerprints they have in common; a high one asks for a closer look, "
            "it is not a proof (short exercises leave few ways to write an answer)."
        }
        h2 { "Pairs at or above " (threshold) }
        @if pairs.is_empty() {
            p { "No pair." }
        } @else {
            table class="sortable" {
                thead {
                    tr {
                        th { "lab" } th { "student A" } th { "student B" } th { "similarity" }
                        th { "longest shared fragment (k-grams)" } th { "in A" } th { "in B" }
                    }
                }
                tbody {
                    @for (k, p) in pairs.iter().enumerate() {
                        tr {
                            td { (p.lab) }
                            td { (p.students[0]) }
                            td { (p.students[1]) }
                            td data-v=(p.similarity) {
                                @if k < MAX_FRAGMENT_PAIRS {
                                    a href={ "#pair-" (k) } { (format!("{:.2}", p.similarity)) }
                                } @else {
                                    (format!("{:.2}", p.similarity))
                                }
                            }
                            td { (p.longest) }
                            td { @if let Some(f) = &p.fragments[0] { code { (f.0) } } }
                            td { @if let Some(f) = &p.fragments[1] { code { (f.0) } } }
                        }
                    }
                }
            }
        }
        h2 { "Labs" }
        table class="sortable" {
            thead {
                tr {
                    th { "lab" } th { "submissions compared" } th { "pairs" }
                    th { "at or above " (threshold) } th { "most similar pair" }
                }
            }
            tbody {
                @for s in summaries {
                    tr {
                        td { (s.lab) }
                        td { (s.compared) }
                        td { (s.pairs) }
                        td { (s.similar) }
                        td data-v=(s.highest.as_ref().map_or(0.0, |h| h.0)) {
                            @if let Some((similarity, a, b)) = &s.highest {
                                (format!("{similarity:.2}")) " (" (a) ", " (b) ")"
                            }
                        }
                    }
                }
            }
        }
        (section_list(html! { "Left out" }, notes))
        @if !pairs.is_empty() {
            h2 { "Longest shared fragments" }
            @if pairs.len() > MAX_FRAGMENT_PAIRS {
                p { "Of the " (MAX_FRAGMENT_PAIRS) " most similar pairs (" (CSV) " lists all " (pairs.len()) ")." }
            }
            @for (k, p) in pairs.iter().enumerate().take(MAX_FRAGMENT_PAIRS) {
                h3 id={ "pair-" (k) } {
                    (p.lab) ": " (p.students[0]) " and " (p.students[1]) ", "
                    (format!("{:.2}", p.similarity))
                }
                div class="images" {
                    @for (student, fragment) in p.students.iter().zip(&p.fragments) {
                        @if let Some((place, lines)) = fragment {
                            // Side by side, each half the page's width.
                            figure style="flex:1 1 0;min-width:0" {
                                figcaption { (student) ": " code { (place) } }
                                pre { (lines) }
                            }
                        }
                    }
                }
            }
        }
    };
    page("Similar submissions", body, Some(SORT_SCRIPT))
}

/// Puts [`link_for_class_page`]'s section into the class page `dir/index.html`, if there is one
/// (in place of the section it has, or before its footer). Whether it did.
fn update_class_page(dir: &Path) -> Result<bool, Error> {
    let path = dir.join("index.html");
    let Ok(bytes) = read_regular(&path, MAX_CSV_BYTES) else {
        return Ok(false);
    };
    let (Ok(old), Some(section)) = (String::from_utf8(bytes), link_for_class_page(dir)) else {
        return Ok(false);
    };
    let section = section.into_string();
    const START: &str = "<section id=\"similarity\">";
    const END: &str = "</section>";
    let new = if let Some(start) = old.find(START) {
        let Some(end) = old[start..].find(END).map(|e| start + e + END.len()) else {
            return Ok(false);
        };
        format!("{}{section}{}", &old[..start], &old[end..])
    } else if let Some(footer) = old.find("<footer>") {
        format!("{}{section}{}", &old[..footer], &old[footer..])
    } else {
        return Ok(false);
    };
    fs::write(&path, new).map_err(io(&path))?;
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_of_joined_files_are_located_in_their_own_file() {
        let lab = LabId::of(3);
        let joined = Joined::of(
            lab,
            &[
                (
                    PathBuf::from("shapes/mod.rs"),
                    b"fn a() {}\nfn b() {}".to_vec(),
                ),
                (PathBuf::from("notes.txt"), b"not Rust\n".to_vec()),
                (PathBuf::from("lib.rs"), b"mod shapes;\n".to_vec()),
            ],
        );
        // lib.rs first (files in order of path), the text file left out.
        assert_eq!(joined.text, "mod shapes;\nfn a() {}\nfn b() {}\n");
        assert_eq!(joined.locate(2, 3), "labs/lab03/src/shapes/mod.rs:1–2");
        assert_eq!(
            joined.locate(1, 2),
            "labs/lab03/src/lib.rs:1 – labs/lab03/src/shapes/mod.rs:1"
        );
        assert_eq!(joined.excerpt(2, 3), "fn a() {}\nfn b() {}");
    }

    #[test]
    fn a_long_fragment_is_cut_and_says_how_much_is_left_out() {
        let text: String = (1..=100).map(|k| format!("let x{k} = {k};\n")).collect();
        let joined = Joined::of(
            LabId::of(1),
            &[(PathBuf::from("lib.rs"), text.into_bytes())],
        );
        let excerpt = joined.excerpt(11, 100);
        assert!(excerpt.starts_with("let x11 = 11;\n"));
        assert!(
            excerpt.ends_with("let x90 = 90;\n… (10 more lines)"),
            "{excerpt}"
        );
    }

    #[test]
    fn the_class_page_gets_one_section_however_often_it_is_updated() {
        let dir =
            std::env::temp_dir().join(format!("raylab-similarity-page-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        fs::write(
            dir.join("index.html"),
            "<html><body><h1>Grades</h1><footer><p>stamp</p></footer></body></html>",
        )
        .unwrap();
        assert!(!update_class_page(&dir).unwrap(), "no similarity.csv yet");
        let pair = |similarity: &str| {
            format!(
                "lab,student_a,student_b,similarity,longest_fragment,fragment_a,fragment_b\n\
                 lab02,a<b,c,{similarity},30,x,y\n"
            )
        };
        fs::write(dir.join(CSV), pair("0.910")).unwrap();
        assert!(update_class_page(&dir).unwrap());
        fs::write(dir.join(CSV), pair("0.820")).unwrap();
        assert!(update_class_page(&dir).unwrap());
        let page = fs::read_to_string(dir.join("index.html")).unwrap();
        assert_eq!(
            page.matches("<section id=\"similarity\">").count(),
            1,
            "{page}"
        );
        assert!(
            page.contains("<td>0.820</td>") && !page.contains("0.910"),
            "{page}"
        );
        assert!(
            page.contains("<td>a&lt;b</td>"),
            "names are escaped: {page}"
        );
        assert!(
            page.ends_with("<footer><p>stamp</p></footer></body></html>"),
            "{page}"
        );
        fs::remove_dir_all(&dir).ok();
    }
}
