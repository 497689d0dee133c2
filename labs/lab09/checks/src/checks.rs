//! Lab 09's exercises and their checks (docs/lab09.md, "What the checks check").
//!
//! Every exercise is checked by relations its answer satisfies whatever it is, by the answer
//! key's results on random inputs where the key is present, by recorded golden cases, and by a
//! render of the textured default scene ([`textured_scene`]) with the student's function in
//! its slot and the base's everywhere else, compared with a snapshot:
//!
//! - 9.1 `plane_texcoord`: points built as `−d·n + a·t + b·b̂` on planes of every orientation,
//!   with the tangent frame turned about the normal, `tex_scale` from 10⁻³ to 10³ and the plane
//!   up to 10³ from the origin, must give `(a, b)/tex_scale`;
//! - 9.2 `sphere_texcoord`: for directions all over the sphere (poles and seam too), spheres of
//!   radius 10⁻⁴ to 10³ up to 10³ radii from the origin, `(u, v)` lies in `[0, 1]²` and turns
//!   back into the direction (the round trip through the parameterization of the contract);
//! - 9.3 `triangle_texcoord`: the vertices' own coordinates at the corners, affine in the
//!   barycentrics (the midpoint of two points maps to the midpoint of their coordinates), and
//!   moving with the vertices' coordinates;
//! - 9.4 `address`: in `[0, 1]` and the identity on `[0, 1)`; repeat periodic with period 1,
//!   mirror symmetric about every integer and periodic with period 2, clamp constant outside,
//!   for coordinates from −10³ to 10³ and next to integers;
//! - 9.5 `sample_nearest`: first the edge texels where `address` gives exactly 0 or 1 (before
//!   anything can index past the texture), then the texel whose centre is closest to the
//!   addressed point (found by searching every texel), for every addressing mode and for an
//!   arbitrary corresponder (so the lookup must go through `address`); a wrong texel is
//!   compared with what each usual slip would read;
//! - 9.6 `sample_bilinear`: the texel itself at its centre; an affine function of `(u, v)`
//!   sampled at the texel centres reproduced exactly between them; continuity across texel
//!   edges, texel centres and the repeat seam (a bound on the change over a 10⁻³-texel step);
//!   periodic, mirrored or clamped as the mode says; within the range of the texels. A failure
//!   names the slip the lookup makes on a probe of texel-centre coordinates.

use contracts::lab09::Texturing;
use grading::Exercise;

mod address;
mod bilinear;
mod mapping;
mod nearest;
mod scene;

pub use address::{AddressInput, address_input};
pub use bilinear::{CONTINUITY_STEP_TEXELS, ContinuityInput, continuity_input};
pub use mapping::{
    PlaneInput, SphereInput, TriangleInput, direction_of, plane_case, plane_input, sphere_case,
    sphere_input, triangle_input,
};
pub use nearest::closest_texel;
pub use scene::{
    GROUND_TEX_SCALE, SNAPSHOT_SETTINGS, TextureCase, addressing, part_pipeline, random_texture,
    render_textured, snapshot_of, texcoords, texel_centre, texture_case, textured_scene,
};

use address::exercise_9_4;
use bilinear::exercise_9_6;
use mapping::{exercise_9_1, exercise_9_2, exercise_9_3};
use nearest::exercise_9_5;

/// Golden file of Exercise 9.1: plane, position → texture coordinates.
pub const GOLDEN_PLANE: &str = "plane_texcoord.json";
/// Golden file of Exercise 9.2: sphere, position → texture coordinates.
pub const GOLDEN_SPHERE: &str = "sphere_texcoord.json";
/// Golden file of Exercise 9.3: vertex coordinates, barycentrics → texture coordinates.
pub const GOLDEN_TRIANGLE: &str = "triangle_texcoord.json";
/// Golden file of Exercise 9.4: coordinate, mode → addressed coordinate.
pub const GOLDEN_ADDRESS: &str = "address.json";
/// Golden file of Exercise 9.5: texture, coordinates, mode → texel.
pub const GOLDEN_NEAREST: &str = "sample_nearest.json";
/// Golden file of Exercise 9.6: texture, coordinates, mode → colour.
pub const GOLDEN_BILINEAR: &str = "sample_bilinear.json";
/// Snapshot of the textured scene read with nearest lookups.
pub const SNAPSHOT_NEAREST: &str = "textured-nearest";
/// Snapshot of the textured scene read with bilinear lookups.
pub const SNAPSHOT_BILINEAR: &str = "textured-bilinear";

/// This lab.
pub const LAB: course::LabId = course::LabId::of(9);

/// The exercises of lab 09 (`labs/lab09/exercises.toml`), each with its check.
pub fn exercises() -> Vec<Exercise<dyn Texturing>> {
    grading::exercises(
        LAB,
        grading::checks![
            exercise_9_1,
            exercise_9_2,
            exercise_9_3,
            exercise_9_4,
            exercise_9_5,
            exercise_9_6
        ],
    )
}

/// Which student function a render exercises; the others come from the base.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// Exercise 9.1.
    Plane,
    /// Exercise 9.2.
    Sphere,
    /// Exercise 9.3.
    Triangle,
    /// Exercise 9.4.
    Address,
    /// Exercise 9.5.
    Nearest,
    /// Exercise 9.6.
    Bilinear,
}

impl Part {
    /// The contract method whose code this part is (the student's in a [`PartSlot`](pipeline::PartSlot)).
    pub fn function(self) -> &'static str {
        match self {
            Part::Plane => "plane_texcoord",
            Part::Sphere => "sphere_texcoord",
            Part::Triangle => "triangle_texcoord",
            Part::Address => "address",
            Part::Nearest => "sample_nearest",
            Part::Bilinear => "sample_bilinear",
        }
    }
}
