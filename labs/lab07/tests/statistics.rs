//! Each statistic of lab 07's checks accepts the reference's jitters and rejects the mistake it
//! is there for. These tests need correct jitters and averages, so they run on the answer key,
//! in the instructors' tests of the lab (a handout ships only `tests/checks.rs`).

use contracts::lab07::Antialiasing;
use grading::for_all;
use lab07_checks::checks::{
    STATISTICS_SUBDIVISIONS, STREAMS, check_edge, check_generator_moves_on, check_independence,
    check_mean_jitter, check_pooled_uniformity, check_subpixels, edge_input, z_limit,
};
use raylab_core::glam::{UVec2, Vec2, Vec3};
use raylab_core::sampling::Rng;
use reference::lab07::Lab07;

/// The jitters of [`STREAMS`] pixels at subdivision `s`, one generator each: `jitters(s, rng)`
/// per pixel.
fn pixels_of(s: u32, jitters: impl Fn(u32, &mut Rng) -> Vec<Vec2>) -> Vec<Vec<Vec2>> {
    (0..STREAMS)
        .map(|k| jitters(s, &mut Rng::for_sample(5, k, s, 0)))
        .collect()
}

/// The corner of subpixel `(i, j)` in subpixel units.
fn cell(i: u32, j: u32) -> Vec2 {
    Vec2::new(i as f32, j as f32)
}

/// Jitters with the offset inside each subpixel drawn by `offset`, row by row.
fn per_subpixel(s: u32, rng: &mut Rng, offset: impl Fn(&mut Rng) -> Vec2) -> Vec<Vec2> {
    (0..s * s)
        .map(|q| (cell(q % s, q / s) + offset(rng)) / s as f32)
        .collect()
}

#[test]
fn statistics_accept_the_reference() {
    let z = z_limit();
    for s in STATISTICS_SUBDIVISIONS {
        let pixels = pixels_of(s, |s, rng| Lab07.compute_jitters(s, rng));
        check_mean_jitter(s, &pixels, z).unwrap();
        check_subpixels(s, &pixels, z).unwrap();
        check_pooled_uniformity(s, &pixels, z).unwrap();
        check_independence(s, &pixels, z).unwrap();
    }
    assert!(
        (z - 5.07).abs() < 0.005,
        "the checks document |z| ≤ 5.07, not {z:.3}"
    );
}

#[test]
fn generator_check_accepts_a_moved_generator_and_rejects_a_copy() {
    let z = z_limit();
    for s in STATISTICS_SUBDIVISIONS {
        let (mut moved, mut next_moved) = (Vec::new(), Vec::new());
        let (mut copied, mut next_copied) = (Vec::new(), Vec::new());
        for k in 0..STREAMS {
            let mut rng = Rng::for_sample(5, k, s, 0);
            copied.push(Lab07.compute_jitters(s, &mut rng.clone()));
            next_copied.push(rng.clone().next_vec2());
            moved.push(Lab07.compute_jitters(s, &mut rng));
            next_moved.push(rng.next_vec2());
        }
        check_generator_moves_on(s, &moved, &next_moved, z).unwrap();
        assert!(check_generator_moves_on(s, &copied, &next_copied, z).is_err());
    }
}

#[test]
fn each_statistic_rejects_its_mistake() {
    let z = z_limit();
    // Offsets ξ² inside each subpixel: stratified, but pulled towards the corner.
    let squared = pixels_of(3, |s, rng| {
        per_subpixel(s, rng, |rng| {
            let u = rng.next_vec2();
            u * u
        })
    });
    assert!(check_mean_jitter(3, &squared, z).is_err());
    assert!(check_subpixels(3, &squared, z).is_err());
    // Subpixel centres.
    let centres = pixels_of(2, |s, rng| per_subpixel(s, rng, |_| Vec2::splat(0.5)));
    assert!(check_subpixels(2, &centres, z).is_err());
    // One number for both coordinates.
    let diagonal = pixels_of(2, |s, rng| {
        per_subpixel(s, rng, |rng| Vec2::splat(rng.next_f32()))
    });
    assert!(check_pooled_uniformity(2, &diagonal, z).is_err());
    // One offset for every subpixel of a pixel: uniform per subpixel, but not independent.
    let shared = pixels_of(2, |s, rng| {
        per_subpixel(s, rng, |rng| rng.clone().next_vec2())
    });
    check_subpixels(2, &shared, z).unwrap();
    check_pooled_uniformity(2, &shared, z).unwrap();
    assert!(check_independence(2, &shared, z).is_err());
}

/// The reference's jitters, combined by `combine` (the sum, say, for a mistake).
struct Combined(fn(&[Vec3]) -> Vec3);

impl Antialiasing for Combined {
    fn compute_jitters(&self, s: u32, rng: &mut Rng) -> Vec<Vec2> {
        Lab07.compute_jitters(s, rng)
    }
    fn compute_pixel(
        &self,
        pixel: UVec2,
        jitters: &[Vec2],
        radiance: &mut dyn FnMut(Vec2) -> Vec3,
    ) -> Vec3 {
        let values: Vec<Vec3> = jitters
            .iter()
            .map(|&j| radiance(pixel.as_vec2() + j))
            .collect();
        (self.0)(&values)
    }
}

#[test]
fn edge_check_accepts_the_reference_and_rejects_other_combinations() {
    for_all(100, edge_input(), |edge| check_edge(&Lab07, &Lab07, edge)).unwrap();
    let sum = Combined(|v| v.iter().sum());
    let first = Combined(|v| v[0]);
    let per_s = Combined(|v| v.iter().sum::<Vec3>() / (v.len() as f32).sqrt());
    for wrong in [&sum, &first, &per_s] {
        assert!(for_all(100, edge_input(), |edge| check_edge(wrong, &Lab07, edge)).is_err());
    }
}
