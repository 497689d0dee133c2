//! The labs of the course as the command line knows them: their numbers and exercise tables
//! (`labs/course.toml`). Their code it never links: work that needs it runs in the lab's
//! program ([`crate::lab_program`]).

use course::{ExerciseInfo, LabId};
use raylab_core::Error;

/// The labs of the course, in order.
pub fn labs() -> Vec<LabId> {
    course::labs()
}

/// Checks that `lab` is one of the labs the course has.
pub fn check_lab(lab: LabId) -> Result<(), Error> {
    if course::title(lab).is_some() {
        return Ok(());
    }
    let labs: Vec<String> = labs().iter().map(|l| l.number().to_string()).collect();
    Err(Error::Invalid {
        what: format!("lab {}", lab.number()),
        reason: format!(
            "expected one of the labs {} (labs/course.toml)",
            labs.join(", ")
        ),
    })
}

/// The exercises of lab `lab` (none for a lab the course does not have).
pub fn exercises(lab: LabId) -> Vec<ExerciseInfo> {
    course::lab(lab)
        .map(|l| l.exercises.clone())
        .unwrap_or_default()
}
