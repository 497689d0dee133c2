//! The random numbers of the framework's unit tests: a tiny deterministic generator (the
//! PCG-like LCG step of Knuth's MMIX constants), so that every test's data is fixed by its seed.

use glam::Vec3;

/// A deterministic generator for test data.
pub(crate) struct Rng(pub u64);

impl Rng {
    /// A uniform value in `[0, 1)`.
    pub fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 40) as f32) / (1u64 << 24) as f32
    }

    /// A point in `[-1, 1]³`.
    pub fn vec(&mut self) -> Vec3 {
        Vec3::new(self.next(), self.next(), self.next()) * 2.0 - 1.0
    }

    /// An index in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        ((self.next() * n as f32) as usize).min(n - 1)
    }

    /// A coordinate in `[-1, 1)`, exactly 0, −0, 1 or −1 one time in sixteen each: the values
    /// at which slab and edge tests meet their special cases.
    pub fn coord(&mut self) -> f32 {
        match (self.next() * 16.0) as u32 {
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
