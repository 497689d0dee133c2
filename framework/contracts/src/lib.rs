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

// One module per lab contract `src/labNN.rs`, one per lab of the registry (`labs/course.toml`).
contract_macros::lab_modules!();

mod part_slot;
pub mod trace;
pub mod wire;

pub use contract_macros::{answer_keys, contract};
pub use part_slot::{
    CallLog, ContractMethods, Mix, PartSlot, StudentFor, WAITING_FOR_LAB, Waiting, method_bit,
};
pub use trace::{Trace, Traced};
