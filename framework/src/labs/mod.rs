//! The lab contracts: one module per lab with the traits a student implements, the lab's
//! checks, and the generator of its golden data. The renderer reaches student code only
//! through these traits, composed in a [`Pipeline`](crate::pipeline::Pipeline).

pub mod lab01;
pub mod lab02;
pub mod lab03;
pub mod lab04;
pub mod lab07;
pub mod strategies;

use crate::grading::{DeniedItem, ExerciseInfo};

/// Every lab the framework knows, with its title.
pub const LABS: &[(u32, &str)] = &[
    (1, "Camera rays and the image loop"),
    (2, "Intersections and Lambertian shading"),
    (3, "Shadows and area lights"),
    (4, "Reflection, refraction and Phong"),
    (7, "Anti-aliasing"),
];

/// The exercises of lab `lab`, in order, or `None` for a lab the framework does not know.
pub fn exercise_infos(lab: u32) -> Option<Vec<ExerciseInfo>> {
    fn infos<S: ?Sized>(lab: u32, exercises: &[crate::grading::Exercise<S>]) -> Vec<ExerciseInfo> {
        exercises.iter().map(|e| e.info(lab)).collect()
    }
    Some(match lab {
        1 => infos(lab, &lab01::checks::exercises()),
        2 => infos(lab, &lab02::checks::exercises()),
        3 => infos(lab, &lab03::checks::exercises()),
        4 => infos(lab, &lab04::checks::exercises()),
        7 => infos(lab, &lab07::checks::exercises()),
        _ => return None,
    })
}

/// The framework items that answer exercises of lab `lab` (see [`DeniedItem`]): a submission
/// whose code for that lab names one gets no points for those exercises.
pub fn denied_items(lab: u32) -> &'static [DeniedItem] {
    match lab {
        2 => LAB02_DENIED,
        _ => &[],
    }
}

/// The scene's own ray queries answer the intersection exercises for a one-shape scene.
const LAB02_DENIED: &[DeniedItem] = &[
    DeniedItem {
        name: "trace_to_closest",
        exercises: &["2.1", "2.2", "2.3"],
        computes: "closest hit of a ray with a scene's planes, triangles and spheres",
    },
    DeniedItem {
        name: "trace_to_any",
        exercises: &["2.1", "2.2", "2.3"],
        computes: "test of whether a ray hits any of a scene's planes, triangles and spheres",
    },
    DeniedItem {
        name: "BuiltinIntersection",
        exercises: &["2.1", "2.2", "2.3"],
        computes: "own ray-plane, ray-triangle and ray-sphere tests",
    },
    DeniedItem {
        name: "closest_hit_watertight",
        exercises: &["2.2"],
        computes: "closest hit of a ray among triangles, by its own watertight test",
    },
    DeniedItem {
        name: "any_hit_watertight",
        exercises: &["2.2"],
        computes: "any hit of a ray among triangles, by its own watertight test",
    },
    DeniedItem {
        name: "TriangleRay",
        exercises: &["2.2"],
        computes: "own watertight ray-triangle test",
    },
];
