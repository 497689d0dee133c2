use glam::Vec2;

/// The PCG32 generator (O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient
/// Statistically Good Algorithms for Random Number Generation"), XSH-RR output.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Rng {
    state: u64,
    inc: u64,
}

const MULTIPLIER: u64 = 6364136223846793005;

impl Rng {
    /// A generator on stream `stream`, started from `seed`.
    pub fn new(seed: u64, stream: u64) -> Self {
        let mut rng = Self {
            state: 0,
            inc: (stream << 1) | 1,
        };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(seed);
        rng.next_u32();
        rng
    }

    /// The generator for sample `sample` of pixel `(x, y)` in a render with seed `seed`.
    pub fn for_sample(seed: u64, x: u32, y: u32, sample: u32) -> Self {
        Self::new(sample_seed(seed, x, y, sample), seed)
    }

    /// The next 32 uniformly distributed bits.
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(MULTIPLIER).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// A uniform float in `[0, 1)` (24 random bits, so 1.0 never occurs).
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
    }

    /// A uniform point in `[0, 1)²`.
    pub fn next_vec2(&mut self) -> Vec2 {
        let x = self.next_f32();
        Vec2::new(x, self.next_f32())
    }

    /// A uniform integer in `0..n` (Lemire's multiply-shift; `n > 0`).
    pub fn next_below(&mut self, n: u32) -> u32 {
        ((self.next_u32() as u64 * n as u64) >> 32) as u32
    }
}

/// A 64-bit seed for one (pixel, sample) of a render: the coordinates hashed with SplitMix64's
/// finalizer, so neighbouring pixels get unrelated sequences.
pub fn sample_seed(seed: u64, x: u32, y: u32, sample: u32) -> u64 {
    let mut h = seed ^ 0x9E37_79B9_7F4A_7C15;
    for v in [x as u64, y as u64, sample as u64] {
        h = splitmix64(h ^ v.wrapping_mul(0xD6E8_FEB8_6659_FD93));
    }
    h
}

fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pcg32_matches_the_reference_sequence() {
        // pcg32-demo from pcg-c-basic: seed 42, sequence 54.
        let mut rng = Rng::new(42, 54);
        let got: Vec<u32> = (0..6).map(|_| rng.next_u32()).collect();
        assert_eq!(
            got,
            [
                0xa15c02b7, 0x7b47f409, 0xba1d3330, 0x83d2f293, 0xbfa4784b, 0xcbed606e
            ]
        );
    }

    #[test]
    fn floats_are_in_unit_interval_with_mean_one_half() {
        let mut rng = Rng::for_sample(7, 3, 4, 5);
        let n = 100_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let u = rng.next_f32();
            assert!((0.0..1.0).contains(&u));
            sum += u as f64;
        }
        assert!((sum / n as f64 - 0.5).abs() < 0.005);
    }

    #[test]
    fn neighbouring_samples_differ() {
        let a = Rng::for_sample(1, 10, 10, 0).next_u32();
        let b = Rng::for_sample(1, 11, 10, 0).next_u32();
        let c = Rng::for_sample(1, 10, 10, 1).next_u32();
        let d = Rng::for_sample(2, 10, 10, 0).next_u32();
        assert!(a != b && a != c && a != d);
    }
}
