//! The meshes the checks solve: quads, grids, closed boxes and the Cornell box of the snapshots.

use glam::Vec3;

use contracts::lab06::Radiosity;
use grading::{LabContext, PixelTolerance};
use pipeline::Pipeline;
use pipeline::radiosity::solver::{FormFactors, Shading, SolveSettings, render_solution, solve};
use pipeline::radiosity::{MeshingOptions, Patch, PatchMesh};
use raylab_core::film::Film;
use raylab_core::scene::builtin_scene;

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

pub(super) fn check_image(
    r: &dyn Radiosity,
    ctx: &LabContext,
    smooth: bool,
    name: &str,
) -> Result<(), String> {
    let film = cornell_image(r, &ctx.base, smooth).map_err(|e| e.to_string())?;
    ctx.check_snapshot(name, &film, &SNAPSHOT_TOLERANCE)
}
