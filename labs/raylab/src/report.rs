//! `raylab report --lab N`: the figures of a lab's report, made in the lab's program (its
//! checks' `report` module, drawn with the `figures` crate) through the reference or the
//! student's code in the lab's slots; then each figure the lab's written answers show as
//! `figures/NAME.png` copied beside them, into `labs/labNN/figures/`, where git keeps it for
//! grading (git ignores `out/`).

use std::fs;
use std::path::{Path, PathBuf};

use clap::Args;
use course::LabId;
use course::answers::FIGURES;
use grading::task::Task;
use pipeline::job::ReportJob;
use raylab_core::Error;

use crate::render::PipelineChoice;

/// Options of `raylab report`.
#[derive(Args, Debug)]
pub struct ReportArgs {
    /// The lab whose figures to make.
    #[arg(long)]
    pub lab: LabId,
    /// Whose code renders the lab's part of the pipeline.
    #[arg(long, value_enum, default_value_t = PipelineChoice::Reference)]
    pub pipeline: PipelineChoice,
    /// Directory for the figures (a `labNN/` folder is made inside).
    #[arg(long, default_value = "out/report")]
    pub out: PathBuf,
    /// Smaller images and fewer samples, for a quick look (and for tests).
    #[arg(long)]
    pub quick: bool,
    /// The written answers shown after the figures, whose `figures/` folder gets the figures
    /// they show (default: the lab's `labs/labNN/answers.md`; another for the tests).
    #[arg(long, hide = true, value_name = "FILE")]
    pub answers: Option<PathBuf>,
}

/// Runs `raylab report`.
pub fn run(args: &ReportArgs) -> Result<(), Error> {
    crate::labs::check_lab(args.lab)?;
    let cwd = std::env::current_dir().map_err(|e| Error::io(std::path::Path::new("."), e))?;
    let answers = args
        .answers
        .clone()
        .unwrap_or_else(|| crate::checkout::workspace_root().join(args.lab.answers()));
    let job = ReportJob {
        dir: cwd.join(&args.out).join(args.lab.to_string()),
        quick: args.quick,
        whose: format!("{:?}", args.pipeline),
        answers: Some(answers).filter(|path| path.is_file()),
    };
    if let Some(note) =
        crate::render::student_code_note(args.pipeline, args.lab, crate::render::has_solution)
    {
        eprintln!("note: {note}");
    }
    let features: &[&str] = match args.pipeline {
        // The key in the lab's slots, where the tree holds it.
        PipelineChoice::Reference if crate::render::has_solution(args.lab) => {
            &["report", "reference"]
        }
        _ => &["report"],
    };
    crate::render::run_in_lab_program(args.lab, features, &Task::Report(job.clone()))?;
    match &job.answers {
        Some(answers) => copy_shown_figures(answers, &job.dir),
        None => Ok(()),
    }
}

/// Copies each figure of the report in `dir` that the answers file `answers` shows as
/// `figures/NAME` into the `figures/` folder beside it, and says so; warns of an image the
/// answers show that will not reach grading: one in `out/`, which git ignores, or a
/// `figures/NAME` that is neither a figure of this report nor there already.
fn copy_shown_figures(answers: &Path, dir: &Path) -> Result<(), Error> {
    // The figures crate has read the file within its limit already.
    let text = fs::read_to_string(answers).map_err(|e| Error::io(answers, e))?;
    let folder = answers.with_file_name(FIGURES);
    let mut done: Vec<String> = Vec::new();
    for link in course::answers::parse(&text)
        .iter()
        .flat_map(|a| course::answers::image_links(&a.text))
    {
        if done.contains(&link.target) {
            continue;
        }
        done.push(link.target.clone());
        let name = link
            .target
            .strip_prefix(&format!("{FIGURES}/"))
            .filter(|name| !name.is_empty() && !name.contains('/') && !name.starts_with('.'));
        let Some(name) = name else {
            if link.target.split('/').any(|part| part == "out") {
                eprintln!(
                    "warning: the answers show {}, which git does not keep (it ignores out/): write it as {FIGURES}/{} to hand it in",
                    link.target,
                    link.target.rsplit('/').next().unwrap_or_default()
                );
            }
            continue;
        };
        let figure = dir.join(name);
        let copy = folder.join(name);
        if fs::symlink_metadata(&figure).is_ok_and(|m| m.is_file()) {
            fs::create_dir_all(&folder).map_err(|e| Error::io(&folder, e))?;
            fs::copy(&figure, &copy).map_err(|e| Error::io(&copy, e))?;
            println!("{} (shown in the answers)", copy.display());
        } else if !copy.is_file() {
            eprintln!(
                "warning: the answers show {}, which is not a figure of this report (nor in {})",
                link.target,
                folder.display()
            );
        }
    }
    Ok(())
}
