//! A lab's exercise table (`labs/labNN/exercises.toml`): what each exercise is called, what it
//! is worth, who sees its test, its hint; and the items a submission may not name.

use serde::{Deserialize, Serialize};

use crate::LabId;

/// Whether students see an exercise's test before grading (Gradescope's `visibility`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Visibility {
    /// In the handout: `cargo test` and `raylab status` run it.
    #[default]
    Visible,
    /// Left out of the handout's tests; run only by `raylab grade` (the lab's golden data and
    /// snapshots still ship, since the other exercises share them).
    Hidden,
}

/// One exercise of a lab, as its table states it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExerciseInfo {
    /// The lab.
    pub lab: LabId,
    /// Its number as in the docs, `"2.2"`.
    pub id: String,
    /// The student function it is about (`intersect_triangle`).
    pub function: String,
    /// One-line description.
    pub title: String,
    /// Points it is worth.
    pub points: u32,
    /// Whether students see its test before grading.
    pub visibility: Visibility,
    /// The next step for a student who is stuck (`raylab hint N.M`): where to look or what to
    /// try, without the formula.
    pub hint: String,
}

/// Whether `function` names one function (`intersect_triangle`), not several checked together
/// (`CameraRays (all of it)`).
pub fn is_function_name(function: &str) -> bool {
    !function.is_empty()
        && function
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_')
}

impl ExerciseInfo {
    /// Whether the exercise checks several of the student's functions together (its `function`
    /// is not one name): it is worth no points of its own, and its check passes only on the
    /// student's code, the key's in place of those functions whose own exercises fail.
    pub fn is_composite(&self) -> bool {
        !is_function_name(&self.function)
    }

    /// The name of the exercise's test starts with this: `exercise_2_2_` for Exercise 2.2.
    pub fn test_prefix(&self) -> String {
        format!("exercise_{}_", self.id.replace('.', "_"))
    }

    /// The name of its test: `exercise_2_2_intersect_triangle`.
    pub fn test_name(&self) -> String {
        format!("{}{}", self.test_prefix(), self.function)
    }

    /// The command that runs its test alone, from anywhere in the workspace: `cargo test -p
    /// lab02 exercise_2_2_`. The filter is the test's prefix, `_` included, so that
    /// `exercise_12_1_` leaves 12.10–12.13 out; a hidden exercise's test is built only with
    /// the lab's `hidden-exercises` feature.
    pub fn test_command(&self) -> String {
        let features = match self.visibility {
            Visibility::Visible => "",
            Visibility::Hidden => " --features hidden-exercises",
        };
        format!(
            "cargo test -p {}{features} {}",
            self.lab,
            self.test_prefix()
        )
    }
}

/// An item a handout ships that computes what an exercise asks (the framework's closest-hit
/// query, glam's `Vec3::reflect`): `raylab grade` looks for its name in a submission and gives
/// no points for the exercises it answers, saying so in the report.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DeniedItem {
    /// The item's name as it appears in code (`trace_to_closest`): an identifier token.
    pub name: String,
    /// Where the name is the student's own: empty when every use of it counts; otherwise the
    /// receivers and paths under which it is the lab's contract (`["self", "Self",
    /// "Reflection"]` for `reflect`, a method of lab 04's contract and of glam's `Vec3`). Then
    /// only a call on another receiver (`d.reflect(n)`) or path (`Vec3::reflect`) counts.
    #[serde(default)]
    pub own: Vec<String>,
    /// The exercises whose answer it computes (`"2.1"`).
    pub exercises: Vec<String>,
    /// Whose it is and what it computes, for the report: "the framework's closest hit of a ray
    /// in a scene".
    pub computes: String,
}

impl DeniedItem {
    /// Whether a use of the name counts, given the token before it (`.` or `::`, if any) and
    /// the identifier before that: always when [`own`](Self::own) is empty; otherwise only a
    /// method call or path whose receiver or qualifier is not one of `own`.
    pub fn counts(&self, qualified: bool, qualifier: Option<&str>) -> bool {
        self.own.is_empty()
            || (qualified && !qualifier.is_some_and(|q| self.own.iter().any(|o| o == q)))
    }
}

/// A lab's table as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Table {
    exercise: Vec<Row>,
    #[serde(default)]
    denied: Vec<DeniedItem>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Row {
    id: String,
    function: String,
    title: String,
    points: u32,
    #[serde(default)]
    visibility: Visibility,
    hint: String,
}

/// The exercises and denied items of lab `lab`'s table `text` (from `file`, which errors
/// name); `Err` says what is wrong and where.
pub fn parse_table(
    lab: LabId,
    file: &str,
    text: &str,
) -> Result<(Vec<ExerciseInfo>, Vec<DeniedItem>), String> {
    let table: Table = toml::from_str(text).map_err(|e| format!("{file}: {e}"))?;
    let mut exercises: Vec<ExerciseInfo> = Vec::new();
    for row in table.exercise {
        let wrong = |why: String| Err(format!("{file}: exercise '{}': {why}", row.id));
        let number = row
            .id
            .split_once('.')
            .filter(|(l, m)| {
                l.parse::<u32>().ok() == Some(lab.number())
                    && !m.is_empty()
                    && m.bytes().all(|b| b.is_ascii_digit())
                    && !m.starts_with('0')
            })
            .map(|(_, m)| m);
        if number.is_none() {
            return wrong(format!("expected {}.M, M from 1 up", lab.number()));
        }
        if exercises.iter().any(|e| e.id == row.id) {
            return wrong("listed twice".into());
        }
        for (field, value) in [
            ("function", &row.function),
            ("title", &row.title),
            ("hint", &row.hint),
        ] {
            if value.trim().is_empty() {
                return wrong(format!("its {field} is empty"));
            }
        }
        let one_function = is_function_name(&row.function);
        if row.points == 0 && one_function {
            return wrong("it is worth no points".into());
        }
        if row.points != 0 && !one_function {
            return wrong(format!(
                "it checks several functions together (`{}`), so it is worth no points of its \
                 own: its points are those of the exercises of its functions",
                row.function
            ));
        }
        exercises.push(ExerciseInfo {
            lab,
            id: row.id,
            function: row.function,
            title: row.title,
            points: row.points,
            visibility: row.visibility,
            hint: row.hint.trim().to_string(),
        });
    }
    if exercises.is_empty() {
        return Err(format!("{file}: the lab has no [[exercise]]"));
    }
    for item in &table.denied {
        if let Some(unknown) = item
            .exercises
            .iter()
            .find(|id| !exercises.iter().any(|e| &&e.id == id))
        {
            return Err(format!(
                "{file}: denied item '{}' names exercise '{unknown}', which the table does not have",
                item.name
            ));
        }
    }
    Ok((exercises, table.denied))
}

#[cfg(test)]
mod tests {
    use super::*;

    const LAB: LabId = LabId::of(3);

    fn row(id: &str, points: u32) -> String {
        format!(
            "[[exercise]]\nid = \"{id}\"\nfunction = \"f\"\ntitle = \"t\"\npoints = {points}\nhint = \"h\"\n"
        )
    }

    #[test]
    fn reads_a_table_and_refuses_mistakes_naming_the_file() {
        let text = format!(
            "{}{}visibility = \"hidden\"\n",
            row("3.1", 2),
            row("3.2", 1)
        );
        let (exercises, denied) = parse_table(LAB, "t.toml", &text).unwrap();
        assert_eq!(exercises.len(), 2);
        assert_eq!(exercises[1].visibility, Visibility::Hidden);
        assert_eq!(exercises[0].test_name(), "exercise_3_1_f");
        assert_eq!(
            exercises[0].test_command(),
            "cargo test -p lab03 exercise_3_1_"
        );
        assert_eq!(
            exercises[1].test_command(),
            "cargo test -p lab03 --features hidden-exercises exercise_3_2_"
        );
        assert!(denied.is_empty());
        // An exercise of several functions together is worth none of its own.
        let composite = format!(
            "{}{}",
            row("3.1", 1),
            row("3.2", 0).replace("\"f\"", "\"Shadows (all of it)\"")
        );
        let (exercises, _) = parse_table(LAB, "t.toml", &composite).unwrap();
        assert!(exercises[1].is_composite() && !exercises[0].is_composite());
        for bad in [
            row("2.1", 1),
            row("3.0", 1),
            row("3.x", 1),
            row("3.1", 0),
            row("3.1", 1).replace("\"f\"", "\"Shadows (all of it)\""),
            format!("{}{}", row("3.1", 1), row("3.1", 1)),
            format!("{}colour = 1\n", row("3.1", 1)),
            format!(
                "{}[[denied]]\nname = \"x\"\nexercises = [\"3.9\"]\ncomputes = \"c\"\n",
                row("3.1", 1)
            ),
            String::new(),
        ] {
            let error = parse_table(LAB, "t.toml", &bad).unwrap_err();
            assert!(error.starts_with("t.toml"), "{bad}: {error}");
        }
    }

    #[test]
    fn a_denied_item_of_the_contract_counts_only_on_another_receiver() {
        let item = DeniedItem {
            name: "reflect".into(),
            own: vec!["self".into(), "Reflection".into()],
            exercises: vec!["4.1".into()],
            computes: "glam's reflection".into(),
        };
        assert!(!item.counts(true, Some("self")));
        assert!(item.counts(true, Some("d")));
        assert!(!item.counts(false, None));
    }
}
