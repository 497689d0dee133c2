//! The work a student's code may do, counted in wasmtime's fuel (about one unit per
//! WebAssembly instruction): so much per call and so much per run of a check, so that an
//! endless loop fails its exercise after the same work on every machine, as a time-out, long
//! before the grader's wall clock would stop the process.
//!
//! The budgets come from the answer keys compiled as students' crates and judged through every
//! exercise of every lab with fuel on, as the grader judges them (`tests/tests/graded_wasm.rs`,
//! `every_lab_s_key_within_the_budgets`, run with `--ignored`; 2-core machine): the most one
//! call used was 2.80·10⁸ units (lab 05, Exercise 5.7, a numerical integral calling back per
//! step), the most one run used 8.82·10⁹ (lab 12's path tracer, Exercise 12.8, 17.5 s); no
//! lab nests calls. The budgets are 10.7 and 5.7 times those. An endless loop burns a call's
//! budget in 0.8 s there (about 4·10⁹ units a second), and once a call of a run has run past
//! its budget every later call of that run fails at once: lab 1 with a loop in 1.1 fails 1.1 in
//! 0.8 s and passes 1.6 (on the key's 1.1) in 2.4 s.

use contracts::wire::OUT_OF_WORK;

/// The most fuel one call of the student's code may use, nested calls included.
pub const CALL_FUEL: u64 = 3_000_000_000;

/// The most fuel all calls of one run of a check may use together.
pub const RUN_FUEL: u64 = 50_000_000_000;

/// Which budget a call's fuel came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Limit {
    /// The call's own, [`CALL_FUEL`].
    Call,
    /// What was left of the run's, [`RUN_FUEL`].
    Run,
}

impl Limit {
    /// The message of a call stopped for having used up this budget.
    pub fn message(self) -> String {
        match self {
            Limit::Call => format!(
                "{OUT_OF_WORK} for one call: {} units of fuel, about one WebAssembly instruction \
                 each (an endless loop?)",
                grouped(CALL_FUEL)
            ),
            Limit::Run => format!(
                "{OUT_OF_WORK} for one run of the check: {} units of fuel in all its calls, \
                 about one WebAssembly instruction each (an endless loop, or far too much work \
                 per call?)",
                grouped(RUN_FUEL)
            ),
        }
    }
}

/// The most work the student's code did, for measuring the budgets.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Work {
    /// The most fuel one call used (with the calls nested in it).
    pub most_in_one_call: u64,
    /// The most fuel one run used.
    pub most_in_one_run: u64,
    /// The calls made.
    pub calls: u64,
    /// The calls made from a callback of another call (through one of its closures).
    pub nested_calls: u64,
}

/// `n` with its digits in groups of three: `2 000 000 000`.
pub(crate) fn grouped(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budgets_are_written_with_their_digits_grouped() {
        assert_eq!(grouped(2_000_000_000), "2 000 000 000");
        assert_eq!(grouped(999), "999");
        assert_eq!(grouped(1000), "1 000");
        assert!(Limit::Call.message().starts_with(OUT_OF_WORK));
        assert!(Limit::Run.message().contains(&grouped(RUN_FUEL)));
    }
}
