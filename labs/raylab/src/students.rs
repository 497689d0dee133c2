//! The code of each lab — the student's, and the answer key's where the tree holds it — with
//! the lab's contract: the one place of the command line that names every lab's types. Each
//! command that works on any lab is a [`LabVisitor`].

use std::sync::Arc;

use course::{ExerciseInfo, LabId};
use grading::Exercise;
use pipeline::{LabSlots, Pipeline};
use raylab_core::Error;

/// Each lab's checks crate under its lab's name.
mod lab_checks {
    pub use lab01_checks as lab01;
    pub use lab02_checks as lab02;
    pub use lab03_checks as lab03;
    pub use lab04_checks as lab04;
    pub use lab05_checks as lab05;
    pub use lab06_checks as lab06;
    pub use lab07_checks as lab07;
    pub use lab08_checks as lab08;
    pub use lab09_checks as lab09;
    pub use lab10_checks as lab10;
    pub use lab11_checks as lab11;
}

/// One lab's code and contract, whatever the contract's trait `S`.
pub struct LabCode<S: ?Sized> {
    /// The lab.
    pub number: LabId,
    /// Its exercise table.
    pub exercises: Vec<Exercise<S>>,
    /// The student's code (`labs/labNN/src`).
    pub student: Arc<S>,
    /// The answer key's code: in the instructor's tree only.
    #[cfg(feature = "instructor")]
    pub key: Arc<S>,
    /// The figures of the lab's report (`raylab report`, `report/labNN.rs`).
    pub figures: fn(&crate::report::ReportContext) -> Result<Vec<crate::report::Figure>, Error>,
    /// The lab's golden-data generator.
    #[cfg(feature = "instructor")]
    pub generate_golden:
        fn(&Arc<S>, &grading::LabContext) -> Result<Vec<std::path::PathBuf>, Error>,
}

/// A command's work on one lab, generic over the lab's contract.
pub trait LabVisitor {
    /// What the work gives.
    type Output;
    /// Does the work on lab `code`.
    fn visit<S: ?Sized + LabSlots + Send + Sync + 'static>(self, code: LabCode<S>) -> Self::Output;
}

/// [`LabCode`] of lab `$number` with contract `$contract`, student `$student` and key `$key`.
macro_rules! lab_code {
    ($number:expr, $contract:ident, $student:expr, $key:expr, $module:ident) => {
        LabCode::<dyn contracts::$module::$contract> {
            number: LabId::of($number),
            exercises: lab_checks::$module::checks::exercises(),
            student: Arc::new($student),
            figures: crate::report::$module::figures,
            #[cfg(feature = "instructor")]
            key: Arc::new($key),
            #[cfg(feature = "instructor")]
            generate_golden: lab_checks::$module::generate_golden,
        }
    };
}

/// Runs `visitor` on lab `lab`'s code; an error for a lab the course does not have.
pub fn visit<V: LabVisitor>(lab: LabId, visitor: V) -> Result<V::Output, Error> {
    Ok(match lab.number() {
        1 => visitor.visit(lab_code!(
            1,
            CameraRays,
            ::lab01::Student,
            reference::lab01::Lab01,
            lab01
        )),
        2 => visitor.visit(lab_code!(
            2,
            Lab02,
            ::lab02::Student,
            reference::lab02::Lab02,
            lab02
        )),
        3 => visitor.visit(lab_code!(
            3,
            Shadows,
            ::lab03::Student,
            reference::lab03::Lab03,
            lab03
        )),
        4 => visitor.visit(lab_code!(
            4,
            Reflection,
            ::lab04::Student,
            reference::lab04::Lab04,
            lab04
        )),
        5 => visitor.visit(lab_code!(
            5,
            Radiometry,
            ::lab05::Student,
            reference::lab05::Lab05,
            lab05
        )),
        6 => visitor.visit(lab_code!(
            6,
            Radiosity,
            ::lab06::Student,
            reference::lab06::Lab06,
            lab06
        )),
        7 => visitor.visit(lab_code!(
            7,
            Antialiasing,
            ::lab07::Student,
            reference::lab07::Lab07,
            lab07
        )),
        8 => visitor.visit(lab_code!(
            8,
            PhotonMapping,
            ::lab08::Student,
            reference::lab08::Lab08,
            lab08
        )),
        9 => visitor.visit(lab_code!(
            9,
            Texturing,
            ::lab09::Student,
            reference::lab09::Lab09,
            lab09
        )),
        10 => visitor.visit(lab_code!(
            10,
            Fresnel,
            ::lab10::Student,
            reference::lab10::Lab10,
            lab10
        )),
        11 => visitor.visit(lab_code!(
            11,
            AmbientOcclusion,
            ::lab11::Student,
            reference::lab11::Lab11,
            lab11
        )),
        _ => {
            check_lab(lab)?;
            return Err(Error::Invalid {
                what: format!("lab {lab}"),
                reason: "the command line has no code for this lab (labs/raylab/src/students.rs)"
                    .into(),
            });
        }
    })
}

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

/// `base` with the slots of lab `lab` replaced by the student's code of that lab.
pub fn with_student_lab(base: Pipeline, lab: LabId) -> Result<Pipeline, Error> {
    struct Install(Pipeline);
    impl LabVisitor for Install {
        type Output = Pipeline;
        fn visit<S: ?Sized + LabSlots + Send + Sync + 'static>(self, code: LabCode<S>) -> Pipeline {
            S::install(code.student, self.0)
        }
    }
    visit(lab, Install(base))
}
