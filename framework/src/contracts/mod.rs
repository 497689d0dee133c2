//! The lab contracts: one module per lab with the traits a student implements and their data
//! types. The renderer reaches student code only through these traits, composed in a
//! [`Pipeline`](crate::pipeline::Pipeline); a lab's checks live in [`crate::labs`].
//!
//! This layer stands above `scene` and `sampling` (the types the traits take) and below the
//! pipeline: it imports nothing that renders or checks.

pub mod lab01;
pub mod lab02;
pub mod lab03;
pub mod lab04;
pub mod lab05;
pub mod lab06;
pub mod lab07;
pub mod lab08;
pub mod lab09;
pub mod lab10;
pub mod lab11;
