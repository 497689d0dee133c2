//! The student's code of each lab, plugged into the pipeline slots of that lab.

use std::sync::Arc;

use framework::Error;
use framework::pipeline::Pipeline;

/// The labs of the course, in order.
pub fn labs() -> &'static [u32] {
    reference::LABS
}

/// Checks that `lab` is one of the labs the course has.
pub fn check_lab(lab: u32) -> Result<(), Error> {
    if reference::LABS.contains(&lab) {
        Ok(())
    } else {
        Err(Error::Invalid {
            what: format!("lab {lab}"),
            reason: format!("expected one of the labs {:?}", reference::LABS),
        })
    }
}

/// `base` with the slots of lab `lab` replaced by the student's code of that lab.
pub fn with_student_lab(base: Pipeline, lab: u32) -> Result<Pipeline, Error> {
    Ok(match lab {
        1 => Pipeline {
            camera: Arc::new(lab01::Student),
            ..base
        },
        2 => Pipeline {
            intersection: Some(Arc::new(lab02::Student)),
            shading: Arc::new(lab02::Student),
            ..base
        },
        3 => Pipeline {
            shadows: Arc::new(lab03::Student),
            ..base
        },
        4 => Pipeline {
            reflection: Arc::new(lab04::Student),
            ..base
        },
        7 => Pipeline {
            antialiasing: Arc::new(lab07::Student),
            ..base
        },
        _ => {
            check_lab(lab)?;
            return Err(Error::Invalid {
                what: format!("--pipeline student --lab {lab}"),
                reason: "this lab has no student crate".into(),
            });
        }
    })
}
