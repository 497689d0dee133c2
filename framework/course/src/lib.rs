//! # The course as data
//!
//! The registry `labs/course.toml` lists the course's labs, one line each; each lab's
//! `labs/labNN/exercises.toml` is its exercise table (number, function, title, points,
//! visibility, hint of each exercise, and the items a submission may not name). Both are
//! embedded at build time, and this crate is the one place that reads them: the checks take
//! their exercises from here, the command line its `hint`, `status`, gradebooks and handouts,
//! the tests what they compare the stubs and docs pages with.
//!
//! [`LabId`] names a lab; it replaces bare numbers and `lab{:02}` strings.

pub mod answers;
mod exercise;
mod lab_id;
mod registry;

use std::sync::OnceLock;

pub use exercise::{DeniedItem, ExerciseInfo, Visibility, parse_table};
pub use lab_id::LabId;
pub use registry::{Entry as RegistryEntry, parse as parse_registry};

/// The registry as it was built in.
pub const REGISTRY: &str = include_str!("../../../labs/course.toml");

/// Every registered lab's table: (number, text).
const TABLES: &[(u8, &str)] = include!(concat!(env!("OUT_DIR"), "/tables.rs"));

/// One lab of the course.
#[derive(Debug)]
pub struct Lab {
    /// Which lab.
    pub id: LabId,
    /// Its title.
    pub title: String,
    /// Its exercises, in order.
    pub exercises: Vec<ExerciseInfo>,
    /// The items a submission may not name.
    pub denied: Vec<DeniedItem>,
}

impl Lab {
    /// The exercise numbered `id` (`"2.2"`).
    pub fn exercise(&self, id: &str) -> Option<&ExerciseInfo> {
        self.exercises.iter().find(|e| e.id == id)
    }

    /// Points of all its exercises.
    pub fn points(&self) -> u32 {
        self.exercises.iter().map(|e| e.points).sum()
    }
}

/// An error about the course: a lab it does not have, an exercise table that does not parse.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CourseError(pub String);

impl std::fmt::Display for CourseError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for CourseError {}

fn registry() -> &'static [(LabId, String)] {
    static LABS: OnceLock<Vec<(LabId, String)>> = OnceLock::new();
    LABS.get_or_init(|| {
        // The build script read this text with the same parser: it cannot fail here.
        registry::parse(REGISTRY)
            .expect("the build script checked labs/course.toml")
            .into_iter()
            .map(|e| (LabId::of(e.number.into()), e.title))
            .collect()
    })
}

/// The labs of the course, in order.
pub fn labs() -> Vec<LabId> {
    registry().iter().map(|(id, _)| *id).collect()
}

/// The labs of the course from the first up to `lab`, in order; none when the course has no
/// lab `lab`.
pub fn labs_through(lab: LabId) -> Vec<LabId> {
    let labs = labs();
    match labs.iter().position(|&l| l == lab) {
        Some(at) => labs[..=at].to_vec(),
        None => Vec::new(),
    }
}

/// The last lab of the course.
pub fn last() -> LabId {
    registry().last().expect("the registry lists a lab").0
}

/// The title of lab `id`, if the course has it.
pub fn title(id: LabId) -> Option<&'static str> {
    registry()
        .iter()
        .find(|(l, _)| *l == id)
        .map(|(_, t)| t.as_str())
}

/// Lab `id` with its exercise table; an error for a lab the course does not have, or whose
/// table does not parse (the error names the file and line).
pub fn lab(id: LabId) -> Result<&'static Lab, CourseError> {
    static TABLES_READ: OnceLock<Vec<Result<Lab, CourseError>>> = OnceLock::new();
    let tables = TABLES_READ.get_or_init(|| {
        registry()
            .iter()
            .map(|(lab, title)| {
                let text = TABLES
                    .iter()
                    .find(|(n, _)| u32::from(*n) == lab.number())
                    .map(|(_, t)| *t)
                    .expect("the build script embedded every registered lab's table");
                let file = format!("{}/exercises.toml", lab.folder());
                parse_table(*lab, &file, text)
                    .map(|(exercises, denied)| Lab {
                        id: *lab,
                        title: title.clone(),
                        exercises,
                        denied,
                    })
                    .map_err(CourseError)
            })
            .collect()
    });
    match registry().iter().position(|(l, _)| *l == id) {
        Some(i) => tables[i].as_ref().map_err(Clone::clone),
        None => Err(unknown_lab(id)),
    }
}

/// The error for a lab the course does not have.
fn unknown_lab(id: LabId) -> CourseError {
    let labs: Vec<String> = labs().iter().map(|l| l.number().to_string()).collect();
    CourseError(format!(
        "the course has no {id} (labs/course.toml lists the labs {})",
        labs.join(", ")
    ))
}

/// Checks that the course has lab `id`.
pub fn check(id: LabId) -> Result<LabId, CourseError> {
    title(id).map(|_| id).ok_or_else(|| unknown_lab(id))
}

/// The exercise numbered `id` (`"2.3"`) in the course; an error that says which exercises
/// there are when it has none such.
pub fn exercise(id: &str) -> Result<&'static ExerciseInfo, CourseError> {
    let lab = id
        .split_once('.')
        .and_then(|(lab, _)| lab.parse::<LabId>().ok())
        .ok_or_else(|| {
            CourseError(format!(
                "exercise '{id}': expected an exercise number N.M, such as 2.3"
            ))
        })?;
    let lab = self::lab(check(lab)?)?;
    lab.exercise(id).ok_or_else(|| {
        let ids: Vec<&str> = lab.exercises.iter().map(|e| e.id.as_str()).collect();
        CourseError(format!(
            "exercise '{id}': lab {} has the exercises {}",
            lab.id.number(),
            ids.join(", ")
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_registered_lab_has_a_table_that_parses() {
        assert!(!labs().is_empty());
        for id in labs() {
            let lab = lab(id).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(lab.id, id);
            assert!(lab.points() > 0);
        }
    }

    #[test]
    fn unknown_labs_and_exercises_are_errors_that_say_what_there_is() {
        let missing = LabId::of(99);
        assert!(lab(missing).unwrap_err().0.contains("labs/course.toml"));
        let first = labs()[0];
        let error = exercise(&format!("{}.99", first.number())).unwrap_err();
        assert!(error.0.contains("has the exercises"), "{error}");
        assert!(exercise("two").is_err());
        assert_eq!(
            exercise(&format!("{}.1", first.number())).unwrap().lab,
            first
        );
    }
}
