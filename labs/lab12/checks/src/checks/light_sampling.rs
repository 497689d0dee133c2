//! Exercises 12.4 and 12.5: points sampled on emitting triangles and their densities.

use std::sync::Arc;

use glam::{DVec3, Vec3};
use proptest::prelude::*;

use contracts::lab12::{EmitterSample, PathTracing};
use contracts::sampling::Rng;
use grading::stats::{family_z_limit, mean_and_standard_error};
use grading::strategies::unit_vector;
use grading::{GoldenFile, LabContext, compare_f32, for_all};

use super::{CASES, SIGNIFICANCE, above, key, load};

/// Golden file of Exercise 12.5.
pub const GOLDEN_EMITTER_PDF: &str = "emitter_pdf.json";

/// Points drawn per case of the emitter checks.
const EMITTER_SAMPLES: usize = 4_000;

/// A triangle, a point in front of it, at a scale of `grading::strategies::scale()` and
/// moved away from the origin.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EmitterCase {
    /// The emitting triangle.
    pub triangle: [Vec3; 3],
    /// The shaded point.
    pub position: Vec3,
}

/// Cases of the emitter checks: random triangles seen from random points in front, near (a
/// fifth of their size) and far (fifty times), head-on and at a grazing angle.
pub fn emitter_case() -> impl Strategy<Value = EmitterCase> + Clone {
    (
        grading::strategies::triangle_strategy(),
        unit_vector(),
        prop::sample::select(vec![0.2f32, 1.0, 5.0, 50.0]),
        grading::strategies::scale(),
        grading::strategies::point(1.0),
    )
        .prop_map(|([a, b, c], d, distance, scale, offset)| {
            let normal = (b - a).cross(c - a).normalize();
            let centre = (a + b + c) / 3.0;
            let d = above(normal, d, 0.05);
            let place = |p: Vec3| (p * scale) + offset * (scale * 20.0);
            EmitterCase {
                triangle: [place(a), place(b), place(c)],
                position: place(centre + d * distance * 2.0),
            }
        })
}

/// The solid angle of the triangle `[a, b, c]` seen from `p` (Van Oosterom and Strackee 1983).
pub fn solid_angle(p: DVec3, [a, b, c]: [DVec3; 3]) -> f64 {
    let (a, b, c) = (a - p, b - p, c - p);
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let numerator = a.dot(b.cross(c)).abs();
    let denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * numerator.atan2(denominator)
}

/// The four triangles the edge midpoints cut `t` into.
fn quarters([a, b, c]: [DVec3; 3]) -> [[DVec3; 3]; 4] {
    let (ab, bc, ca) = ((a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0);
    [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
}

/// Which of [`quarters`] the point with barycentric coordinates `(β, γ)` (of `b` and `c`) is in.
fn quarter(beta: f64, gamma: f64) -> usize {
    let alpha = 1.0 - beta - gamma;
    if alpha >= 0.5 {
        0
    } else if beta >= 0.5 {
        1
    } else if gamma >= 0.5 {
        2
    } else {
        3
    }
}

/// The barycentric coordinates `(β, γ)` of `p` in `[a, b, c]`, and its distance from the plane.
fn barycentric(p: DVec3, [a, b, c]: [DVec3; 3]) -> (f64, f64, f64) {
    let (e1, e2, d) = (b - a, c - a, p - a);
    let n = e1.cross(e2);
    let nn = n.length_squared();
    let beta = d.cross(e2).dot(n) / nn;
    let gamma = e1.cross(d).dot(n) / nn;
    (beta, gamma, d.dot(n) / nn.sqrt())
}

/// Draws `EMITTER_SAMPLES` points of `case` from `s`, checking each lies on the triangle with
/// the radiance given; then `E[1/pdf]` over each quarter of the triangle must be its solid
/// angle (Z-tests at `z_limit`).
fn check_emitter_case(
    s: &dyn PathTracing,
    case: &EmitterCase,
    seed: u64,
    z_limit: f64,
    key: Option<&dyn PathTracing>,
) -> Result<(), String> {
    let radiance = Vec3::new(3.0, 2.0, 0.5);
    let call = format!(
        "sample_emitter(triangle = {:?}, radiance = {radiance}, position = {})",
        case.triangle, case.position
    );
    let t = case.triangle.map(Vec3::as_dvec3);
    let p = case.position.as_dvec3();
    let size = (t[1] - t[0]).length().max((t[2] - t[0]).length());
    let mut rng = Rng::new(seed, 12);
    let mut per_quarter: [Vec<f64>; 4] = Default::default();
    let mut points = Vec::new();
    for _ in 0..EMITTER_SAMPLES {
        let Some(sample) = s.sample_emitter(case.triangle, radiance, case.position, &mut rng)
        else {
            return Err(format!(
                "{call} returned `None`, but the point sees the emitting side of the triangle"
            ));
        };
        let EmitterSample {
            direction,
            distance,
            radiance: got,
            pdf,
            delta,
        } = sample;
        if delta {
            return Err(format!(
                "{call} returned a sample with `delta: true`: a triangle is an area light, which a direction drawn from a BSDF can hit too"
            ));
        }
        let unit = (direction.length() - 1.0).abs() <= 1e-4;
        if !unit {
            return Err(format!(
                "{call} returned the direction {direction} of length {}: return a unit vector",
                direction.length()
            ));
        }
        if got != radiance {
            return Err(format!(
                "{call} returned the radiance {got}: return the emitter's radiance as it is"
            ));
        }
        if !(pdf > 0.0 && pdf.is_finite()) {
            return Err(format!(
                "{call} returned the density {pdf}: a point drawn has a positive, finite density"
            ));
        }
        let point = p + direction.as_dvec3() * f64::from(distance);
        let (beta, gamma, off) = barycentric(point, t);
        let tol = 2e-3;
        if off.abs() > 1e-3 * size || beta < -tol || gamma < -tol || beta + gamma > 1.0 + tol {
            return Err(format!(
                "{call}: position + distance·direction = {} is not on the triangle (barycentric β = {beta:.4}, γ = {gamma:.4}, {off:.3e} off its plane): return the direction to the point drawn and its distance",
                point.as_vec3()
            ));
        }
        per_quarter[quarter(beta, gamma)].push(1.0 / f64::from(pdf));
        if points.len() < 200 {
            points.push((direction, distance, pdf));
        }
    }
    for (q, sub) in quarters(t).into_iter().enumerate() {
        let omega = solid_angle(p, sub);
        let (mean, error) = mean_and_standard_error(&per_quarter[q], EMITTER_SAMPLES);
        let z = (mean - omega) / error.max(omega * 1e-9);
        if z.abs() > z_limit {
            let total = solid_angle(p, t);
            let (all, _) = mean_and_standard_error(
                &per_quarter.iter().flatten().copied().collect::<Vec<_>>(),
                EMITTER_SAMPLES,
            );
            return Err(format!(
                "{call}: the mean of 1/pdf over the points drawn in one quarter of the triangle is {mean:.4e} ± {error:.2e}, not its solid angle {omega:.4e} (z = {z:.1}); over the whole triangle {all:.4e}, its solid angle {total:.4e}. Points are uniform over the area (density 1/A) and pdf = d²/(A cos θ_l) per unit solid angle"
            ));
        }
    }
    if let Some(key) = key {
        for (direction, distance, pdf) in points {
            let expected = key.emitter_pdf(case.triangle, case.position, direction, distance);
            compare_f32(
                &format!("the density {call} returned with the direction {direction}"),
                pdf,
                expected,
                0.0,
                2e-3,
            )?;
        }
    }
    Ok(())
}

/// Exercise 12.4: on random triangles at every scale, near and far, head-on and grazing: points
/// on the triangle, the radiance as given, `E[1/pdf]` the solid angle of each quarter of the
/// triangle; `None` from behind and for a triangle without area; the generator advances.
pub(super) fn exercise_12_4(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
    let cases = grading::strategies::samples(emitter_case(), 24, 41);
    let z_limit = family_z_limit(SIGNIFICANCE, cases.len() * 4);
    let key = key(ctx);
    for (k, case) in cases.iter().enumerate() {
        check_emitter_case(s.as_ref(), case, 400 + k as u64, z_limit, key.as_deref())?;
        // From behind: the point mirrored through the triangle's plane.
        let [a, b, c] = case.triangle;
        let n = (b - a).cross(c - a).normalize();
        let behind = case.position - 2.0 * n * n.dot(case.position - a);
        let mut rng = Rng::new(7, k as u64);
        for _ in 0..8 {
            if let Some(got) = s.sample_emitter(case.triangle, Vec3::ONE, behind, &mut rng) {
                return Err(format!(
                    "sample_emitter(triangle = {:?}, position = {behind}) returned {got:?}, but the point is behind the triangle, which emits on the side of (v1 − v0) × (v2 − v0): return `None`",
                    case.triangle
                ));
            }
        }
    }
    // The generator advances.
    let case = &cases[0];
    let mut rng = Rng::new(5, 5);
    let first = s.sample_emitter(case.triangle, Vec3::ONE, case.position, &mut rng);
    let second = s.sample_emitter(case.triangle, Vec3::ONE, case.position, &mut rng);
    if first == second {
        return Err(format!(
            "sample_emitter(triangle = {:?}, position = {}) returned {first:?} twice in a row: draw new numbers from `rng` every call",
            case.triangle, case.position
        ));
    }
    // A triangle without area.
    let line = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
    let mut rng = Rng::new(6, 6);
    let got = s.sample_emitter(line, Vec3::ONE, Vec3::new(0.5, 1.0, 0.0), &mut rng);
    if got.is_some() {
        return Err(format!(
            "sample_emitter(triangle = {line:?}, …) returned {got:?} for a triangle without area: return `None`"
        ));
    }
    Ok(())
}

/// Exercise 12.5: points drawn uniformly on random triangles (by the check) have
/// `E[1/emitter_pdf]` equal to the solid angle of each quarter; 0 from behind and for a
/// triangle without area; the key's values (where present) and the golden cases'.
pub(super) fn exercise_12_5(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
    let cases = grading::strategies::samples(emitter_case(), 24, 51);
    let z_limit = family_z_limit(SIGNIFICANCE, cases.len() * 4);
    for (k, case) in cases.iter().enumerate() {
        let t = case.triangle.map(Vec3::as_dvec3);
        let p = case.position.as_dvec3();
        let mut rng = Rng::new(500 + k as u64, 12);
        let mut per_quarter: [Vec<f64>; 4] = Default::default();
        for _ in 0..EMITTER_SAMPLES {
            let (u, v) = (f64::from(rng.next_f32()), f64::from(rng.next_f32()));
            let r = u.sqrt();
            let (beta, gamma) = (r * (1.0 - v), r * v);
            let point = t[0] * (1.0 - beta - gamma) + t[1] * beta + t[2] * gamma;
            let to = point - p;
            let distance = to.length();
            let direction = (to / distance).as_vec3();
            let pdf = s.emitter_pdf(case.triangle, case.position, direction, distance as f32);
            if !(pdf > 0.0 && pdf.is_finite()) {
                return Err(format!(
                    "emitter_pdf(triangle = {:?}, position = {}, direction = {direction}, distance = {distance}) is {pdf}, for a point on the emitting side of the triangle",
                    case.triangle, case.position
                ));
            }
            per_quarter[quarter(beta, gamma)].push(1.0 / f64::from(pdf));
        }
        for (q, sub) in quarters(t).into_iter().enumerate() {
            let omega = solid_angle(p, sub);
            let (mean, error) = mean_and_standard_error(&per_quarter[q], EMITTER_SAMPLES);
            let z = (mean - omega) / error.max(omega * 1e-9);
            if z.abs() > z_limit {
                return Err(format!(
                    "emitter_pdf(triangle = {:?}, position = {}, …): over points drawn uniformly on one quarter of the triangle, the mean of 1/pdf is {mean:.4e} ± {error:.2e}, not the quarter's solid angle {omega:.4e} (z = {z:.1}): pdf = d²/(A cos θ_l), with A the triangle's area and θ_l at the emitter",
                    case.triangle, case.position
                ));
            }
        }
        let [a, b, c] = case.triangle;
        let n = (b - a).cross(c - a).normalize();
        let behind = case.position - 2.0 * n * n.dot(case.position - a);
        let centre = (a + b + c) / 3.0;
        let to = centre - behind;
        let pdf = s.emitter_pdf(case.triangle, behind, to.normalize(), to.length());
        if pdf != 0.0 {
            return Err(format!(
                "emitter_pdf(triangle = {:?}, position = {behind}, …) is {pdf} from behind the triangle, which emits on the side of (v1 − v0) × (v2 − v0) only: return 0",
                case.triangle
            ));
        }
    }
    let line = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
    let pdf = s.emitter_pdf(line, Vec3::new(0.5, 1.0, 0.0), -Vec3::Y, 1.0);
    if pdf != 0.0 {
        return Err(format!(
            "emitter_pdf(triangle = {line:?}, …) is {pdf} for a triangle without area: return 0"
        ));
    }
    let call = |c: &(EmitterCase, Vec3, f32)| {
        format!(
            "emitter_pdf(triangle = {:?}, position = {}, direction = {}, distance = {})",
            c.0.triangle, c.0.position, c.1, c.2
        )
    };
    if let Some(key) = key(ctx) {
        for_all(CASES, emitter_pdf_input(), |c| {
            compare_f32(
                &call(&c),
                s.emitter_pdf(c.0.triangle, c.0.position, c.1, c.2),
                key.emitter_pdf(c.0.triangle, c.0.position, c.1, c.2),
                0.0,
                2e-3,
            )
        })?;
    }
    let golden: GoldenFile<(EmitterCase, Vec3, f32), f32> = load(ctx, GOLDEN_EMITTER_PDF)?;
    for case in &golden.cases {
        let c = &case.input;
        compare_f32(
            &call(c),
            s.emitter_pdf(c.0.triangle, c.0.position, c.1, c.2),
            case.expected,
            0.0,
            2e-3,
        )?;
    }
    Ok(())
}

/// Inputs of Exercise 12.5: a case and the direction and distance to a point of its triangle.
pub fn emitter_pdf_input() -> impl Strategy<Value = (EmitterCase, Vec3, f32)> + Clone {
    (emitter_case(), 0.0f32..1.0, 0.0f32..1.0).prop_map(|(case, u, v)| {
        let [a, b, c] = case.triangle;
        let r = u.sqrt();
        let point = a * (1.0 - r) + b * (r * (1.0 - v)) + c * (r * v);
        let to = point - case.position;
        (case, to.normalize(), to.length())
    })
}
