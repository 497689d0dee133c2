//! The course's labs: the one list of them ([`COURSE`]), and per lab its checks (the exercise
//! table and one check per exercise) and the generator of its golden data. The contracts the
//! checks test are in [`crate::contracts`].

pub mod lab01;
pub mod lab02;
pub mod lab03;
pub mod lab04;
pub mod lab05;
pub mod lab06;
pub mod lab07;
pub mod lab08;
pub mod lab09;
pub mod lab10;
pub mod lab11;
pub mod strategies;

use crate::grading::{DeniedItem, ExerciseInfo};

/// One lab of the course, as the framework knows it.
#[derive(Clone, Copy, Debug)]
pub struct Lab {
    /// Its number: the crate is `labs/labNN`, the docs `docs/labNN.md`.
    pub number: u32,
    /// Its title.
    pub title: &'static str,
    /// Its exercises, in order, without their checks.
    pub exercises: fn() -> Vec<ExerciseInfo>,
    /// The framework items that answer its exercises (see [`DeniedItem`]): a submission whose
    /// code for the lab names one gets no points for those exercises.
    pub denied: &'static [DeniedItem],
}

/// The labs of the course, in order: the one list the command line, the reference's key, the
/// grader and the docs index take the labs from.
pub const COURSE: &[Lab] = &[
    Lab {
        number: 1,
        title: "Camera rays and the image loop",
        exercises: || infos(1, &lab01::checks::exercises()),
        denied: LAB01_DENIED,
    },
    Lab {
        number: 2,
        title: "Intersections and Lambertian shading",
        exercises: || infos(2, &lab02::checks::exercises()),
        denied: LAB02_DENIED,
    },
    Lab {
        number: 3,
        title: "Shadows and area lights",
        exercises: || infos(3, &lab03::checks::exercises()),
        denied: &[],
    },
    Lab {
        number: 4,
        title: "Reflection, refraction and Phong",
        exercises: || infos(4, &lab04::checks::exercises()),
        denied: LAB04_DENIED,
    },
    Lab {
        number: 5,
        title: "Radiometry",
        exercises: || infos(5, &lab05::checks::exercises()),
        denied: LAB05_DENIED,
    },
    Lab {
        number: 6,
        title: "Radiosity with the hemicube",
        exercises: || infos(6, &lab06::checks::exercises()),
        denied: &[],
    },
    Lab {
        number: 7,
        title: "Anti-aliasing",
        exercises: || infos(7, &lab07::checks::exercises()),
        denied: &[],
    },
    Lab {
        number: 8,
        title: "Photon-mapped caustics",
        exercises: || infos(8, &lab08::checks::exercises()),
        denied: &[],
    },
    Lab {
        number: 9,
        title: "Texture mapping",
        exercises: || infos(9, &lab09::checks::exercises()),
        denied: LAB09_DENIED,
    },
    Lab {
        number: 10,
        title: "Fresnel reflectance and absorption",
        exercises: || infos(10, &lab10::checks::exercises()),
        denied: LAB10_DENIED,
    },
    Lab {
        number: 11,
        title: "Ambient occlusion and HDR light probes",
        exercises: || infos(11, &lab11::checks::exercises()),
        denied: &[],
    },
];

/// glam's vectors reflect and refract about a normal; the names are also the contract's own
/// methods, so only a call on another receiver or path counts.
const LAB04_DENIED: &[DeniedItem] = &[
    DeniedItem {
        name: "reflect",
        own: &["self", "Self", "Reflection"],
        exercises: &["4.1"],
        computes: "glam's reflection of a direction about a normal",
    },
    DeniedItem {
        name: "refract",
        own: &["self", "Self", "Reflection"],
        exercises: &["4.4"],
        computes: "glam's refraction of a direction through a surface",
    },
];

/// Lab 10's checks find the transmitted cosine that goes with a cosine of incidence (Snell's
/// law, through a lab 04 `refract`): the first step of Exercise 10.4.
const LAB10_DENIED: &[DeniedItem] = &[
    DeniedItem {
        name: "transmitted_cosine",
        own: &[],
        exercises: &["10.4"],
        computes: "the checks' cosine of the transmitted ray by Snell's law",
    },
    DeniedItem {
        name: "pair_of",
        own: &[],
        exercises: &["10.4"],
        computes: "the checks' pair of cosines of incidence and transmission by Snell's law",
    },
];

/// Lab 03's closed forms of the irradiance from a polygonal light answer the Monte Carlo
/// exercises without sampling.
const LAB05_DENIED: &[DeniedItem] = &[
    DeniedItem {
        name: "irradiance_polygon",
        own: &[],
        exercises: &["5.8", "5.9"],
        computes: "the framework's exact irradiance from a Lambertian polygon (Lambert's formula)",
    },
    DeniedItem {
        name: "irradiance_parallel_rectangle",
        own: &[],
        exercises: &["5.8", "5.9"],
        computes: "the framework's exact irradiance from a rectangle parallel to the receiver",
    },
    DeniedItem {
        name: "form_factor_parallel_corner",
        own: &[],
        exercises: &["5.8", "5.9"],
        computes: "the framework's point-to-rectangle form factor",
    },
];

/// The numbers of the labs of [`COURSE`], in order.
pub const NUMBERS: [u32; COURSE.len()] = {
    let mut numbers = [0; COURSE.len()];
    let mut i = 0;
    while i < COURSE.len() {
        numbers[i] = COURSE[i].number;
        i += 1;
    }
    numbers
};

/// The last lab of the course: `raylab render` turns on every lab up to it.
pub const LAST_LAB: u32 = NUMBERS[NUMBERS.len() - 1];

/// The lab numbered `number`, if the course has one.
pub fn lab(number: u32) -> Option<&'static Lab> {
    COURSE.iter().find(|l| l.number == number)
}

/// The exercises of lab `lab`, in order, or `None` for a lab the framework does not know.
pub fn exercise_infos(lab: u32) -> Option<Vec<ExerciseInfo>> {
    self::lab(lab).map(|l| (l.exercises)())
}

/// The framework items that answer exercises of lab `lab` (none for a lab the course does not
/// have).
pub fn denied_items(lab: u32) -> &'static [DeniedItem] {
    self::lab(lab).map_or(&[], |l| l.denied)
}

/// The exercise table without the checks.
fn infos<S: ?Sized>(lab: u32, exercises: &[crate::grading::Exercise<S>]) -> Vec<ExerciseInfo> {
    exercises.iter().map(|e| e.info(lab)).collect()
}

/// glam's view matrices hold the camera's orthonormal basis.
const LAB01_DENIED: &[DeniedItem] = &[
    DeniedItem {
        name: "look_at_rh",
        own: &[],
        exercises: &["1.2"],
        computes: "glam's view matrix, whose rows are the camera basis",
    },
    DeniedItem {
        name: "look_at_lh",
        own: &[],
        exercises: &["1.2"],
        computes: "glam's view matrix, whose rows are the camera basis",
    },
    DeniedItem {
        name: "look_to_rh",
        own: &[],
        exercises: &["1.2"],
        computes: "glam's view matrix, whose rows are the camera basis",
    },
    DeniedItem {
        name: "look_to_lh",
        own: &[],
        exercises: &["1.2"],
        computes: "glam's view matrix, whose rows are the camera basis",
    },
];

/// The scene's own ray queries answer the intersection exercises for a one-shape scene.
const LAB02_DENIED: &[DeniedItem] = &[
    DeniedItem {
        name: "trace_to_closest",
        own: &[],
        exercises: &["2.1", "2.2", "2.3"],
        computes: "the framework's closest hit of a ray with a scene's planes, triangles and spheres",
    },
    DeniedItem {
        name: "trace_to_any",
        own: &[],
        exercises: &["2.1", "2.2", "2.3"],
        computes: "the framework's test of whether a ray hits any of a scene's planes, triangles and spheres",
    },
    DeniedItem {
        name: "closest_hit_watertight",
        own: &[],
        exercises: &["2.2"],
        computes: "the framework's closest hit of a ray among triangles, by its own watertight test",
    },
    DeniedItem {
        name: "any_hit_watertight",
        own: &[],
        exercises: &["2.2"],
        computes: "the framework's any hit of a ray among triangles, by its own watertight test",
    },
    DeniedItem {
        name: "TriangleRay",
        own: &[],
        exercises: &["2.2"],
        computes: "the framework's own watertight ray-triangle test",
    },
];

/// glam's GLSL-style fractional part is the repeat corresponder.
const LAB09_DENIED: &[DeniedItem] = &[DeniedItem {
    name: "fract_gl",
    own: &[],
    exercises: &["9.4"],
    computes: "glam's fractional part x − ⌊x⌋ (the repeat corresponder)",
}];
