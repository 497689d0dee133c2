//! Per lab, its checks (each exercise's check, bound to the lab's exercise table in
//! `labs/labNN/exercises.toml`) and the generator of its golden data. The labs of the course
//! and their exercises are the `course` crate's; the contracts the checks test are in
//! [`crate::contracts`].

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
pub mod strategies;
