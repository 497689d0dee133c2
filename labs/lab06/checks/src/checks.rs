//! Lab 06's exercises and their checks (docs/lab06.md, "What the checks check").
//!
//! Every check of exercise 6.N uses the student's function for 6.N and the base's (the answer
//! key, or in a handout the student's own code for the rest) for everything else, through
//! [`PartSlot`]. With the key present the student's function is also compared with the key's
//! on random inputs; without it the checks judge by golden cases, relations and the
//! literature's closed forms alone:
//!
//! - 6.1 (`point_form_factor`): reciprocity `A_x F_xy = A_y F_yx`, invariance under scaling
//!   the configuration (lengths from 10⁻⁴ to 10³), zero for a patch facing away, linearity in
//!   the area, and agreement with Howell's differential element to a coaxial disc far away.
//! - 6.2 / 6.3 (`delta_form_factor_top` / `_side`): the delta form factors of a whole hemicube
//!   sum to 1 within [`sum_bound`] (shrinking as `1/n²`) at resolutions 8 to 256; the two faces
//!   meet continuously at their common edge; symmetry; and the hemicube form factor from an
//!   element to a parallel and to a perpendicular square matches Howell's B-3 and B-2 within
//!   [`element_bound`] (shrinking as `1/n`) at resolutions 16, 32, 64.
//! - 6.4 (`accumulate_form_factors`): on random item buffers, the total is the sum of the
//!   weights of the pixels that see a patch, unseen patches get 0, renaming the patches renames
//!   the result; on real ones, a closed box's form factors sum to the hemicube's total, and
//!   the form factors between parallel and between perpendicular unit squares (7 × 7 patches
//!   each) are reciprocal and match Howell's C-11 and C-14 within [`area_bound`].
//! - 6.5 (`select_shooter`): the patch chosen has the most unshot power (radiosity times area)
//!   over areas from 10⁻⁸ to 10⁶, and `None` when nothing is left to shoot.
//! - 6.6 (`shoot`): on a shot whose factors all differ, relations that name each usual mistake
//!   ([`diagnose_shoot`]): what a receiver gets halves with its area, doubles with the
//!   shooter's, ignores the shooter's radiosity `B_i` and reflectance; then on random shots
//!   the shooter's unshot radiosity is zeroed and nothing else of it changes;
//!   radiosity and unshot radiosity grow by the same amount; the power received is the power
//!   shot times `ρ` where the form factors sum to 1 (energy conservation); in a closed box with
//!   `ρ < 1` the solution's total power stays below the geometric-series bound
//!   `P_E / (1 − ρ)` and converges to it, at scales from 10⁻³ to 10³; and the Cornell box solved
//!   with it matches the reference's snapshot.
//! - 6.7 (`patch_colours`), 6.8 (`vertex_colours`): linearity, bounds (a vertex's colour lies
//!   between its patches' colours), blindness to the patches' areas (from 10⁻³ to 10³: the
//!   mean counts each patch once), golden cases, and the Cornell box's flat and smooth images.

use std::sync::Arc;

use glam::Vec3;
use proptest::prelude::*;

use super::closed_forms;
use contracts::lab06::Radiosity;
use grading::strategies::{SCALES, point, scale, unit_vector};
use grading::{Exercise, GoldenFile, LabContext, PixelTolerance, for_all};
use pipeline::radiosity::solver::{FormFactors, Shading, SolveSettings, render_solution, solve};
use pipeline::radiosity::{
    DeltaFormFactors, HemicubeFace, ItemBuffer, MeshingOptions, Patch, PatchMesh,
};
use pipeline::{PartSlot, Pipeline};
use raylab_core::film::Film;
use raylab_core::scene::builtin_scene;

/// Golden file of Exercise 6.1.
pub const GOLDEN_POINT: &str = "point_form_factor.json";
/// Golden file of Exercise 6.2.
pub const GOLDEN_TOP: &str = "delta_form_factor_top.json";
/// Golden file of Exercise 6.3.
pub const GOLDEN_SIDE: &str = "delta_form_factor_side.json";
/// Golden file of Exercise 6.4.
pub const GOLDEN_ACCUMULATE: &str = "accumulate_form_factors.json";
/// Golden file of Exercise 6.5.
pub const GOLDEN_SHOOTER: &str = "select_shooter.json";
/// Golden file of Exercise 6.6.
pub const GOLDEN_SHOOT: &str = "shoot.json";
/// Golden file of Exercise 6.7.
pub const GOLDEN_COLOURS: &str = "patch_colours.json";
/// Golden file of Exercise 6.8.
pub const GOLDEN_VERTICES: &str = "vertex_colours.json";
/// Snapshot of the Cornell box's solution in flat patches (Exercises 6.6 and 6.7).
pub const SNAPSHOT_FLAT: &str = "cornell-flat";
/// Snapshot of the Cornell box's solution smoothed by nodal averaging (Exercise 6.8).
pub const SNAPSHOT_SMOOTH: &str = "cornell-smooth";
/// Size of the snapshots.
pub const SNAPSHOT_SIZE: (u32, u32) = (128, 128);
/// Meshing of the snapshots' Cornell box (coarse, so the checks stay fast).
pub const SNAPSHOT_MESHING: MeshingOptions = MeshingOptions {
    max_size: 0.1,
    max_light_size: 0.05,
};
/// Solver of the snapshots: a 16 × 16 hemicube, down to 0.1 % unshot power.
pub const SNAPSHOT_SOLVE: SolveSettings = SolveSettings {
    form_factors: FormFactors::Hemicube(16),
    threshold: 1e-3,
    max_shots: 20_000,
};
/// Resolutions at which the delta form factors must sum to 1.
pub const SUM_RESOLUTIONS: [u32; 6] = [8, 16, 32, 64, 128, 256];
/// Resolutions of the closed-form comparisons.
pub const CLOSED_FORM_RESOLUTIONS: [u32; 3] = [16, 32, 64];

/// How far from 1 the delta form factors of a hemicube at resolution `n` may sum: the midpoint
/// rule's error falls as `1/n²` (the textbook formulas' is `0.54/n²`).
pub fn sum_bound(n: u32) -> f64 {
    1.1 / (n as f64 * n as f64)
}

/// How far a hemicube form factor from an element to a square may be from the closed form at
/// resolution `n`: the pixels along the square's outline are in or out whole, so the error
/// falls as `1/n`.
pub fn element_bound(n: u32) -> f64 {
    0.25 / n as f64
}

/// How far the area-to-area form factor of two unit squares (each cut into 7 × 7 patches,
/// one hemicube per patch) may be from the closed form at resolution `n`: the hemicube's
/// `1/n` and the patches' point sampling of the emitter.
pub fn area_bound(n: u32) -> f64 {
    0.2 / n as f64 + 2e-3
}

/// This lab.
pub const LAB: course::LabId = course::LabId::of(6);

/// The exercises of lab 06 (`labs/lab06/exercises.toml`), each with its check.
pub fn exercises() -> Vec<Exercise<dyn Radiosity>> {
    grading::exercises(
        LAB,
        grading::checks![
            exercise_6_1,
            exercise_6_2,
            exercise_6_3,
            exercise_6_4,
            exercise_6_5,
            exercise_6_6,
            exercise_6_7,
            exercise_6_8
        ],
    )
}

// ---------------------------------------------------------------------------------------------
// Parts and the configurations the checks solve

/// Which student function a check exercises; the others come from the base.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// Exercise 6.1.
    PointFormFactor,
    /// Exercise 6.2.
    Top,
    /// Exercise 6.3.
    Side,
    /// Exercise 6.4.
    Accumulate,
    /// Exercise 6.5.
    Shooter,
    /// Exercise 6.6.
    Shoot,
    /// Exercise 6.7.
    Colours,
    /// Exercise 6.8.
    Vertices,
}

impl Part {
    /// The contract method whose code this part is (the student's in a [`PartSlot`]).
    pub fn function(self) -> &'static str {
        match self {
            Part::PointFormFactor => "point_form_factor",
            Part::Top => "delta_form_factor_top",
            Part::Side => "delta_form_factor_side",
            Part::Accumulate => "accumulate_form_factors",
            Part::Shooter => "select_shooter",
            Part::Shoot => "shoot",
            Part::Colours => "patch_colours",
            Part::Vertices => "vertex_colours",
        }
    }
}

/// The student's code for `part`, the base's for the rest.
pub fn part_slot(part: Part, student: &Arc<dyn Radiosity>, base: &Pipeline) -> Arc<dyn Radiosity> {
    PartSlot::shared(part.function(), student, &base.code::<dyn Radiosity>())
}

/// A planar quad patch with corners `c` (counter-clockwise about `normal`), as a patch list
/// entry with vertex ids `first..first + 4`.
pub fn quad_patch(c: [Vec3; 4], first: u32, reflectance: Vec3, emission: Vec3) -> Patch {
    let normal = (c[1] - c[0]).cross(c[3] - c[0]).normalize();
    Patch {
        vertices: (first..first + 4).collect(),
        centre: 0.25 * (c[0] + c[1] + c[2] + c[3]),
        normal,
        area: 0.5 * (c[2] - c[0]).cross(c[3] - c[1]).length(),
        reflectance,
        emission,
    }
}

/// A rectangle `origin + [0, 1]·a + [0, 1]·b` cut into `k × k` quad patches (normal `a × b`).
pub fn grid(origin: Vec3, a: Vec3, b: Vec3, k: u32, reflectance: Vec3) -> (Vec<Vec3>, Vec<Patch>) {
    let (mut vertices, mut patches) = (Vec::new(), Vec::new());
    let at = |i: u32, j: u32| origin + a * (i as f32 / k as f32) + b * (j as f32 / k as f32);
    for j in 0..k {
        for i in 0..k {
            let c = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
            patches.push(quad_patch(
                c,
                vertices.len() as u32,
                reflectance,
                Vec3::ZERO,
            ));
            vertices.extend(c);
        }
    }
    (vertices, patches)
}

/// Joins patch lists into one mesh; returns it with the index of each list's first patch.
pub fn join(parts: Vec<(Vec<Vec3>, Vec<Patch>)>) -> (PatchMesh, Vec<usize>) {
    let (mut vertices, mut patches, mut starts) = (Vec::new(), Vec::new(), Vec::new());
    for (v, p) in parts {
        starts.push(patches.len());
        let offset = vertices.len() as u32;
        vertices.extend(v);
        patches.extend(p.into_iter().map(|mut p| {
            p.vertices.iter_mut().for_each(|i| *i += offset);
            p
        }));
    }
    (PatchMesh::from_patches(vertices, patches), starts)
}

/// A closed box of side `size`, each face cut into `k × k` patches of reflectance `rho`
/// facing inwards; the first patch of the floor emits `E = 1` (white).
pub fn closed_box(size: f32, k: u32, rho: f32) -> PatchMesh {
    let s = size;
    let (x, y, z) = (Vec3::X * s, Vec3::Y * s, Vec3::Z * s);
    let r = Vec3::splat(rho);
    let faces = vec![
        grid(Vec3::ZERO, z, x, k, r), // floor, normal +y
        grid(y, x, z, k, r),          // ceiling, normal −y
        grid(Vec3::ZERO, x, y, k, r), // back, normal +z
        grid(z, y, x, k, r),          // front, normal −z
        grid(Vec3::ZERO, y, z, k, r), // left, normal +x
        grid(x, z, y, k, r),          // right, normal −x
    ];
    let (mut mesh, _) = join(faces);
    mesh.patches[0].emission = Vec3::ONE;
    mesh
}

/// The Cornell box of the snapshots, meshed.
pub fn snapshot_mesh() -> Result<(raylab_core::scene::Scene, PatchMesh), raylab_core::Error> {
    let scene = builtin_scene("cornell")?;
    let mesh = PatchMesh::from_scene(&scene, SNAPSHOT_MESHING);
    Ok((scene, mesh))
}

/// The snapshot of the Cornell box solved, coloured and drawn by `r`: flat patches, or
/// smoothed by nodal averaging.
pub fn cornell_image(
    r: &dyn Radiosity,
    pipeline: &Pipeline,
    smooth: bool,
) -> Result<Film, raylab_core::Error> {
    let (scene, mesh) = snapshot_mesh()?;
    let solution = solve(r, &mesh, &SNAPSHOT_SOLVE);
    let colours = r.patch_colours(&solution.radiosity);
    let (w, h) = SNAPSHOT_SIZE;
    Ok(if smooth {
        let vertex = r.vertex_colours(&mesh.patches, mesh.vertices.len(), &colours);
        render_solution(pipeline, &scene, &mesh, Shading::Smooth(&vertex), w, h)
    } else {
        render_solution(pipeline, &scene, &mesh, Shading::Flat(&colours), w, h)
    })
}

/// Tolerance of the Cornell snapshots: the solution stops at 0.1 % unshot power, so two
/// correct codes that shoot in a different order (ties) differ by about that much.
pub const SNAPSHOT_TOLERANCE: PixelTolerance = PixelTolerance {
    abs: 2e-3,
    rel: 1e-2,
    max_outlier_fraction: 0.002,
};

fn check_image(
    r: &dyn Radiosity,
    ctx: &LabContext,
    smooth: bool,
    name: &str,
) -> Result<(), String> {
    let film = cornell_image(r, &ctx.base, smooth).map_err(|e| e.to_string())?;
    ctx.check_snapshot(name, &film, &SNAPSHOT_TOLERANCE)
}

fn close(got: f64, expected: f64, abs: f64, rel: f64) -> bool {
    (got - expected).abs() <= abs + rel * expected.abs()
}

fn load<I, O>(ctx: &LabContext, name: &str) -> Result<GoldenFile<I, O>, String>
where
    I: serde::Serialize + serde::de::DeserializeOwned,
    O: serde::Serialize + serde::de::DeserializeOwned,
{
    ctx.golden(name)
}

fn vec3_close(a: Vec3, b: Vec3, abs: f32, rel: f32) -> bool {
    ((a - b).abs().cmple(Vec3::splat(abs) + rel * b.abs())).all()
}

// ---------------------------------------------------------------------------------------------
// Exercise 6.1

/// Input of `point_form_factor`: `x, n_x, y, n_y, area_y`.
pub type PointInput = (Vec3, Vec3, Vec3, Vec3, f32);

/// Two points at least a tenth of the scale apart, unit normals, and an area, at one of the
/// shared scales.
pub fn point_input() -> impl Strategy<Value = PointInput> {
    (
        point(1.0),
        unit_vector(),
        point(1.0),
        unit_vector(),
        0.001f32..0.1,
        scale(),
    )
        .prop_filter("points apart", |(x, _, y, _, _, _)| x.distance(*y) > 0.1)
        .prop_map(|(x, nx, y, ny, a, s)| (x * s, nx, y * s, ny, a * s * s))
}

fn point_call((x, nx, y, ny, a): PointInput) -> String {
    format!("point_form_factor(x = {x}, n_x = {nx}, y = {y}, n_y = {ny}, area_y = {a:e})")
}

fn check_point(
    r: &dyn Radiosity,
    key: Option<&dyn Radiosity>,
    input: PointInput,
) -> Result<(), String> {
    let (x, nx, y, ny, a) = input;
    let call = point_call(input);
    let f = r.point_form_factor(x, nx, y, ny, a);
    if !f.is_finite() || f < 0.0 {
        return Err(format!(
            "{call} = {f}: a form factor is a fraction, finite and at least 0"
        ));
    }
    // Reciprocity with an area for x of its own.
    let ax = a * 0.37;
    let back = r.point_form_factor(y, ny, x, nx, ax);
    if !close((ax * f) as f64, (a * back) as f64, 1e-30, 1e-3) {
        return Err(format!(
            "{call} = {f:e} but from y back to x (area {ax:e}) it is {back:e}: reciprocity A_x F_xy = A_y F_yx fails ({:e} ≠ {:e}); both cosines and 1/(π r²) are the same both ways, only the area differs",
            ax * f,
            a * back
        ));
    }
    let twice = r.point_form_factor(x, nx, y, ny, 2.0 * a);
    if !close(twice as f64, 2.0 * f as f64, 1e-30, 1e-4) {
        return Err(format!(
            "{call} = {f:e}, but with twice the area it is {twice:e}: the form factor of a small patch is proportional to its area"
        ));
    }
    for s in SCALES {
        let scaled = r.point_form_factor(x * s, nx, y * s, ny, a * s * s);
        if !close(scaled as f64, f as f64, 1e-30, 1e-3) {
            return Err(format!(
                "{call} = {f:e}, but with every length scaled by {s:e} (and the area by {:e}) it is {scaled:e}: a form factor has no units, it must not change when the whole configuration is scaled",
                s * s
            ));
        }
    }
    let d = y - x;
    let away_y = ny - 2.0 * ny.dot(d.normalize()).min(0.0) * d.normalize();
    let g = r.point_form_factor(x, nx, y, away_y, a);
    if ny.dot(d) < 0.0 && away_y.dot(d) > 0.0 && g != 0.0 {
        return Err(format!(
            "{} = {g:e}: the patch at y faces away from x, so no light from x reaches its front; clamp cos φ_y at 0",
            point_call((x, nx, y, away_y, a))
        ));
    }
    if let Some(key) = key {
        let expected = key.point_form_factor(x, nx, y, ny, a);
        if !close(f as f64, expected as f64, 1e-30, 1e-4) {
            return Err(format!("{call} = {f:e}, expected {expected:e}"));
        }
    }
    Ok(())
}

/// Far from a coaxial disc of radius `R` at height `h` the point formula approaches Howell's
/// differential element to a parallel coaxial disc, `R² / (h² + R²)`, within `(R/h)²`.
fn check_far_disc(r: &dyn Radiosity) -> Result<(), String> {
    for (radius, h) in [(0.01f64, 1.0f64), (0.1, 2.0), (1e-3, 0.05), (50.0, 1e3)] {
        let exact = radius * radius / (h * h + radius * radius);
        let area = (std::f64::consts::PI * radius * radius) as f32;
        let got =
            r.point_form_factor(Vec3::ZERO, Vec3::Z, Vec3::Z * h as f32, -Vec3::Z, area) as f64;
        let bound = (radius / h).powi(2);
        if !close(got, exact, 0.0, bound + 1e-4) {
            return Err(format!(
                "point_form_factor from the origin (normal +z) to a small disc of radius {radius} (area πR² = {area:e}) at height {h} facing back is {got:e}; far away it must approach Howell's closed form R²/(h² + R²) = {exact:e} (within a relative {bound:.1e})"
            ));
        }
    }
    Ok(())
}

fn exercise_6_1(p: &Arc<dyn Radiosity>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab06::Radiosity>());
    for_all(300, point_input(), |input| {
        check_point(p.as_ref(), key.as_deref(), input)
    })?;
    check_far_disc(p.as_ref())?;
    let golden: GoldenFile<PointInput, f32> = load(ctx, GOLDEN_POINT)?;
    for case in &golden.cases {
        let (x, nx, y, ny, a) = case.input;
        let got = p.point_form_factor(x, nx, y, ny, a);
        if !close(got as f64, case.expected as f64, 1e-30, 1e-4) {
            return Err(format!(
                "{} = {got:e}, expected {:e}",
                point_call(case.input),
                case.expected
            ));
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Exercises 6.2 and 6.3

/// Input of a delta form factor: a point of the face and a pixel area `(2/n)²`.
pub type DeltaInput = (f32, f32, f32);

/// A point of the top face and the pixel area of a resolution from 2 to 1024.
pub fn top_input() -> impl Strategy<Value = DeltaInput> {
    (-1.0f32..=1.0, -1.0f32..=1.0, 2u32..1024).prop_map(|(x, y, n)| (x, y, 4.0 / (n * n) as f32))
}

/// A point of a side face and the pixel area of a resolution from 2 to 1024.
pub fn side_input() -> impl Strategy<Value = DeltaInput> {
    (-1.0f32..=1.0, 0.0f32..=1.0, 2u32..1024).prop_map(|(u, z, n)| (u, z, 4.0 / (n * n) as f32))
}

fn check_delta(
    name: &str,
    f: &dyn Fn(f32, f32, f32) -> f32,
    key: Option<&dyn Fn(f32, f32, f32) -> f32>,
    (a, b, area): DeltaInput,
    symmetric_swap: bool,
) -> Result<(), String> {
    let call = |a: f32, b: f32, area: f32| format!("{name}({a}, {b}, pixel_area = {area:e})");
    let d = f(a, b, area);
    if !d.is_finite() || d < 0.0 {
        return Err(format!(
            "{} = {d}: a delta form factor is finite and at least 0",
            call(a, b, area)
        ));
    }
    let mirrored = f(-a, b, area);
    if !close(mirrored as f64, d as f64, 1e-30, 1e-5) {
        return Err(format!(
            "{} = {d:e} but {} = {mirrored:e}: the hemicube is symmetric about its axis",
            call(a, b, area),
            call(-a, b, area)
        ));
    }
    if symmetric_swap {
        let swapped = f(b, a, area);
        if !close(swapped as f64, d as f64, 1e-30, 1e-5) {
            return Err(format!(
                "{} = {d:e} but {} = {swapped:e}: the top face is symmetric in x and y",
                call(a, b, area),
                call(b, a, area)
            ));
        }
    }
    let double = f(a, b, 2.0 * area);
    if !close(double as f64, 2.0 * d as f64, 1e-30, 1e-5) {
        return Err(format!(
            "{} = {d:e} but with twice the pixel area it is {double:e}: a delta form factor is proportional to the pixel's area",
            call(a, b, area)
        ));
    }
    if let Some(key) = key {
        let expected = key(a, b, area);
        if !close(d as f64, expected as f64, 1e-30, 1e-4) {
            return Err(format!(
                "{} = {d:e}, expected {expected:e}",
                call(a, b, area)
            ));
        }
    }
    Ok(())
}

/// The delta form factors of `r` sum to 1 at every resolution of [`SUM_RESOLUTIONS`].
fn check_sum(r: &dyn Radiosity, exercise: &str) -> Result<(), String> {
    for n in SUM_RESOLUTIONS {
        let delta = DeltaFormFactors::tabulate(r, n);
        let (top, side) = (
            delta.top.iter().map(|&d| d as f64).sum::<f64>(),
            delta.side.iter().map(|&d| d as f64).sum::<f64>(),
        );
        let total = top + 4.0 * side;
        if !total.is_finite() || (total - 1.0).abs() > sum_bound(n) {
            return Err(format!(
                "over a whole hemicube of resolution {n} (the top face's {n}×{n} pixels and four side faces of {n}×{} pixels) the delta form factors sum to {total:.6} (top face {top:.6}, side faces 4 × {side:.6}); the hemicube covers every direction above the patch, so they must sum to 1 within {:.1e} (your {exercise}, the key's other face)",
                n / 2,
                sum_bound(n)
            ));
        }
    }
    Ok(())
}

/// The two faces' formulas agree on their common edge (`x = 1` on the top, `z = 1` on a side).
fn check_edge(r: &dyn Radiosity) -> Result<(), String> {
    for k in 0..=8 {
        let t = -1.0 + k as f32 / 4.0;
        let area = 1e-3;
        let (top, side) = (
            r.delta_form_factor_top(1.0, t, area),
            r.delta_form_factor_side(t, 1.0, area),
        );
        if !close(top as f64, side as f64, 1e-30, 1e-4) {
            return Err(format!(
                "on the edge where the top face meets a side face the two formulas must agree (the same point (1, {t}, 1) of the cube), but delta_form_factor_top(1, {t}, {area}) = {top:e} and delta_form_factor_side({t}, 1, {area}) = {side:e}"
            ));
        }
    }
    Ok(())
}

/// A unit square's outline seen from an element, as a one-patch mesh.
fn square_mesh(corners: [Vec3; 4]) -> PatchMesh {
    PatchMesh::from_patches(
        corners.to_vec(),
        vec![quad_patch(corners, 0, Vec3::ONE, Vec3::ZERO)],
    )
}

/// Element-to-square form factors by the hemicube of `r` against Howell B-3 and B-2.
fn check_element_closed_forms(r: &dyn Radiosity) -> Result<(), String> {
    // From the origin (normal +z): a square of side s centred on the axis at height c facing
    // down, and a unit wall at y = d standing on the element's plane facing it.
    let parallel = |s: f32, c: f32| {
        let h = s / 2.0;
        let mesh = square_mesh([
            Vec3::new(-h, -h, c),
            Vec3::new(-h, h, c),
            Vec3::new(h, h, c),
            Vec3::new(h, -h, c),
        ]);
        let exact = 4.0 * closed_forms::element_to_parallel_rectangle(h as f64, h as f64, c as f64);
        (
            mesh,
            exact,
            format!(
                "a {s}×{s} square centred on the normal at distance {c}, facing the element (Howell B-3)"
            ),
        )
    };
    let perpendicular = |d: f32| {
        let mesh = square_mesh([
            Vec3::new(-0.5, d, 0.0),
            Vec3::new(-0.5, d, 1.0),
            Vec3::new(0.5, d, 1.0),
            Vec3::new(0.5, d, 0.0),
        ]);
        let exact = 2.0 * closed_forms::element_to_perpendicular_rectangle(0.5, 1.0, d as f64);
        (
            mesh,
            exact,
            format!(
                "a unit square standing at right angles on the element's plane at distance {d}, facing it (Howell B-2)"
            ),
        )
    };
    for (mesh, exact, what) in [
        parallel(1.0, 1.0),
        parallel(4.0, 1.0),
        perpendicular(0.5),
        perpendicular(0.2),
    ] {
        for n in CLOSED_FORM_RESOLUTIONS {
            let items = pipeline::radiosity::item_buffer_at(&mesh, Vec3::ZERO, Vec3::Z, n);
            let delta = DeltaFormFactors::tabulate(r, n);
            let f = r.accumulate_form_factors(&items, &delta, 1)[0] as f64;
            if !f.is_finite() || (f - exact).abs() > element_bound(n) {
                return Err(format!(
                    "the hemicube form factor (resolution {n}) from an element at the origin with normal +z to {what} is {f:.5}; the closed form is {exact:.5}, and the hemicube must come within {:.4} of it at this resolution",
                    element_bound(n)
                ));
            }
        }
    }
    Ok(())
}

fn exercise_delta(p: &Arc<dyn Radiosity>, ctx: &LabContext, part: Part) -> Result<(), String> {
    let (name, exercise, golden_name) = match part {
        Part::Top => ("delta_form_factor_top", "delta_form_factor_top", GOLDEN_TOP),
        _ => (
            "delta_form_factor_side",
            "delta_form_factor_side",
            GOLDEN_SIDE,
        ),
    };
    let r = part_slot(part, p, &ctx.base);
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab06::Radiosity>());
    let student = |a: f32, b: f32, area: f32| match part {
        Part::Top => p.delta_form_factor_top(a, b, area),
        _ => p.delta_form_factor_side(a, b, area),
    };
    let keyed = key.as_ref().map(|k| {
        let k = k.clone();
        move |a: f32, b: f32, area: f32| match part {
            Part::Top => k.delta_form_factor_top(a, b, area),
            _ => k.delta_form_factor_side(a, b, area),
        }
    });
    let keyed_ref: Option<&dyn Fn(f32, f32, f32) -> f32> = keyed.as_ref().map(|k| k as _);
    match part {
        Part::Top => for_all(300, top_input(), |i| {
            check_delta(name, &student, keyed_ref, i, true)
        })?,
        _ => for_all(300, side_input(), |i| {
            check_delta(name, &student, keyed_ref, i, false)
        })?,
    }
    if part == Part::Side {
        for u in [-1.0, -0.3, 0.0, 0.8] {
            let d = p.delta_form_factor_side(u, 0.0, 1e-2);
            if d != 0.0 {
                return Err(format!(
                    "delta_form_factor_side({u}, 0, 0.01) = {d:e}: a pixel in the patch's own plane (z = 0) is seen at grazing angle, cos φ = 0, so its delta form factor is 0"
                ));
            }
        }
    }
    check_edge(r.as_ref())?;
    check_sum(r.as_ref(), exercise)?;
    check_element_closed_forms(r.as_ref())?;
    let golden: GoldenFile<DeltaInput, f32> = load(ctx, golden_name)?;
    for case in &golden.cases {
        let (a, b, area) = case.input;
        let got = student(a, b, area);
        if !close(got as f64, case.expected as f64, 1e-30, 1e-4) {
            return Err(format!(
                "{name}({a}, {b}, pixel_area = {area:e}) = {got:e}, expected {:e}",
                case.expected
            ));
        }
    }
    Ok(())
}

fn exercise_6_2(p: &Arc<dyn Radiosity>, ctx: &LabContext) -> Result<(), String> {
    exercise_delta(p, ctx, Part::Top)
}

fn exercise_6_3(p: &Arc<dyn Radiosity>, ctx: &LabContext) -> Result<(), String> {
    exercise_delta(p, ctx, Part::Side)
}

// ---------------------------------------------------------------------------------------------
// Exercise 6.4

/// Input of `accumulate_form_factors`: an item buffer, its delta form factors, the patch count.
pub type AccumulateInput = (ItemBuffer, DeltaFormFactors, usize);

/// A random item buffer (resolution 2 to 8, ids below a patch count from 1 to 20, a third of
/// the pixels empty) and random positive delta form factors from 10⁻⁶ to 1.
pub fn accumulate_input() -> impl Strategy<Value = AccumulateInput> {
    (1u32..=4, 1usize..=20).prop_flat_map(|(half, count)| {
        let n = 2 * half;
        let id = prop::option::weighted(0.67, 0..count as u32);
        let weight = (-6.0f32..0.0).prop_map(|e| 10f32.powf(e));
        (
            prop::collection::vec(id.clone(), (n * n) as usize),
            prop::collection::vec(prop::collection::vec(id, (n * n / 2) as usize), 4),
            prop::collection::vec(weight.clone(), (n * n) as usize),
            prop::collection::vec(weight, (n * n / 2) as usize),
        )
            .prop_map(move |(top, sides, wt, ws)| {
                let [a, b, c, d]: [Vec<Option<u32>>; 4] = sides.try_into().expect("four sides");
                (
                    ItemBuffer {
                        resolution: n,
                        faces: [top, a, b, c, d],
                    },
                    DeltaFormFactors {
                        resolution: n,
                        top: wt,
                        side: ws,
                    },
                    count,
                )
            })
    })
}

fn check_accumulate(
    r: &dyn Radiosity,
    key: Option<&dyn Radiosity>,
    (items, delta, count): &AccumulateInput,
) -> Result<(), String> {
    let call = format!(
        "accumulate_form_factors(items of resolution {}, delta, patch_count = {count})",
        items.resolution
    );
    let f = r.accumulate_form_factors(items, delta, *count);
    if f.len() != *count {
        return Err(format!(
            "{call} returned {} form factors, expected one per patch ({count})",
            f.len()
        ));
    }
    let mut seen_weight = 0.0f64;
    let mut seen = vec![false; *count];
    for face in HemicubeFace::ALL {
        for (id, d) in items.face(face).iter().zip(delta.face(face)) {
            if let Some(j) = id {
                seen_weight += *d as f64;
                seen[*j as usize] = true;
            }
        }
    }
    let total: f64 = f.iter().map(|&x| x as f64).sum();
    if !close(total, seen_weight, 1e-12, 1e-4) {
        return Err(format!(
            "{call}: the form factors sum to {total:e}, but the delta form factors of the pixels that see a patch (all five faces; the four side faces share one table) sum to {seen_weight:e}: every such pixel counts once, for the patch it sees, and empty pixels count for none"
        ));
    }
    if let Some(j) = (0..*count).find(|&j| !seen[j] && f[j] != 0.0) {
        return Err(format!(
            "{call}: patch {j} appears in no pixel but has form factor {:e}",
            f[j]
        ));
    }
    // Renaming the patches renames the form factors.
    let rename = |j: u32| (*count as u32 - 1) - j;
    let renamed = ItemBuffer {
        resolution: items.resolution,
        faces: items
            .faces
            .clone()
            .map(|face| face.into_iter().map(|id| id.map(rename)).collect()),
    };
    let g = r.accumulate_form_factors(&renamed, delta, *count);
    for j in 0..*count {
        if g.get(rename(j as u32) as usize).copied() != Some(f[j])
            && !close(
                g[rename(j as u32) as usize] as f64,
                f[j] as f64,
                1e-12,
                1e-5,
            )
        {
            return Err(format!(
                "{call}: patch {j}'s form factor is {:e}, but with the patches numbered in reverse it is {:e}: each pixel's delta form factor goes to the patch it sees",
                f[j],
                g[rename(j as u32) as usize]
            ));
        }
    }
    if let Some(key) = key {
        let expected = key.accumulate_form_factors(items, delta, *count);
        for j in 0..*count {
            if !close(f[j] as f64, expected[j] as f64, 1e-12, 1e-4) {
                return Err(format!(
                    "{call}: patch {j}'s form factor is {:e}, expected {:e}",
                    f[j], expected[j]
                ));
            }
        }
    }
    Ok(())
}

/// Area-to-area form factors of two unit squares (7 × 7 patches each) by hemicubes: reciprocal,
/// and equal to Howell's C-11 and C-14.
fn check_area_closed_forms(r: &dyn Radiosity) -> Result<(), String> {
    // 7 × 7: no pixel centre of hemicubes of resolution 16, 32, 64 lies on a patch edge.
    let k = 7;
    let parallel = join(vec![
        grid(Vec3::ZERO, Vec3::X, Vec3::Y, k, Vec3::ONE),
        grid(Vec3::Z, Vec3::Y, Vec3::X, k, Vec3::ONE),
    ]);
    let perpendicular = join(vec![
        grid(Vec3::ZERO, Vec3::X, Vec3::Y, k, Vec3::ONE),
        grid(Vec3::ZERO, Vec3::Z, Vec3::X, k, Vec3::ONE),
    ]);
    let configs = [
        (
            parallel,
            closed_forms::parallel_rectangles(1.0, 1.0, 1.0),
            "two directly opposed parallel unit squares at unit distance (Howell C-11)",
        ),
        (
            perpendicular,
            closed_forms::perpendicular_rectangles(1.0, 1.0, 1.0),
            "two unit squares at right angles along a common edge (Howell C-14)",
        ),
    ];
    for ((mesh, starts), exact, what) in &configs {
        let (a, b) = (starts[0]..starts[1], starts[1]..mesh.patches.len());
        for n in CLOSED_FORM_RESOLUTIONS {
            let delta = DeltaFormFactors::tabulate(r, n);
            let from = |src: &std::ops::Range<usize>, dst: &std::ops::Range<usize>| -> f64 {
                let area: f64 = src.clone().map(|i| mesh.patches[i].area as f64).sum();
                src.clone()
                    .map(|i| {
                        let items = pipeline::radiosity::item_buffer(mesh, i, n);
                        let f = r.accumulate_form_factors(&items, &delta, mesh.patches.len());
                        mesh.patches[i].area as f64 * dst.clone().map(|j| f[j] as f64).sum::<f64>()
                    })
                    .sum::<f64>()
                    / area
            };
            let (f_ab, f_ba) = (from(&a, &b), from(&b, &a));
            let bound = area_bound(n);
            if !f_ab.is_finite() || (f_ab - f_ba).abs() > bound {
                return Err(format!(
                    "for {what}, the hemicube form factors (resolution {n}, {k}×{k} patches a square) are F_12 = {f_ab:.5} and F_21 = {f_ba:.5}: with equal areas reciprocity A_1 F_12 = A_2 F_21 makes them equal (within {bound:.4})"
                ));
            }
            if (f_ab - exact).abs() > bound {
                return Err(format!(
                    "for {what}, the hemicube form factor (resolution {n}, {k}×{k} patches a square) is {f_ab:.5}; the closed form is {exact:.5}, and it must come within {bound:.4}"
                ));
            }
        }
    }
    Ok(())
}

/// In a closed box every pixel sees a patch: each patch's form factors sum to the hemicube's
/// total delta form factor, 1 up to the discretisation.
fn check_closed_box_sums(r: &dyn Radiosity) -> Result<(), String> {
    let mesh = closed_box(1.0, 3, 0.5);
    let n = 32;
    let delta = DeltaFormFactors::tabulate(r, n);
    for i in [0, 4, 13, 30, 53] {
        let items = pipeline::radiosity::item_buffer(&mesh, i, n);
        let f = r.accumulate_form_factors(&items, &delta, mesh.patches.len());
        let sum: f64 = f.iter().map(|&x| x as f64).sum();
        if !close(sum, delta.total(), 1e-9, 1e-4) {
            return Err(format!(
                "in a closed box (6 faces of 3×3 patches) the form factors from patch {i} by a hemicube of resolution {n} sum to {sum:.6}; every pixel sees some patch, so they must sum to the hemicube's total delta form factor {:.6} (1 up to the discretisation)",
                delta.total()
            ));
        }
        if f[i] != 0.0 {
            return Err(format!(
                "in a closed box the form factor from patch {i} to itself is {:e}; a planar patch cannot see itself",
                f[i]
            ));
        }
    }
    Ok(())
}

fn exercise_6_4(p: &Arc<dyn Radiosity>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab06::Radiosity>());
    for_all(200, accumulate_input(), |input| {
        check_accumulate(p.as_ref(), key.as_deref(), &input)
    })?;
    let r = part_slot(Part::Accumulate, p, &ctx.base);
    check_closed_box_sums(r.as_ref())?;
    check_area_closed_forms(r.as_ref())?;
    let golden: GoldenFile<AccumulateInput, Vec<f32>> = load(ctx, GOLDEN_ACCUMULATE)?;
    for case in &golden.cases {
        let (items, delta, count) = &case.input;
        let got = p.accumulate_form_factors(items, delta, *count);
        let ok = got.len() == case.expected.len()
            && got
                .iter()
                .zip(&case.expected)
                .all(|(a, b)| close(*a as f64, *b as f64, 1e-12, 1e-4));
        if !ok {
            return Err(format!(
                "accumulate_form_factors(items of resolution {}, delta, patch_count = {count}) = {got:?}, expected {:?}",
                items.resolution, case.expected
            ));
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Exercises 6.5 and 6.6: patches and their radiosities

/// A patch with only what shooting needs: area and reflectance (one vertex, at no position).
fn bare_patch(area: f32, reflectance: Vec3) -> Patch {
    Patch {
        vertices: vec![0, 0, 0],
        centre: Vec3::ZERO,
        normal: Vec3::Z,
        area,
        reflectance,
        emission: Vec3::ZERO,
    }
}

/// A colour with channels from 10⁻³ to 10³, some of them 0.
fn radiosity() -> impl Strategy<Value = Vec3> {
    let channel = prop_oneof![1 => Just(0.0f32), 3 => (-3.0f32..3.0).prop_map(|e| 10f32.powf(e))];
    (channel.clone(), channel.clone(), channel).prop_map(|(r, g, b)| Vec3::new(r, g, b))
}

/// Input of `select_shooter`: patch areas from 10⁻⁸ to 10⁶ and unshot radiosities (a tenth of
/// the cases with nothing left to shoot).
pub type ShooterInput = (Vec<Patch>, Vec<Vec3>);

/// Patches and unshot radiosities for `select_shooter`.
pub fn shooter_input() -> impl Strategy<Value = ShooterInput> {
    (1usize..30, prop::bool::weighted(0.1)).prop_flat_map(|(n, empty)| {
        (
            prop::collection::vec(
                (-8.0f32..6.0).prop_map(|e| bare_patch(10f32.powf(e), Vec3::splat(0.5))),
                n,
            ),
            prop::collection::vec(
                radiosity().prop_map(move |u| if empty { Vec3::ZERO } else { u }),
                n,
            ),
        )
    })
}

fn power(p: &Patch, u: Vec3) -> f64 {
    p.area as f64 * (u.x as f64 + u.y as f64 + u.z as f64)
}

fn check_shooter(
    r: &dyn Radiosity,
    key: Option<&dyn Radiosity>,
    (patches, unshot): &ShooterInput,
) -> Result<(), String> {
    let got = r.select_shooter(patches, unshot);
    let powers: Vec<f64> = patches
        .iter()
        .zip(unshot)
        .map(|(p, u)| power(p, *u))
        .collect();
    let most = powers.iter().cloned().fold(0.0, f64::max);
    let call = format!(
        "select_shooter(patches with areas {:?}, unshot {:?})",
        patches.iter().map(|p| p.area).collect::<Vec<_>>(),
        unshot
    );
    match got {
        None if most > 0.0 => Err(format!(
            "{call} = None, but patches still have unshot power (most: {most:e})"
        )),
        None => Ok(()),
        Some(i) if i >= patches.len() => Err(format!(
            "{call} = Some({i}): there are only {} patches",
            patches.len()
        )),
        Some(_) if most == 0.0 => Err(format!(
            "{call} = {got:?}, but no patch has unshot power left: return None, so that refinement stops"
        )),
        Some(i) if powers[i] < most * (1.0 - 1e-5) => {
            let j = powers.iter().position(|&p| p == most).unwrap_or(0);
            Err(format!(
                "{call} = Some({i}), whose unshot power A·(ΔB.r + ΔB.g + ΔB.b) is {:e}; patch {j} has {most:e}: pick the most unshot power (radiosity times area), not the most unshot radiosity",
                powers[i]
            ))
        }
        Some(i) => match key.and_then(|k| k.select_shooter(patches, unshot)) {
            Some(k) if (powers[k] - powers[i]).abs() > 1e-5 * most => {
                Err(format!("{call} = Some({i}), expected Some({k})"))
            }
            _ => Ok(()),
        },
    }
}

fn exercise_6_5(p: &Arc<dyn Radiosity>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab06::Radiosity>());
    for_all(300, shooter_input(), |input| {
        check_shooter(p.as_ref(), key.as_deref(), &input)
    })?;
    let golden: GoldenFile<ShooterInput, Option<usize>> = load(ctx, GOLDEN_SHOOTER)?;
    for case in &golden.cases {
        let (patches, unshot) = &case.input;
        let got = p.select_shooter(patches, unshot);
        let same = match (got, case.expected) {
            (Some(a), Some(b)) => {
                a < patches.len()
                    && (power(&patches[a], unshot[a]) - power(&patches[b], unshot[b])).abs()
                        <= 1e-5 * power(&patches[b], unshot[b])
            }
            (a, b) => a == b,
        };
        if !same {
            return Err(format!(
                "select_shooter on a recorded case of {} patches = {got:?}, expected {:?}",
                patches.len(),
                case.expected
            ));
        }
    }
    Ok(())
}

/// Input of `shoot`: patches, form factors from the shooter (summing to at most 1), the
/// shooter, radiosities and unshot radiosities.
pub type ShootInput = (Vec<Patch>, Vec<f32>, usize, Vec<Vec3>, Vec<Vec3>);

/// Patches with areas from 10⁻⁶ to 10⁴ and reflectances in `[0, 1]`, form factors summing to at
/// most 1 (none to the shooter itself), a shooter with unshot radiosity, radiosities at least
/// the unshot ones.
pub fn shoot_input() -> impl Strategy<Value = ShootInput> {
    (2usize..12).prop_flat_map(|n| {
        let patch = ((-6.0f32..4.0), (0.0f32..=1.0, 0.0f32..=1.0, 0.0f32..=1.0))
            .prop_map(|(e, (r, g, b))| bare_patch(10f32.powf(e), Vec3::new(r, g, b)));
        (
            prop::collection::vec(patch, n),
            prop::collection::vec(0.0f32..1.0, n),
            0..n,
            prop::collection::vec(radiosity(), n),
            prop::collection::vec(radiosity(), n),
            radiosity().prop_map(|u| u + Vec3::splat(1e-3)),
        )
            .prop_map(|(patches, raw, i, extra, mut unshot, shooter_unshot)| {
                let mut f = raw;
                f[i] = 0.0;
                let sum: f32 = f.iter().sum();
                if sum > 1.0 {
                    f.iter_mut().for_each(|x| *x /= sum);
                }
                unshot[i] = shooter_unshot;
                let b = unshot.iter().zip(&extra).map(|(u, e)| *u + *e).collect();
                (patches, f, i, b, unshot)
            })
    })
}

fn check_shoot(
    r: &dyn Radiosity,
    key: Option<&dyn Radiosity>,
    input: &ShootInput,
) -> Result<(), String> {
    let (patches, f, i, b0, u0) = input;
    let i = *i;
    let (mut b, mut u) = (b0.clone(), u0.clone());
    r.shoot(patches, f, i, &mut b, &mut u);
    let call = format!("shoot(… {} patches, shooter = {i}, …)", patches.len());
    if u[i] != Vec3::ZERO {
        return Err(format!(
            "{call}: afterwards the shooter's unshot radiosity is {}; it has shot everything it had, so it must be 0",
            u[i]
        ));
    }
    if !vec3_close(b[i], b0[i], 0.0, 1e-6) {
        return Err(format!(
            "{call}: the shooter's radiosity went from {} to {}; shooting passes on its unshot radiosity but keeps its radiosity (it still sends that light out)",
            b0[i], b[i]
        ));
    }
    for j in 0..patches.len() {
        if j == i {
            continue;
        }
        let (db, du) = (b[j] - b0[j], u[j] - u0[j]);
        if !vec3_close(db, du, 1e-30, 1e-3) && !vec3_close(b[j], b0[j] + du, 1e-30, 1e-5) {
            return Err(format!(
                "{call}: patch {j}'s radiosity grew by {db} but its unshot radiosity by {du}: what a patch receives is added to both"
            ));
        }
        if (du.cmplt(Vec3::ZERO)).any() || !du.is_finite() {
            return Err(format!(
                "{call}: patch {j} received {du}: received radiosity is finite and at least 0"
            ));
        }
        if f[j] == 0.0 && du != Vec3::ZERO {
            return Err(format!(
                "{call}: patch {j} has form factor 0 from the shooter but received {du}"
            ));
        }
        for c in 0..3 {
            if patches[j].reflectance[c] == 0.0 && du[c] != 0.0 {
                return Err(format!(
                    "{call}: patch {j} has reflectance {} but received {du}: a patch reflects what it receives times its reflectance ρ_j, so a channel with ρ = 0 receives nothing",
                    patches[j].reflectance
                ));
            }
        }
    }
    diagnose_shoot(r, &call, input)?;
    // Energy: the power arriving at the others is the shooter's power times Σ F_ij, per channel
    // (on the channels of patches with ρ > 0).
    let shot_power = u0[i].as_dvec3() * patches[i].area as f64;
    let mut arriving = glam::DVec3::ZERO;
    let mut expected = glam::DVec3::ZERO;
    // The f32 rounding of ΔB_j added to the unshot radiosity it already had.
    let mut rounding = glam::DVec3::ZERO;
    for j in 0..patches.len() {
        if j == i {
            continue;
        }
        let rho = patches[j].reflectance.as_dvec3();
        let du = (u[j] - u0[j]).as_dvec3();
        for c in 0..3 {
            if rho[c] > 1e-3 {
                arriving[c] += du[c] * patches[j].area as f64 / rho[c];
                expected[c] += shot_power[c] * f[j] as f64;
                rounding[c] += 2e-7 * u[j][c].abs() as f64 * patches[j].area as f64 / rho[c];
            }
        }
    }
    for c in 0..3 {
        if !close(
            arriving[c],
            expected[c],
            rounding[c] + 1e-12 * shot_power[c],
            1e-3,
        ) {
            return Err(format!(
                "{call}: in channel {c} the shooter sends power A_i ΔB_i = {:e}, of which Σ_j F_ij = {:.4} should arrive at the other patches (power {:e}); your radiosities make A_j ΔB_j / ρ_j add up to {:e}. Radiosity is power per area: what patch j receives is ρ_j ΔB_i F_ij A_i / A_j",
                shot_power[c],
                expected[c] / shot_power[c].max(1e-300),
                expected[c],
                arriving[c]
            ));
        }
    }
    if let Some(key) = key {
        let (mut kb, mut ku) = (b0.clone(), u0.clone());
        key.shoot(patches, f, i, &mut kb, &mut ku);
        for j in 0..patches.len() {
            if !vec3_close(b[j], kb[j], 1e-30, 1e-4) || !vec3_close(u[j], ku[j], 1e-30, 1e-4) {
                return Err(format!(
                    "{call}: patch {j} has radiosity {} and unshot {} afterwards, expected {} and {}",
                    b[j], u[j], kb[j], ku[j]
                ));
            }
        }
    }
    Ok(())
}

/// What each patch's radiosity receives from one shot of `input`'s shooter through `r`, every
/// other patch starting from nothing (so that nothing is lost to rounding against what it had).
fn received(r: &dyn Radiosity, (patches, f, i, b0, u0): &ShootInput) -> Vec<Vec3> {
    let mut b = vec![Vec3::ZERO; patches.len()];
    let mut u = b.clone();
    b[*i] = b0[*i];
    u[*i] = u0[*i];
    r.shoot(patches, f, *i, &mut b, &mut u);
    b.iter()
        .enumerate()
        .map(|(j, x)| if j == *i { Vec3::ZERO } else { *x })
        .collect()
}

/// The first patch and channel whose received radiosity in `changed` is not `factor` times
/// that in `before` (channels that received a normal, finite amount only): `(j, before_j,
/// changed_j)`.
fn not_scaled(before: &[Vec3], changed: &[Vec3], factor: f32) -> Option<(usize, Vec3, Vec3)> {
    before
        .iter()
        .zip(changed)
        .enumerate()
        .find_map(|(j, (a, b))| {
            let differs = (0..3).any(|c| {
                a[c].is_normal()
                    && a[c].is_finite()
                    && (a[c] * 1e-20).is_normal()
                    && (b[c] - factor * a[c]).abs() > 1e-3 * factor * a[c].abs()
            });
            differs.then_some((j, *a, *b))
        })
}

/// The relations of one shot that tell its mistakes apart: what patch `j` receives halves
/// when the receivers' areas double (the power arriving spreads over `A_j`), doubles when the
/// shooter's area doubles (the power shot is `A_i ΔB_i`), and does not change with the
/// shooter's radiosity `B_i` (only the unshot `ΔB_i` is shot) or its reflectance (the receiver
/// reflects, with its own `ρ_j`).
fn diagnose_shoot(r: &dyn Radiosity, call: &str, input: &ShootInput) -> Result<(), String> {
    let (patches, f, i, b0, u0) = input;
    let i = *i;
    let before = received(r, input);
    if before.iter().all(|x| *x == Vec3::ZERO) {
        // A patch that receives a normal amount (ρ_j ΔB_i F_ij A_i / A_j, in f64).
        let lit = (0..patches.len()).find(|&j| {
            let ratio = f[j] as f64 * patches[i].area as f64 / patches[j].area as f64;
            j != i && (patches[j].reflectance * u0[i]).as_dvec3().max_element() * ratio > 1e-30
        });
        return match lit {
            Some(j) => Err(format!(
                "{call}: no patch receives anything, though patch {j} has form factor F_ij = {} from the shooter, reflectance {} and the shooter has unshot radiosity ΔB_i = {}: read ΔB_i (into a local) before setting the shooter's unshot radiosity to 0, which comes last",
                f[j], patches[j].reflectance, u0[i]
            )),
            None => Ok(()),
        };
    }
    let with = |change: &dyn Fn(usize, &mut Patch)| {
        let mut p = patches.clone();
        for (j, patch) in p.iter_mut().enumerate() {
            change(j, patch);
        }
        received(r, &(p, f.clone(), i, b0.clone(), u0.clone()))
    };
    let receivers_doubled = with(&|j, p| {
        if j != i {
            p.area *= 2.0;
        }
    });
    let shooter_doubled = with(&|j, p| {
        if j == i {
            p.area *= 2.0;
        }
    });
    if not_scaled(&before, &receivers_doubled, 0.5).is_some() {
        if not_scaled(&before, &receivers_doubled, 2.0).is_none() {
            let (j, a, b) = not_scaled(&before, &receivers_doubled, 0.5).unwrap_or_default();
            return Err(format!(
                "{call}: patch {j} receives {a}, and {b} with every receiver's area doubled: twice as much, where a patch twice as large receives half the radiosity (the same power over twice the area). The shooter's power A_i ΔB_i F_ij spreads over the receiver's area: the ratio is A_i / A_j, the shooter's area over the receiver's, not A_j / A_i"
            ));
        }
        if not_scaled(&before, &receivers_doubled, 1.0).is_none()
            && not_scaled(&before, &shooter_doubled, 1.0).is_none()
        {
            let j = before.iter().position(|x| *x != Vec3::ZERO).unwrap_or(0);
            return Err(format!(
                "{call}: patch {j} receives {} whatever the patches' areas (the same with every receiver's area doubled, and with the shooter's): ΔB_i F_ij is power per unit of the shooter's area; the power A_i ΔB_i F_ij that arrives spreads over the receiver's area A_j, so patch j receives ρ_j ΔB_i F_ij A_i / A_j — the ratio of areas is missing",
                before[j]
            ));
        }
        let (j, a, b) = not_scaled(&before, &receivers_doubled, 0.5).unwrap_or_default();
        return Err(format!(
            "{call}: patch {j} receives {a}, and {b} with every receiver's area doubled, expected half of it: radiosity is power per area, so the same power arriving at a patch twice as large is half the radiosity (ρ_j ΔB_i F_ij A_i / A_j)"
        ));
    }
    if let Some((j, a, b)) = not_scaled(&before, &shooter_doubled, 2.0) {
        return Err(format!(
            "{call}: patch {j} receives {a}, and {b} with the shooter's area doubled, expected twice as much: a shooter twice as large shoots twice the power A_i ΔB_i (ρ_j ΔB_i F_ij A_i / A_j)"
        ));
    }
    let mut b_changed = b0.clone();
    b_changed[i] = b0[i] * 3.0 + Vec3::new(1.0, 2.0, 3.0);
    let radiosity_changed = received(r, &(patches.clone(), f.clone(), i, b_changed, u0.clone()));
    if let Some((j, a, b)) = not_scaled(&before, &radiosity_changed, 1.0) {
        return Err(format!(
            "{call}: patch {j} receives {a}, but {b} when only the shooter's radiosity B_i changes (its unshot radiosity ΔB_i the same): a shot sends the unshot radiosity ΔB_i, the light the shooter has received since it last shot; B_i also holds the light it has already shot, which would be sent again"
        ));
    }
    let reflectance_changed = with(&|j, p| {
        if j == i {
            p.reflectance = Vec3::select(
                p.reflectance.cmpgt(Vec3::splat(0.5)),
                Vec3::splat(0.2),
                Vec3::splat(0.8),
            );
        }
    });
    if let Some((j, a, b)) = not_scaled(&before, &reflectance_changed, 1.0) {
        return Err(format!(
            "{call}: patch {j} receives {a}, but {b} when only the shooter's reflectance changes: the receiving patch reflects what arrives, so the factor is its own reflectance ρ_j (patches[j].reflectance), not the shooter's"
        ));
    }
    Ok(())
}

/// A shot in which every factor of `ρ_j ΔB_i F_ij A_i / A_j` differs from patch to patch and
/// from channel to channel, and the shooter's radiosity from its unshot radiosity: the input
/// on which [`diagnose_shoot`] first tells the mistakes apart.
pub fn diagnosis_input() -> ShootInput {
    let patches = vec![
        bare_patch(0.5, Vec3::new(0.3, 0.6, 0.9)),
        bare_patch(2.0, Vec3::new(0.8, 0.5, 0.2)),
        bare_patch(0.1, Vec3::new(0.4, 0.7, 0.6)),
        bare_patch(1.0, Vec3::new(0.5, 0.25, 0.75)),
    ];
    let f = vec![0.0, 0.3, 0.05, 0.2];
    let u = vec![
        Vec3::new(1.0, 2.0, 1.5),
        Vec3::new(0.1, 0.2, 0.3),
        Vec3::ZERO,
        Vec3::new(0.5, 0.0, 0.25),
    ];
    let b = vec![
        Vec3::new(5.0, 4.0, 3.0),
        Vec3::new(0.4, 0.5, 0.6),
        Vec3::new(0.2, 0.1, 0.3),
        Vec3::new(0.5, 0.7, 0.25),
    ];
    (patches, f, 0, b, u)
}

/// In a closed box with `ρ < 1` (6 faces of 3 × 3 patches, one emitting), the solution's total
/// power stays below the geometric series `P_E (1 + ρ + ρ² + …) = P_E / (1 − ρ)` and reaches
/// it, at scales from 10⁻³ to 10³.
fn check_closed_box_energy(r: &dyn Radiosity) -> Result<(), String> {
    let (rho, n) = (0.6f32, 16);
    for size in [1e-3f32, 1.0, 1e3] {
        let mesh = closed_box(size, 3, rho);
        let settings = SolveSettings {
            form_factors: FormFactors::Hemicube(n),
            threshold: 1e-4,
            max_shots: 5000,
        };
        let solution = solve(r, &mesh, &settings);
        let emitted = mesh.power(&mesh.emission());
        let total = mesh.power(&solution.radiosity) / emitted;
        let bound = 1.0 / (1.0 - rho as f64);
        let slack = 1e-3 + 2.0 * sum_bound(n);
        let unshot = mesh.power(&solution.unshot) / emitted;
        if !total.is_finite()
            || total > bound * (1.0 + slack)
            || total < bound * (1.0 - slack) - unshot / (1.0 - rho as f64)
        {
            return Err(format!(
                "in a closed box of side {size:e} with reflectance ρ = {rho} everywhere and one emitting patch, the converged solution ({} shots, hemicube {n}) has total power Σ A_j B_j = {total:.5} times the emitted power; every bounce keeps the fraction ρ of the light, so it must reach the geometric series 1/(1 − ρ) = {bound:.5} without exceeding it (within {slack:.1e})",
                solution.shots()
            ));
        }
    }
    Ok(())
}

fn exercise_6_6(p: &Arc<dyn Radiosity>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab06::Radiosity>());
    let input = diagnosis_input();
    let call = format!(
        "shoot(patches with areas {:?} and reflectances {}, form factors {:?}, shooter = 0 with radiosity B_0 = {} and unshot ΔB_0 = {}, …)",
        input.0.iter().map(|p| p.area).collect::<Vec<_>>(),
        input
            .0
            .iter()
            .map(|p| p.reflectance.to_string())
            .collect::<Vec<_>>()
            .join(", "),
        input.1,
        input.3[0],
        input.4[0]
    );
    diagnose_shoot(p.as_ref(), &call, &input)?;
    for_all(300, shoot_input(), |input| {
        check_shoot(p.as_ref(), key.as_deref(), &input)
    })?;
    let golden: GoldenFile<ShootInput, (Vec<Vec3>, Vec<Vec3>)> = load(ctx, GOLDEN_SHOOT)?;
    for case in &golden.cases {
        let (patches, f, i, b0, u0) = &case.input;
        let (mut b, mut u) = (b0.clone(), u0.clone());
        p.shoot(patches, f, *i, &mut b, &mut u);
        let (eb, eu) = &case.expected;
        for j in 0..patches.len() {
            if !vec3_close(b[j], eb[j], 1e-30, 1e-4) || !vec3_close(u[j], eu[j], 1e-30, 1e-4) {
                return Err(format!(
                    "shoot on a recorded case ({} patches, shooter {i}): patch {j} has radiosity {} and unshot {} afterwards, expected {} and {}",
                    patches.len(),
                    b[j],
                    u[j],
                    eb[j],
                    eu[j]
                ));
            }
        }
    }
    let r = part_slot(Part::Shoot, p, &ctx.base);
    check_closed_box_energy(r.as_ref())?;
    check_image(r.as_ref(), ctx, false, SNAPSHOT_FLAT)
}

// ---------------------------------------------------------------------------------------------
// Exercises 6.7 and 6.8

/// Radiosities from 10⁻⁴ to 10⁴, 1 to 40 patches.
pub fn colours_input() -> impl Strategy<Value = Vec<Vec3>> {
    let c = (-4.0f32..4.0).prop_map(|e| 10f32.powf(e));
    prop::collection::vec(
        (c.clone(), c.clone(), c).prop_map(|(r, g, b)| Vec3::new(r, g, b)),
        1..40,
    )
}

fn exercise_6_7(p: &Arc<dyn Radiosity>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab06::Radiosity>());
    for_all(200, colours_input(), |b| {
        let l = p.patch_colours(&b);
        if l.len() != b.len() {
            return Err(format!(
                "patch_colours of {} radiosities returned {} colours",
                b.len(),
                l.len()
            ));
        }
        let doubled: Vec<Vec3> = b.iter().map(|x| *x * 2.0).collect();
        let l2 = p.patch_colours(&doubled);
        for (k, (a, c)) in l.iter().zip(&l2).enumerate() {
            if !vec3_close(*c, *a * 2.0, 1e-30, 1e-5) {
                return Err(format!(
                    "patch_colours: radiosity {} gives {a}, but twice it gives {c}: radiance is proportional to radiosity",
                    b[k]
                ));
            }
            if !a.is_finite() || a.cmpgt(b[k]).any() {
                return Err(format!(
                    "patch_colours: radiosity {} gives {a}; a Lambertian patch's radiance is smaller than its radiosity (B = ∫ L cos θ dω = π L)",
                    b[k]
                ));
            }
        }
        if let Some(key) = &key {
            for (k, (a, e)) in l.iter().zip(key.patch_colours(&b)).enumerate() {
                if !vec3_close(*a, e, 1e-30, 1e-5) {
                    return Err(format!(
                        "patch_colours: radiosity {} gives {a}, expected {e}",
                        b[k]
                    ));
                }
            }
        }
        Ok(())
    })?;
    let golden: GoldenFile<Vec<Vec3>, Vec<Vec3>> = load(ctx, GOLDEN_COLOURS)?;
    for case in &golden.cases {
        let got = p.patch_colours(&case.input);
        for (k, e) in case.expected.iter().enumerate() {
            if got.get(k).is_none_or(|a| !vec3_close(*a, *e, 1e-30, 1e-5)) {
                return Err(format!(
                    "patch_colours: radiosity {} gives {:?}, expected {e}",
                    case.input[k],
                    got.get(k)
                ));
            }
        }
    }
    let r = part_slot(Part::Colours, p, &ctx.base);
    check_image(r.as_ref(), ctx, false, SNAPSHOT_FLAT)
}

/// Input of `vertex_colours`: patches (3 or 4 distinct corners each), the vertex count, and
/// the patches' colours.
pub type VerticesInput = (Vec<Patch>, usize, Vec<Vec3>);

/// 1 to 30 patches over 3 to 40 vertices (some vertices of no patch), areas from 10⁻³ to 10³
/// (neighbours of unequal size, as where a coarse quad meets a fine one), colours from 10⁻³
/// to 10³.
pub fn vertices_input() -> impl Strategy<Value = VerticesInput> {
    (4usize..40, 1usize..30).prop_flat_map(|(vertices, n)| {
        let corners = (3usize..=4).prop_flat_map(move |k| {
            prop::sample::subsequence((0..vertices as u32).collect::<Vec<_>>(), k).prop_shuffle()
        });
        let c = (-3.0f32..3.0).prop_map(|e| 10f32.powf(e));
        (
            prop::collection::vec(
                (corners, -3.0f32..3.0).prop_map(|(v, e)| Patch {
                    vertices: v,
                    ..bare_patch(10f32.powf(e), Vec3::ONE)
                }),
                n,
            ),
            Just(vertices),
            prop::collection::vec(
                (c.clone(), c.clone(), c).prop_map(|(r, g, b)| Vec3::new(r, g, b)),
                n,
            ),
        )
    })
}

fn check_vertices(
    r: &dyn Radiosity,
    key: Option<&dyn Radiosity>,
    (patches, count, colours): &VerticesInput,
) -> Result<(), String> {
    let got = r.vertex_colours(patches, *count, colours);
    let call = format!(
        "vertex_colours({} patches, vertex_count = {count}, …)",
        patches.len()
    );
    if got.len() != *count {
        return Err(format!(
            "{call} returned {} colours, expected one per vertex ({count})",
            got.len()
        ));
    }
    for (v, &c) in got.iter().enumerate() {
        let around: Vec<(usize, Vec3)> = patches
            .iter()
            .enumerate()
            .filter(|(_, p)| p.vertices.contains(&(v as u32)))
            .map(|(k, _)| (k, colours[k]))
            .collect();
        if around.is_empty() {
            if c != Vec3::ZERO {
                return Err(format!(
                    "{call}: vertex {v} is a corner of no patch but has colour {c}; it must be black (and not NaN)"
                ));
            }
            continue;
        }
        let lo = around
            .iter()
            .fold(Vec3::splat(f32::INFINITY), |m, (_, c)| m.min(*c));
        let hi = around.iter().fold(Vec3::ZERO, |m, (_, c)| m.max(*c));
        if !c.is_finite() || c.cmplt(lo * (1.0 - 1e-5)).any() || c.cmpgt(hi * (1.0 + 1e-5)).any() {
            return Err(format!(
                "{call}: vertex {v} is a corner of patches {:?} with colours from {lo} to {hi}, but its colour is {c}: the mean of its patches' colours lies between them",
                around.iter().map(|(k, _)| *k).collect::<Vec<_>>()
            ));
        }
        if around.len() == 1 && !vec3_close(c, around[0].1, 1e-30, 1e-5) {
            return Err(format!(
                "{call}: vertex {v} is a corner of patch {} only (colour {}), but its colour is {c}",
                around[0].0, around[0].1
            ));
        }
    }
    // The mean counts every patch once: the same patches with other areas give the same colours.
    let resized: Vec<Patch> = patches
        .iter()
        .enumerate()
        .map(|(k, p)| Patch {
            area: if k % 2 == 0 { 1.0 } else { 7.0 },
            ..p.clone()
        })
        .collect();
    let again = r.vertex_colours(&resized, *count, colours);
    for (v, (&c, a)) in got.iter().zip(&again).enumerate() {
        if !vec3_close(c, *a, 1e-30, 1e-5) {
            let around: Vec<usize> = (0..patches.len())
                .filter(|&k| patches[k].vertices.contains(&(v as u32)))
                .collect();
            return Err(format!(
                "{call}: vertex {v} is a corner of patches {around:?} with areas {:?} and colours {:?}; its colour is {c}, but {a} when only the patches' areas change (to {:?}): nodal averaging is the plain mean of the colours of the patches around a vertex, each patch counting once whatever its area",
                around.iter().map(|&k| patches[k].area).collect::<Vec<_>>(),
                around.iter().map(|&k| colours[k]).collect::<Vec<_>>(),
                around.iter().map(|&k| resized[k].area).collect::<Vec<_>>(),
            ));
        }
    }
    if let Some(key) = key {
        for (v, e) in key
            .vertex_colours(patches, *count, colours)
            .iter()
            .enumerate()
        {
            if !vec3_close(got[v], *e, 1e-30, 1e-5) {
                return Err(format!(
                    "{call}: vertex {v} has colour {}, expected {e} (the mean over the patches it is a corner of)",
                    got[v]
                ));
            }
        }
    }
    Ok(())
}

fn exercise_6_8(p: &Arc<dyn Radiosity>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab06::Radiosity>());
    for_all(200, vertices_input(), |input| {
        check_vertices(p.as_ref(), key.as_deref(), &input)
    })?;
    let golden: GoldenFile<VerticesInput, Vec<Vec3>> = load(ctx, GOLDEN_VERTICES)?;
    for case in &golden.cases {
        let (patches, count, colours) = &case.input;
        let got = p.vertex_colours(patches, *count, colours);
        for (v, e) in case.expected.iter().enumerate() {
            if got.get(v).is_none_or(|a| !vec3_close(*a, *e, 1e-30, 1e-5)) {
                return Err(format!(
                    "vertex_colours on a recorded case ({} patches, {count} vertices): vertex {v} has colour {:?}, expected {e}",
                    patches.len(),
                    got.get(v)
                ));
            }
        }
    }
    let r = part_slot(Part::Vertices, p, &ctx.base);
    check_image(r.as_ref(), ctx, true, SNAPSHOT_SMOOTH)
}
