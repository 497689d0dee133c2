//! Progressive refinement (Cohen, Chen, Wallace and Greenberg 1988) and the images of a
//! solution. The loop and the images are the framework's; every formula in them is a call of
//! the lab's contract ([`Radiosity`]), so a solution shows the student's code at work.

use std::time::{Duration, Instant};

use glam::{UVec2, Vec2, Vec3};
use rayon::prelude::*;

use crate::Pipeline;
use contracts::lab06::Radiosity;
use raylab_core::film::Film;
use raylab_core::scene::Scene;

use super::{DeltaFormFactors, PatchMesh};

/// How the shooter's form factors are found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FormFactors {
    /// The point-to-patch formula to every patch (Exercise 6.1): no occlusion.
    Analytic,
    /// A hemicube of this resolution (Exercises 6.2–6.4): occlusion included.
    Hemicube(u32),
}

/// When progressive refinement stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveSettings {
    /// How the form factors are found.
    pub form_factors: FormFactors,
    /// Stop when the unshot power is below this fraction of the emitted power.
    pub threshold: f64,
    /// Stop after this many shots in any case.
    pub max_shots: usize,
}

/// A solution of progressive refinement.
#[derive(Clone, Debug)]
pub struct Solution {
    /// Radiosity `B` of every patch.
    pub radiosity: Vec<Vec3>,
    /// Unshot radiosity `ΔB` of every patch.
    pub unshot: Vec<Vec3>,
    /// The unshot power as a fraction of the emitted power: before the first shot, then
    /// after each shot.
    pub unshot_fraction: Vec<f64>,
    /// Time spent finding form factors (item buffers and their accumulation, or the analytic
    /// formula).
    pub form_factor_time: Duration,
    /// Time spent choosing shooters and shooting.
    pub shoot_time: Duration,
}

impl Solution {
    /// Number of shots made.
    pub fn shots(&self) -> usize {
        self.unshot_fraction.len() - 1
    }
}

/// The unshot power of `unshot` over the emitted power of `mesh` (0 for a mesh that emits
/// nothing).
pub fn unshot_fraction(mesh: &PatchMesh, unshot: &[Vec3]) -> f64 {
    let emitted = mesh.power(&mesh.emission());
    if emitted > 0.0 {
        mesh.power(unshot) / emitted
    } else {
        0.0
    }
}

/// The form factors from patch `shooter` to every patch of `mesh`, through `radiosity`:
/// with the hemicube, `delta` must be tabulated at its resolution.
pub fn form_factors(
    radiosity: &dyn Radiosity,
    mesh: &PatchMesh,
    shooter: usize,
    method: FormFactors,
    delta: Option<&DeltaFormFactors>,
) -> Vec<f32> {
    let n = mesh.patches.len();
    match (method, delta) {
        (FormFactors::Hemicube(res), Some(delta)) => {
            let items = super::item_buffer(mesh, shooter, res);
            radiosity.accumulate_form_factors(&items, delta, n)
        }
        (FormFactors::Hemicube(res), None) => {
            let delta = DeltaFormFactors::tabulate(radiosity, res);
            form_factors(radiosity, mesh, shooter, method, Some(&delta))
        }
        (FormFactors::Analytic, _) => {
            let s = &mesh.patches[shooter];
            mesh.patches
                .par_iter()
                .enumerate()
                .map(|(j, p)| {
                    if j == shooter {
                        0.0
                    } else {
                        radiosity.point_form_factor(s.centre, s.normal, p.centre, p.normal, p.area)
                    }
                })
                .collect()
        }
    }
}

/// Progressive refinement on `mesh` with `radiosity`'s code for every step: from `B = ΔB = E`,
/// shoot from the patch `select_shooter` picks until the unshot power falls below the
/// threshold or the shots run out.
pub fn solve(radiosity: &dyn Radiosity, mesh: &PatchMesh, settings: &SolveSettings) -> Solution {
    let mut b = mesh.emission();
    let mut unshot = b.clone();
    let mut fractions = vec![unshot_fraction(mesh, &unshot)];
    let delta = match settings.form_factors {
        FormFactors::Hemicube(res) => Some(DeltaFormFactors::tabulate(radiosity, res)),
        FormFactors::Analytic => None,
    };
    let (mut ff_time, mut shoot_time) = (Duration::ZERO, Duration::ZERO);
    while fractions.len() <= settings.max_shots
        && *fractions.last().expect("one entry") > settings.threshold
    {
        let start = Instant::now();
        let Some(shooter) = radiosity.select_shooter(&mesh.patches, &unshot) else {
            break;
        };
        shoot_time += start.elapsed();
        let start = Instant::now();
        let f = form_factors(
            radiosity,
            mesh,
            shooter,
            settings.form_factors,
            delta.as_ref(),
        );
        ff_time += start.elapsed();
        let start = Instant::now();
        radiosity.shoot(&mesh.patches, &f, shooter, &mut b, &mut unshot);
        shoot_time += start.elapsed();
        fractions.push(unshot_fraction(mesh, &unshot));
    }
    Solution {
        radiosity: b,
        unshot,
        unshot_fraction: fractions,
        form_factor_time: ff_time,
        shoot_time,
    }
}

/// How a solution's image colours a patch.
#[derive(Clone, Copy, Debug)]
pub enum Shading<'a> {
    /// One colour per patch (flat patches).
    Flat(&'a [Vec3]),
    /// One colour per vertex, interpolated across each patch's triangles (Gouraud).
    Smooth(&'a [Vec3]),
}

/// The patched mesh seen from `scene`'s camera at `width × height`, one ray through each pixel
/// centre (the camera of `pipeline`'s lab 01 slot), each hit coloured by `shading`; black where
/// no patch is.
pub fn render_solution(
    pipeline: &Pipeline,
    scene: &Scene,
    mesh: &PatchMesh,
    shading: Shading<'_>,
    width: u32,
    height: u32,
) -> Film {
    let camera = pipeline.prepare_camera(scene, UVec2::new(width, height));
    let pixels: Vec<Vec3> = (0..width * height)
        .into_par_iter()
        .map(|k| {
            let raster = Vec2::new((k % width) as f32 + 0.5, (k / width) as f32 + 0.5);
            let ray = pipeline.camera_ray(&camera, raster);
            match mesh.closest_patch(&ray) {
                None => scene.background,
                Some(hit) => match shading {
                    Shading::Flat(colours) => colours[hit.patch as usize],
                    Shading::Smooth(colours) => {
                        let [a, b, c] = hit.corners.map(|v| colours[v as usize]);
                        hit.weights.x * a + hit.weights.y * b + hit.weights.z * c
                    }
                },
            }
        })
        .collect();
    Film {
        width,
        height,
        pixels,
    }
}
