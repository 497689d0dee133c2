//! `raylab hint N.M`: the next step of an exercise, for a student who is stuck. The hints are
//! data in each lab's exercise table (`raylab_core::labs`), beside the exercise's title and
//! points; the stub says what to compute and the docs give the formula.

use clap::Args;
use course::{ExerciseInfo, LabId, Visibility};
use raylab_core::Error;

/// Options of `raylab hint`.
#[derive(Args, Debug)]
pub struct HintArgs {
    /// The exercise, numbered as in the docs and the stubs (e.g. `2.3`).
    pub exercise: String,
}

/// Runs `raylab hint`.
pub fn run(args: &HintArgs) -> Result<(), Error> {
    println!("{}", hint(&args.exercise)?);
    Ok(())
}

/// The hint of exercise `id` with where to find the exercise and the command that checks it,
/// or an error naming the exercises there are. A hidden exercise's test is not among a
/// handout's: its hint says so and names the lab's tests instead.
pub fn hint(id: &str) -> Result<String, Error> {
    let exercise = find(id)?;
    let lab = exercise.lab;
    let check = match exercise.visibility {
        Visibility::Visible => format!("check your code with `{}`.", exercise.test_command()),
        Visibility::Hidden => format!(
            "its test runs only when your work is graded, not in `cargo test -p {lab}`, which \
             checks the exercises it builds on."
        ),
    };
    Ok(format!(
        "Exercise {id} — {title} (`{function}` in labs/{lab}/src/lib.rs)\n\n\
         {hint}\n\n\
         The exercise is in docs/{lab}.md, Exercise {id}; {check}",
        id = exercise.id,
        title = exercise.title,
        function = exercise.function,
        hint = exercise.hint,
    ))
}

/// The exercise numbered `id` in the course.
pub fn find(id: &str) -> Result<&'static ExerciseInfo, Error> {
    let lab = id
        .split_once('.')
        .and_then(|(lab, _)| lab.parse::<LabId>().ok());
    if let Some(lab) = lab {
        crate::labs::check_lab(lab)?;
    }
    course::exercise(id).map_err(|e| Error::Invalid {
        what: format!("exercise '{id}'"),
        reason: e
            .0
            .split_once(": ")
            .map_or(e.0.clone(), |(_, why)| why.to_string()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_exercise_of_every_lab_has_a_hint_of_its_own() {
        let mut seen = std::collections::HashSet::new();
        for lab in crate::labs::labs() {
            for e in crate::labs::exercises(lab) {
                let text = hint(&e.id).unwrap();
                assert!(e.hint.len() >= 40, "Exercise {}'s hint is too short", e.id);
                assert!(text.contains(&e.hint) && text.contains(&e.function));
                assert!(
                    seen.insert(e.hint.clone()),
                    "Exercise {} repeats a hint",
                    e.id
                );
            }
        }
    }

    /// A visible exercise's hint names the command that runs its test alone; a hidden one's,
    /// whose test a handout does not have, names none of its own.
    #[test]
    fn a_hint_names_a_test_command_only_for_a_test_the_handout_has() {
        for lab in crate::labs::labs() {
            for e in crate::labs::exercises(lab) {
                let text = hint(&e.id).unwrap();
                let own = format!("exercise_{}", e.id.replace('.', "_"));
                match e.visibility {
                    Visibility::Visible => assert!(
                        text.contains(&format!("`cargo test -p {lab} {own}_`")),
                        "{text}"
                    ),
                    Visibility::Hidden => {
                        assert!(!text.contains(&own), "{text}");
                        assert!(!text.contains("raylab-failures"), "{text}");
                    }
                }
            }
        }
    }

    #[test]
    fn an_unknown_exercise_is_named_with_the_ones_there_are() {
        let error = hint("2.9").unwrap_err().to_string();
        assert!(
            error.contains("'2.9'") && error.contains("2.1, 2.2"),
            "{error}"
        );
        let error = hint("two").unwrap_err().to_string();
        assert!(error.contains("N.M"), "{error}");
        let error = hint("99.1").unwrap_err().to_string();
        assert!(error.contains("lab 99"), "{error}");
    }
}
