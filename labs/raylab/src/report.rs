//! `raylab report --lab N`: the figures of a lab's report, made in the lab's program (its
//! checks' `report` module, drawn with the `figures` crate) through the reference or the
//! student's code in the lab's slots.

use std::path::PathBuf;

use clap::Args;
use course::LabId;
use grading::task::{ReportJob, Task};
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
}

/// Runs `raylab report`.
pub fn run(args: &ReportArgs) -> Result<(), Error> {
    crate::labs::check_lab(args.lab)?;
    let cwd = std::env::current_dir().map_err(|e| Error::io(std::path::Path::new("."), e))?;
    let job = ReportJob {
        dir: cwd.join(&args.out).join(args.lab.to_string()),
        quick: args.quick,
        whose: format!("{:?}", args.pipeline),
        answers: Some(crate::lab_program::workspace_root().join(args.lab.answers()))
            .filter(|path| path.is_file()),
    };
    if let Some(note) = crate::render::student_code_note(args.pipeline, args.lab) {
        eprintln!("note: {note}");
    }
    let features: &[&str] = match args.pipeline {
        // The key in the lab's slots, where the tree holds it.
        PipelineChoice::Reference if crate::render::has_solution(args.lab) => {
            &["report", "reference"]
        }
        _ => &["report"],
    };
    crate::render::run_in_lab_program(args.lab, features, &Task::Report(job))
}
