//! Items a handout ships that compute what an exercise asks. The framework keeps fast kernels
//! and conveniences of its own (the scene's closest-hit query, say), and glam has a few answers
//! of its own (`Vec3::reflect`), that a student could call instead of writing the exercise;
//! `raylab grade` looks for their names in a submission's source and gives no points for the
//! exercises they answer, saying so in the report.

/// An item a submission may not name, and the exercises it would answer.
#[derive(Clone, Copy, Debug)]
pub struct DeniedItem {
    /// The item's name as it appears in code (`trace_to_closest`): an identifier token.
    pub name: &'static str,
    /// Where the name is the student's own: empty when every use of it counts; otherwise the
    /// receivers and paths under which it is the lab's contract (`["self", "Self",
    /// "Reflection"]` for `reflect`, a method of lab 04's contract and of glam's `Vec3`). Then
    /// only a call on another receiver (`d.reflect(n)`) or path (`Vec3::reflect`) counts.
    pub own: &'static [&'static str],
    /// The exercises whose answer it computes (`"2.1"`).
    pub exercises: &'static [&'static str],
    /// Whose it is and what it computes, for the report: "the framework's closest hit of a ray
    /// in a scene".
    pub computes: &'static str,
}

impl DeniedItem {
    /// Whether a use of the name counts, given the token before it (`.` or `::`, if any) and
    /// the identifier before that: always when [`own`](Self::own) is empty; otherwise only a
    /// method call or path whose receiver or qualifier is not one of `own`.
    pub fn counts(&self, qualified: bool, qualifier: Option<&str>) -> bool {
        self.own.is_empty() || (qualified && !qualifier.is_some_and(|q| self.own.contains(&q)))
    }
}
