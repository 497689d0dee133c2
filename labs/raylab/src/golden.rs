//! `raylab golden`: regenerate every lab's golden cases and snapshots from the reference, and
//! beside each snapshot `NAME.exr` the reference image `NAME.png` students look at.

use std::path::{Path, PathBuf};
use std::process::Stdio;

use clap::Args;
use course::LabId;
use grading::task::{self, Task};
use raylab_core::Error;

use crate::lab_program::LabProgram;

/// Options of `raylab golden`.
#[derive(Args, Debug)]
pub struct GoldenArgs {
    /// Only this lab (default: all).
    #[arg(long)]
    pub lab: Option<LabId>,
    /// Where to write the golden data (default: the course tree of the current directory).
    #[arg(long)]
    pub root: Option<PathBuf>,
}

/// Runs `raylab golden`: each lab's program, built with the lab's answer key, records the lab's
/// golden data.
pub fn run(args: &GoldenArgs) -> Result<(), Error> {
    let root = match &args.root {
        Some(r) => r.clone(),
        None => crate::checkout::workspace_root(),
    };
    let labs: Vec<LabId> = match args.lab {
        Some(l) => {
            crate::labs::check_lab(l)?;
            vec![l]
        }
        None => crate::labs::labs(),
    };
    for lab in labs {
        for path in generate(&crate::checkout::workspace_root(), &root, lab)? {
            println!("{}", path.display());
        }
    }
    Ok(())
}

/// Builds lab `lab`'s program in the workspace at `workspace` with its answer key and has it
/// write the lab's golden data under `root`; the files it wrote.
pub fn generate(workspace: &Path, root: &Path, lab: LabId) -> Result<Vec<PathBuf>, Error> {
    let program =
        LabProgram::build_in(workspace, lab, &["reference"]).map_err(|e| Error::Failed {
            what: format!("{lab}"),
            reason: e.to_string(),
        })?;
    let output = program
        .command(&Task::Golden(root.join(lab.folder())))
        .stdin(Stdio::null())
        .stderr(Stdio::inherit())
        .output()
        .map_err(|e| Error::io(&program.executable, e))?;
    if !output.status.success() {
        return Err(Error::Failed {
            what: format!("{lab}'s golden data"),
            reason: format!(
                "its program stopped ({}); its messages are above",
                output.status
            ),
        });
    }
    Ok(task::answer_lines(&String::from_utf8_lossy(&output.stdout))
        .into_iter()
        .map(PathBuf::from)
        .collect())
}
