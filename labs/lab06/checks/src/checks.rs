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
//!   (`shoot::diagnose_shoot`): what a receiver gets halves with its area, doubles with the
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

use contracts::lab06::Radiosity;
use grading::{Exercise, GoldenFile, LabContext};
use pipeline::{PartSlot, Pipeline};

mod accumulate;
mod colours;
mod hemicube;
mod point_form_factor;
mod scenes;
mod shoot;
mod shooter;

pub use accumulate::{AccumulateInput, accumulate_input, area_bound};
pub use colours::{VerticesInput, colours_input, vertices_input};
pub use hemicube::{
    CLOSED_FORM_RESOLUTIONS, DeltaInput, SUM_RESOLUTIONS, element_bound, side_input, sum_bound,
    top_input,
};
pub use point_form_factor::{PointInput, point_input};
pub use scenes::{
    SNAPSHOT_MESHING, SNAPSHOT_SIZE, SNAPSHOT_SOLVE, SNAPSHOT_TOLERANCE, closed_box, cornell_image,
    grid, join, quad_patch, snapshot_mesh,
};
pub use shoot::{ShootInput, diagnosis_input, shoot_input};
pub use shooter::{ShooterInput, shooter_input};

use accumulate::exercise_6_4;
use colours::{exercise_6_7, exercise_6_8};
use hemicube::{exercise_6_2, exercise_6_3};
use point_form_factor::exercise_6_1;
use shoot::exercise_6_6;
use shooter::exercise_6_5;

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
