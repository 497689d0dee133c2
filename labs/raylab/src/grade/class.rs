//! The class a command is given: the labs to grade, and each submission's student name.

use std::fs;
use std::path::PathBuf;

use course::LabId;
use raylab_core::Error;

use crate::handout::io;

/// The labs to grade: `requested`, or every lab; each must be a lab of the course.
pub(crate) fn graded_labs(requested: &[LabId]) -> Result<Vec<LabId>, Error> {
    if requested.is_empty() {
        return Ok(crate::labs::labs().to_vec());
    }
    let mut labs = requested.to_vec();
    labs.sort_unstable();
    labs.dedup();
    for &lab in &labs {
        crate::labs::check_lab(lab)?;
    }
    Ok(labs)
}

/// The name of each submission (its directory's name); each must be a directory, and the
/// names must differ.
pub(crate) fn student_names(submissions: &[PathBuf]) -> Result<Vec<String>, Error> {
    let mut names = Vec::new();
    for path in submissions {
        if !path.is_dir() {
            return Err(Error::Invalid {
                what: format!("submission {}", path.display()),
                reason: "expected a directory (a copy of the handout; unpack archives first)"
                    .into(),
            });
        }
        let name = fs::canonicalize(path)
            .map_err(io(path))?
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let name: String = name
            .chars()
            .map(|c| {
                if c.is_alphanumeric() || "-_.".contains(c) {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        if name.is_empty() || name.starts_with('.') || names.contains(&name) {
            return Err(Error::Invalid {
                what: format!("submission {}", path.display()),
                reason: format!(
                    "its directory name {name:?} must be unique among the submissions and not start with '.'"
                ),
            });
        }
        names.push(name);
    }
    Ok(names)
}
