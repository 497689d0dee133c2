//! Random numbers for Monte Carlo rendering. Every (pixel, sample) pair gets its own generator,
//! seeded from the render seed and its coordinates, so an image never depends on the thread
//! count or the order in which tiles are scheduled.

mod rng;

pub use rng::{Rng, sample_seed};
