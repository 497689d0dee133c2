//! Framework items that compute what an exercise asks. The framework keeps fast kernels and
//! conveniences of its own (the scene's closest-hit query, say) that a student could call
//! instead of writing the exercise; `raylab grade` looks for their names in a submission's
//! source and gives no points for the exercises they answer, saying so in the report.

/// A framework item a submission may not name, and the exercises it would answer.
#[derive(Clone, Copy, Debug)]
pub struct DeniedItem {
    /// The item's name as it appears in code (`trace_to_closest`): an identifier token.
    pub name: &'static str,
    /// The exercises whose answer it computes (`"2.1"`).
    pub exercises: &'static [&'static str],
    /// What it computes, for the report: "the closest hit of a ray in a scene".
    pub computes: &'static str,
}
