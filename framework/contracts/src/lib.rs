//! # The lab contracts
//!
//! One module per lab with the traits a student implements and their data types, with the doc
//! comments that teach. The renderer reaches student code only through these traits, composed
//! in the `pipeline` crate's `Pipeline`; each lab's checks are its own crate (`labs/labNN/checks`).
//!
//! This crate stands on `raylab-types` alone (the data the traits take, re-exported here as
//! [`math`], [`sampling`], [`scene`] and [`glam`]) and nothing that renders or checks: a
//! student's crate depends on it and on nothing else, so the framework's own kernels and scene
//! queries are out of its reach.

pub use raylab_types::{glam, math, sampling, scene};

// One module per lab contract `src/labNN.rs`, one per lab of the registry (`labs/course.toml`),
// and `LABS`.
contract_macros::lab_modules!();

mod part_slot;
pub mod parts;
pub mod surface;
pub mod trace;
pub mod wire;

pub use parts::{Part, Parts};

/// A lab of the course as a pipeline meets it ([`LABS`]).
#[derive(Clone, Copy, Debug)]
pub struct LabParts {
    /// Its number.
    pub lab: u32,
    /// Puts the lab's [`Waiting`] slot into a store: the code of a lab whose solution the
    /// tree does not hold.
    pub waiting: fn(&mut Parts),
    /// Takes the lab's code out of a store.
    pub remove: fn(&mut Parts),
}

/// The labs of the course after lab `lab`, in order; every lab when the course has no lab
/// `lab`.
pub fn labs_after(lab: u32) -> &'static [LabParts] {
    &LABS[labs_through(lab).len()..]
}

/// The labs of the course from the first up to lab `lab`, in the course's order; none when
/// the course has no lab `lab`.
pub fn labs_through(lab: u32) -> &'static [LabParts] {
    LABS.iter()
        .position(|l| l.lab == lab)
        .map_or(&[], |at| &LABS[..=at])
}

pub use contract_macros::{answer_keys, contract};
pub use part_slot::{
    CallLog, ContractMethods, Mix, PartSlot, StudentFor, WAITING_FOR_LAB, Waiting, method_bit,
};
pub use trace::{Trace, Traced};
