//! χ² goodness-of-fit tests of samplers against their densities, in the style of Mitsuba 3's
//! `ChiSquareTest` and pbrt-v4's sampling tests: samples are binned, the density is
//! integrated over every bin, bins of low expected count are pooled, and Pearson's statistic
//! gives a p-value. [`SphereGrid`] bins directions of the sphere; [`chi_square_pooled`] works
//! on any histogram.

use glam::Vec3;

use super::stats::chi_square_p_value;

/// The outcome of a χ² test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChiSquareOutcome {
    /// Pearson's statistic `Σ (O − E)²/E` over the (pooled) cells.
    pub statistic: f64,
    /// Degrees of freedom: the cells compared, less one.
    pub degrees_of_freedom: u32,
    /// The probability of a statistic at least this large if the samples follow the density.
    pub p_value: f64,
    /// How many cells of low expected count were pooled into others.
    pub pooled_cells: usize,
}

/// Pearson's χ² test of `observed` counts against `expected` ones (same length): cells are
/// taken in increasing expected count, and those below `min_expected` (5 in the literature)
/// are pooled until the pool reaches it. A sample in a cell of zero expected count — where
/// the density is zero — is an error, as is a test left with no degree of freedom.
pub fn chi_square_pooled(
    observed: &[u64],
    expected: &[f64],
    min_expected: f64,
) -> Result<ChiSquareOutcome, String> {
    assert_eq!(
        observed.len(),
        expected.len(),
        "one expected count per cell"
    );
    let mut order: Vec<usize> = (0..expected.len()).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let term = |o: f64, e: f64| (o - e) * (o - e) / e.max(1e-300);
    let mut pooled = Pooled::new(min_expected);
    for i in order {
        let (o, e) = (observed[i] as f64, expected[i]);
        if e <= 0.0 {
            if o > 0.0 {
                return Err(format!(
                    "{o} samples fell in cell {i}, where the density is zero"
                ));
            }
            continue;
        }
        pooled.add(o, e, e, &term);
    }
    pooled.finish(&term, |cells| {
        format!(
            "only {cells} cell(s) with an expected count of at least {min_expected}: too few samples for a χ² test"
        )
    })
}

/// Cells summed into a χ² statistic by `term(x, y)`: a cell of size below the minimum joins a
/// pool, which counts as one cell once its size reaches the minimum; what is left of the pool
/// at the end joins as one cell too.
struct Pooled {
    min: f64,
    statistic: f64,
    cells: u32,
    pooled_cells: usize,
    pool: (f64, f64, f64),
    in_pool: usize,
}

impl Pooled {
    fn new(min: f64) -> Self {
        Self {
            min,
            statistic: 0.0,
            cells: 0,
            pooled_cells: 0,
            pool: (0.0, 0.0, 0.0),
            in_pool: 0,
        }
    }

    /// Adds the cell `(x, y)` of size `size`.
    fn add(&mut self, x: f64, y: f64, size: f64, term: &impl Fn(f64, f64) -> f64) {
        if size >= self.min {
            self.statistic += term(x, y);
            self.cells += 1;
            return;
        }
        self.pool = (self.pool.0 + x, self.pool.1 + y, self.pool.2 + size);
        self.in_pool += 1;
        if self.pool.2 >= self.min {
            self.flush(term);
        }
    }

    fn flush(&mut self, term: &impl Fn(f64, f64) -> f64) {
        self.statistic += term(self.pool.0, self.pool.1);
        self.cells += 1;
        self.pooled_cells += self.in_pool - 1;
        (self.pool, self.in_pool) = ((0.0, 0.0, 0.0), 0);
    }

    /// The outcome; `too_few(cells)` says why when fewer than two cells were compared.
    fn finish(
        mut self,
        term: &impl Fn(f64, f64) -> f64,
        too_few: impl FnOnce(u32) -> String,
    ) -> Result<ChiSquareOutcome, String> {
        if self.in_pool > 0 {
            self.flush(term);
        }
        if self.cells < 2 {
            return Err(too_few(self.cells));
        }
        let degrees_of_freedom = self.cells - 1;
        Ok(ChiSquareOutcome {
            statistic: self.statistic,
            degrees_of_freedom,
            p_value: chi_square_p_value(self.statistic, degrees_of_freedom),
            pooled_cells: self.pooled_cells,
        })
    }
}

/// The two-sample χ² test of two histograms over the same cells (Press et al., *Numerical
/// Recipes*, §14.3): whether `a` and `b` are drawn from one distribution, whatever their totals.
/// For a sampler whose density has no closed form, `b` is the answer key's histogram with
/// many more samples. Cells below `min_count` samples of both together are pooled; cells empty
/// in both take no part.
pub fn chi_square_two_sample(
    a: &[u64],
    b: &[u64],
    min_count: u64,
) -> Result<ChiSquareOutcome, String> {
    assert_eq!(a.len(), b.len(), "two histograms over the same cells");
    let (n, m) = (a.iter().sum::<u64>() as f64, b.iter().sum::<u64>() as f64);
    if n == 0.0 || m == 0.0 {
        return Err("a histogram without samples".into());
    }
    let (ka, kb) = ((m / n).sqrt(), (n / m).sqrt());
    let term = |x: f64, y: f64| {
        let d = ka * x - kb * y;
        d * d / (x + y)
    };
    let mut pooled = Pooled::new(min_count as f64);
    for (&x, &y) in a.iter().zip(b) {
        if x + y > 0 {
            pooled.add(x as f64, y as f64, (x + y) as f64, &term);
        }
    }
    pooled.finish(&term, |cells| {
        format!("only {cells} cell(s) with samples: too few for a χ² test")
    })
}

/// A grid over the sphere of directions, equal steps in `cos θ = z` and in `φ = atan2(y, x)`
/// (so every cell has the same solid angle), for χ² tests of direction samplers in a local
/// frame (`z` the normal).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SphereGrid {
    /// Cells in `cos θ ∈ [−1, 1]`; even, so that the equator is a cell boundary.
    pub cos_theta_cells: u32,
    /// Cells in `φ ∈ [0, 2π)`.
    pub phi_cells: u32,
}

impl SphereGrid {
    /// The number of cells.
    pub fn len(&self) -> usize {
        (self.cos_theta_cells * self.phi_cells) as usize
    }

    /// Whether the grid has no cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The cell of the direction `d` (any length but zero), `None` for a non-finite one.
    pub fn cell(&self, d: Vec3) -> Option<usize> {
        let d = d.normalize();
        if !d.is_finite() {
            return None;
        }
        let (n, m) = (self.cos_theta_cells, self.phi_cells);
        let i = ((((d.z as f64 + 1.0) * 0.5) * n as f64) as u32).min(n - 1);
        let phi = (d.y as f64)
            .atan2(d.x as f64)
            .rem_euclid(std::f64::consts::TAU);
        let j = ((phi / std::f64::consts::TAU * m as f64) as u32).min(m - 1);
        Some((i * m + j) as usize)
    }

    /// The counts of `directions` per cell, and how many directions were not finite.
    pub fn histogram(&self, directions: impl IntoIterator<Item = Vec3>) -> (Vec<u64>, usize) {
        let mut counts = vec![0u64; self.len()];
        let mut bad = 0;
        for d in directions {
            match self.cell(d) {
                Some(c) => counts[c] += 1,
                None => bad += 1,
            }
        }
        (counts, bad)
    }

    /// The expected count of each cell for `samples` directions drawn with the density `pdf`
    /// (per steradian): `pdf` integrated over the cell, `dω = d(cos θ) dφ`, by Simpson's rule
    /// on `8 × 8` intervals.
    pub fn expected(&self, pdf: &dyn Fn(Vec3) -> f64, samples: u64) -> Vec<f64> {
        const K: usize = 8;
        let (n, m) = (self.cos_theta_cells, self.phi_cells);
        let (dz, dphi) = (2.0 / n as f64, std::f64::consts::TAU / m as f64);
        let weight = |k: usize| match k {
            0 | K => 1.0,
            k if k % 2 == 1 => 4.0,
            _ => 2.0,
        };
        let mut out = Vec::with_capacity(self.len());
        for i in 0..n {
            for j in 0..m {
                let mut sum = 0.0;
                for a in 0..=K {
                    // Nodes just inside the cell, so that a density with a jump on a cell
                    // boundary (the hemisphere's edge) is integrated from the cell's side.
                    let t = (a as f64 / K as f64).clamp(1e-9, 1.0 - 1e-9);
                    let z = -1.0 + (i as f64 + t) * dz;
                    let s = (1.0 - z * z).max(0.0).sqrt();
                    for b in 0..=K {
                        let phi = (j as f64 + b as f64 / K as f64) * dphi;
                        let d = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, z as f32);
                        sum += weight(a) * weight(b) * pdf(d);
                    }
                }
                let integral = sum * (dz / K as f64 / 3.0) * (dphi / K as f64 / 3.0);
                out.push(integral * samples as f64);
            }
        }
        out
    }

    /// The χ² test of `directions` (in the grid's frame) against the density `pdf`, pooling
    /// cells below an expected count of 5.
    pub fn chi_square(
        &self,
        directions: &[Vec3],
        pdf: &dyn Fn(Vec3) -> f64,
    ) -> Result<ChiSquareOutcome, String> {
        let (counts, bad) = self.histogram(directions.iter().copied());
        if bad > 0 {
            return Err(format!("{bad} of the directions are not finite"));
        }
        chi_square_pooled(&counts, &self.expected(pdf, directions.len() as u64), 5.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pooling_and_zero_density() {
        // Two cells of expected 1 pool into one of 2 (< 5), which joins at the end.
        let o = chi_square_pooled(&[10, 10, 1, 1], &[10.0, 10.0, 1.0, 1.0], 5.0).unwrap();
        assert_eq!(o.degrees_of_freedom, 2);
        assert_eq!(o.pooled_cells, 1);
        assert!(o.statistic.abs() < 1e-12 && (o.p_value - 1.0).abs() < 1e-12);
        assert!(chi_square_pooled(&[3, 1], &[4.0, 0.0], 5.0).is_err());
        assert!(chi_square_pooled(&[3], &[3.0], 5.0).is_err());
    }

    #[test]
    fn two_samples_of_one_distribution_pass_and_of_two_fail() {
        // Proportional histograms of different totals agree exactly.
        let o = chi_square_two_sample(&[100, 200, 300], &[1000, 2000, 3000], 5).unwrap();
        assert!(o.statistic.abs() < 1e-12 && o.degrees_of_freedom == 2);
        // Two draws from one distribution pass; a shifted one fails.
        let mut rng = raylab_core::sampling::Rng::new(3, 4);
        let mut histogram = |shift: f32, n: usize| {
            let mut h = vec![0u64; 10];
            for _ in 0..n {
                let x = (rng.next_f32() + shift * rng.next_f32()) / (1.0 + shift);
                h[((x * 10.0) as usize).min(9)] += 1;
            }
            h
        };
        let (a, b, c) = (
            histogram(0.0, 5_000),
            histogram(0.0, 50_000),
            histogram(0.2, 5_000),
        );
        assert!(chi_square_two_sample(&a, &b, 5).unwrap().p_value > 1e-3);
        assert!(chi_square_two_sample(&c, &b, 5).unwrap().p_value < 1e-6);
    }

    #[test]
    fn uniform_sphere_passes_and_a_biased_one_fails() {
        let grid = SphereGrid {
            cos_theta_cells: 10,
            phi_cells: 20,
        };
        // The integral of the uniform density over the sphere is 1.
        let total: f64 = grid
            .expected(&|_| 1.0 / (4.0 * std::f64::consts::PI), 1)
            .iter()
            .sum();
        assert!((total - 1.0).abs() < 1e-9, "{total}");
        // Directions at the cells' centres, as many in each as the uniform density expects,
        // pass; the same directions crowded into the upper half fail.
        let centre = |i: u32, j: u32| {
            let z = -1.0 + (i as f64 + 0.5) * 2.0 / 10.0;
            let phi = (j as f64 + 0.5) * std::f64::consts::TAU / 20.0;
            let s = (1.0 - z * z).sqrt();
            Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, z as f32)
        };
        let even: Vec<Vec3> = (0..10)
            .flat_map(|i| (0..20).flat_map(move |j| std::iter::repeat_n(centre(i, j), 50)))
            .collect();
        let uniform = |_: Vec3| 1.0 / (4.0 * std::f64::consts::PI);
        let ok = grid.chi_square(&even, &uniform).unwrap();
        assert!(
            ok.statistic < 1e-6 && ok.degrees_of_freedom == 199,
            "{ok:?}"
        );
        let upper: Vec<Vec3> = even
            .iter()
            .map(|d| Vec3::new(d.x, d.y, d.z.abs()))
            .collect();
        let bad = grid.chi_square(&upper, &uniform).unwrap();
        assert!(bad.p_value < 1e-6, "{bad:?}");
        assert!(grid.cell(Vec3::NAN).is_none());
        assert_eq!(grid.cell(Vec3::new(1.0, -1e-9, -1.0)), Some(20 + 19));
    }
}
