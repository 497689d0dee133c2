//! The answer key: one module per lab implementing that lab's contract from
//! `contracts` — every lab in the course's repository, the released ones in a
//! handout — and [`pipeline`], the reference [`Pipeline`] every check and render starts from.
//!
//! Which labs' solutions the crate holds is which `src/labNN.rs` are in the tree
//! (`contracts::answer_keys!` lists them: no line here names a lab). Each key is the type
//! `labNN::LabNN`, which implements the lab's `contracts::labNN::Contract`; the slot of a lab
//! whose solution the crate does not hold is a [`contracts::Waiting`] one, so that no lab's tests need another lab's student
//! crate (a lab's harness puts its own student's code in its own slot).

use pipeline::Pipeline;

contracts::answer_keys!();

/// The reference pipeline of the course's labs up to `lab`: the answer key of each lab whose
/// solution this crate holds ([`KEYS`]), a waiting slot for the others, and no later lab's
/// code, so that what it draws is what the course has taught by then. The framework's kernels
/// intersect: they equal the key's up to rounding, and are faster.
pub fn pipeline(lab: u32) -> Pipeline {
    Pipeline::default()
        .with_parts(|parts| {
            for l in contracts::labs_through(lab) {
                match KEYS.iter().position(|&key| key == l.lab) {
                    Some(at) => INSTALL_KEYS[at](parts),
                    None => (l.waiting)(parts),
                }
            }
        })
        .with_framework_intersection()
}
