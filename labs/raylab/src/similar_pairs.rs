//! The similar pairs `raylab similarity` writes (its page and CSV) and the class page's section
//! on them.

use std::path::Path;

use maud::{Markup, html};

use crate::grade::submission::read_regular;

/// The page of similar pairs, in the output directory.
pub const PAGE: &str = "similarity.html";
/// The similar pairs as CSV, in the output directory: `lab`, `student_a`, `student_b`,
/// `similarity` (0 to 1), `longest_fragment` (in k-grams of tokens), `fragment_a`, `fragment_b`
/// (where the longest shared fragment is in each, `labs/labNN/src/FILE:LINE–LINE`).
pub const CSV: &str = "similarity.csv";
/// The largest [`CSV`] read back for the class page (8 MiB).
pub const MAX_CSV_BYTES: u64 = 8 << 20;
/// The most pairs listed on the class page (all are in [`PAGE`]).
const MAX_CLASS_PAGE_PAIRS: usize = 20;

/// The section of the class page (`index.html` of `raylab grade`) on similar submissions, when
/// `raylab similarity` wrote its results into `dir`: how many pairs, the most similar ones, and
/// a link to [`PAGE`]. `None` when `dir` holds no readable [`CSV`].
pub fn link_for_class_page(dir: &Path) -> Option<Markup> {
    let bytes = read_regular(&dir.join(CSV), MAX_CSV_BYTES).ok()?;
    let mut reader = csv::Reader::from_reader(bytes.as_slice());
    let rows: Vec<csv::StringRecord> = reader.records().collect::<Result<_, _>>().ok()?;
    Some(html! {
        section id="similarity" {
            h2 { "Similar submissions" }
            p {
                (rows.len()) " pairs at or above the threshold of "
                code { "raylab similarity" } ": see " a href=(PAGE) { (PAGE) } "."
            }
            @if !rows.is_empty() {
                table {
                    thead { tr { th { "lab" } th { "student A" } th { "student B" } th { "similarity" } } }
                    tbody {
                        @for row in rows.iter().take(MAX_CLASS_PAGE_PAIRS) {
                            tr {
                                @for k in 0..4 { td { (row.get(k).unwrap_or_default()) } }
                            }
                        }
                    }
                }
            }
        }
    })
}
