//! Workspace-level test support: the helpers of the tests that run the command line on copies
//! of the tree (handouts, grading, hostile submissions). Each lab's own tests — its mutant
//! corpus among them — are in the lab's folder (`labs/labNN/tests/`).

pub mod workflow;
