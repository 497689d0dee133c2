//! Test data for the framework's unit tests: points, indices and awkward coordinates drawn from
//! the framework's own generator ([`sampling::Rng`](crate::sampling::Rng)), so that every test's
//! data is fixed by its seed.

use glam::Vec3;

use crate::sampling;

/// A deterministic source of test data.
pub(crate) struct Rng(sampling::Rng);

impl Rng {
    /// The generator for test seed `seed`.
    pub fn new(seed: u64) -> Self {
        Rng(sampling::Rng::new(seed, 0))
    }

    /// A uniform value in `[0, 1)`.
    pub fn next(&mut self) -> f32 {
        self.0.next_f32()
    }

    /// A point in `[-1, 1)³`.
    pub fn vec(&mut self) -> Vec3 {
        Vec3::new(self.next(), self.next(), self.next()) * 2.0 - 1.0
    }

    /// An index in `0..n` (`0 < n ≤ u32::MAX`).
    pub fn below(&mut self, n: usize) -> usize {
        self.0.next_below(n as u32) as usize
    }

    /// A coordinate in `[-1, 1)`, exactly 0, −0, 1 or −1 one time in sixteen each: the values
    /// at which slab and edge tests meet their special cases.
    pub fn coord(&mut self) -> f32 {
        match self.0.next_below(16) {
            0 => 0.0,
            1 => -0.0,
            2 => 1.0,
            3 => -1.0,
            _ => self.next() * 2.0 - 1.0,
        }
    }

    /// A point of three [`coord`](Self::coord)s.
    pub fn coords(&mut self) -> Vec3 {
        Vec3::new(self.coord(), self.coord(), self.coord())
    }
}
