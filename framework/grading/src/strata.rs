use glam::Vec2;

/// The cell `(i, j)` of an `n × n` grid over the unit square that `p` lies in (`x·n`, `y·n`
/// rounded down; a coordinate of exactly 1, which rounding of `(i + u)/n` in f32 may give,
/// belongs to the last cell).
pub fn cell_of(p: Vec2, n: u32) -> (u32, u32) {
    let c = |v: f32| ((v as f64 * n as f64).floor().max(0.0) as u32).min(n - 1);
    (c(p.x), c(p.y))
}

/// The cell `(i, j)` of an `n × n` grid as messages name it: `(i = 1, j = 0) = [0.5, 1) × [0, 0.5)`.
pub fn cell_name(i: u32, j: u32, n: u32) -> String {
    let f = |v: u32| v as f32 / n as f32;
    format!(
        "(i = {i}, j = {j}) = [{}, {}) × [{}, {})",
        f(i),
        f(i + 1),
        f(j),
        f(j + 1)
    )
}

/// How a stratified set of points is named in messages.
pub struct StrataNames<'a> {
    /// The call that produced the points, e.g. `stratified_samples(n = 4, rng)`.
    pub call: &'a str,
    /// What one point is called (`sample`, `jitter`).
    pub point: &'a str,
    /// What one cell is called (`cell`, `subpixel`).
    pub cell: &'a str,
    /// Extra explanation for a point outside the unit square.
    pub outside_hint: &'a str,
}

/// Checks that `points` are `n²` points of the unit square with exactly one in each cell of the
/// `n × n` grid (stratified sampling, Exercises 3.2 and 7.1); the message names the call, an
/// empty cell and a crowded one.
pub fn check_one_per_cell(names: &StrataNames<'_>, n: u32, points: &[Vec2]) -> Result<(), String> {
    let StrataNames {
        call,
        point,
        cell,
        outside_hint,
    } = names;
    if points.len() != (n * n) as usize {
        return Err(format!(
            "{call} returned {} {point}s, expected n² = {} (one per {cell}); {point}s: {points:?}",
            points.len(),
            n * n
        ));
    }
    if let Some(p) = points
        .iter()
        .find(|p| !(p.x >= 0.0 && p.x <= 1.0 && p.y >= 0.0 && p.y <= 1.0))
    {
        return Err(format!(
            "{call} returned the {point} {p}, outside the unit square [0, 1)²{outside_hint}; {point}s: {points:?}"
        ));
    }
    let mut count = vec![0u32; (n * n) as usize];
    for p in points {
        let (i, j) = cell_of(*p, n);
        count[(j * n + i) as usize] += 1;
    }
    let name = |k: usize| cell_name(k as u32 % n, k as u32 / n, n);
    if let (Some(empty), Some(full)) = (
        count.iter().position(|&c| c == 0),
        count.iter().position(|&c| c > 1),
    ) {
        return Err(format!(
            "{call} must put exactly one {point} in each of the n² {cell}s [i/n, (i+1)/n) × [j/n, (j+1)/n), but {cell} {} holds none and {cell} {} holds {}; {point}s: {points:?}",
            name(empty),
            name(full),
            count[full]
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const NAMES: StrataNames<'static> = StrataNames {
        call: "f()",
        point: "sample",
        cell: "cell",
        outside_hint: "",
    };

    #[test]
    fn accepts_one_per_cell_and_rejects_the_rest() {
        let good = [
            Vec2::new(0.1, 0.2),
            Vec2::new(0.9, 0.3),
            Vec2::new(0.4, 0.6),
            Vec2::new(0.5, 0.99),
        ];
        assert!(check_one_per_cell(&NAMES, 2, &good).is_ok());
        let crowded = [
            Vec2::new(0.1, 0.2),
            Vec2::new(0.2, 0.1),
            Vec2::new(0.4, 0.6),
            Vec2::new(0.5, 0.99),
        ];
        let e = check_one_per_cell(&NAMES, 2, &crowded).unwrap_err();
        assert!(e.contains("holds none") && e.contains("holds 2"), "{e}");
        assert!(check_one_per_cell(&NAMES, 2, &good[..3]).is_err());
        let outside = [Vec2::new(1.5, 0.2), good[1], good[2], good[3]];
        assert!(
            check_one_per_cell(&NAMES, 2, &outside)
                .unwrap_err()
                .contains("outside")
        );
        assert_eq!(cell_of(Vec2::new(1.0, 0.0), 4), (3, 0));
    }
}
