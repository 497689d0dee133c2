//! The pipelines, random textures and textured scene the checks render and sample.

use std::sync::Arc;

use glam::{Vec2, Vec3};
use proptest::prelude::*;

use contracts::lab09::{Addressing, TextureFilter, Texturing};
use grading::{LabContext, PixelTolerance};
use pipeline::render::render;
use pipeline::{Pipeline, View};
use raylab_core::film::Film;
use raylab_core::render::RenderSettings;
use raylab_core::sampling::Rng;
use raylab_core::scene::{Scene, Texture, builtin_scene};

use super::{Part, SNAPSHOT_BILINEAR, SNAPSHOT_NEAREST};

/// Size, sampling and seed of lab 09's snapshots.
pub const SNAPSHOT_SETTINGS: RenderSettings = RenderSettings::snapshot(9);
/// World units per repeat of the ground's texture in [`textured_scene`] at scale 1.
pub const GROUND_TEX_SCALE: f32 = 2.0;

/// The pipeline of one part's renders: `student` for that part only, `base` for the rest,
/// shaded, at lab 9, reading textures with `filter`.
pub fn part_pipeline(
    part: Part,
    student: &Arc<dyn Texturing>,
    base: &Pipeline,
    filter: TextureFilter,
) -> Pipeline {
    let mut pipeline = base.with_student_function(part.function(), student);
    pipeline.view = View::Shaded;
    pipeline.texture_filter = filter;
    pipeline
}

/// The default scene with generated textures (no file needed): a checkerboard on the ground
/// (one repeat per `GROUND_TEX_SCALE / tex_frequency` metres), a red-and-white checkerboard
/// on the red sphere (spherical coordinates), a colour gradient on the torus (its OBJ's
/// texture coordinates), under the scene's lights.
pub fn textured_scene(tex_frequency: f32) -> Result<Scene, raylab_core::Error> {
    let mut scene = builtin_scene("default")?;
    let ground = Texture::checkerboard(8, 2, Vec3::splat(0.95), Vec3::new(0.15, 0.2, 0.3));
    let red = Texture::checkerboard(8, 1, Vec3::new(0.9, 0.1, 0.1), Vec3::splat(0.9));
    let gradient = Texture::gradient(8, 8);
    let by_name = |scene: &Scene, name: &str| scene.materials.iter().position(|m| m.name == name);
    for (name, texture, diffuse) in [
        ("ground", ground, Vec3::ONE),
        ("red", red, Vec3::ONE),
        ("gold", gradient, Vec3::new(1.0, 0.85, 0.6)),
    ] {
        let Some(i) = by_name(&scene, name) else {
            return Err(raylab_core::Error::Failed {
                what: format!("the default scene's material '{name}'"),
                reason: "lab 09's textured scene puts a texture on it; it is not in the scene"
                    .into(),
            });
        };
        scene.materials[i].diffuse = diffuse;
        scene.materials[i].diffuse_texture = Some(Arc::new(texture));
    }
    for plane in &mut scene.planes {
        plane.tex_scale = GROUND_TEX_SCALE / tex_frequency;
    }
    scene.name = "default (textured)".into();
    Ok(scene)
}

/// Renders the textured scene at the snapshot size (texture frequency 1).
pub fn render_textured(pipeline: &Pipeline) -> Result<Film, raylab_core::Error> {
    render(&textured_scene(1.0)?, pipeline, &SNAPSHOT_SETTINGS)
}

/// The snapshot a part's render is compared with: nearest lookups for Exercise 9.5, bilinear
/// for the others.
pub fn snapshot_of(part: Part) -> (&'static str, TextureFilter) {
    match part {
        Part::Nearest => (SNAPSHOT_NEAREST, TextureFilter::Nearest),
        _ => (SNAPSHOT_BILINEAR, TextureFilter::Bilinear),
    }
}

/// Renders the textured scene with the student's `part` and compares it with its snapshot.
pub(super) fn check_render(
    p: &Arc<dyn Texturing>,
    part: Part,
    ctx: &LabContext,
) -> Result<(), String> {
    let (name, filter) = snapshot_of(part);
    let film =
        render_textured(&part_pipeline(part, p, &ctx.base, filter)).map_err(|e| e.to_string())?;
    let tol = PixelTolerance {
        abs: 2e-3,
        rel: 2e-3,
        max_outlier_fraction: 0.01,
    };
    ctx.check_snapshot(name, &film, &tol)
}

/// A texture case: width, height and the seed of its random texels.
pub type TextureCase = (u32, u32, u64);

/// A `width × height` texture of random texels in `[0, 1)³` from `seed`.
pub fn random_texture((width, height, seed): TextureCase) -> Texture {
    let mut rng = Rng::new(seed, 9);
    let texels: Vec<Vec3> = (0..width.max(1) * height.max(1))
        .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()))
        .collect();
    let w = width.max(1);
    Texture::from_fn(
        &format!("<random {width}×{height} #{seed}>"),
        width,
        height,
        |i, j| texels[(j * w + i) as usize],
    )
}

/// A texture case from 1×1 to 16×12.
pub fn texture_case() -> impl Strategy<Value = TextureCase> + Clone {
    (1u32..=16, 1u32..=12, any::<u64>())
}

/// An addressing mode.
pub fn addressing() -> impl Strategy<Value = Addressing> + Clone {
    prop::sample::select(Addressing::ALL.to_vec())
}

/// Texture coordinates: mostly in `[−3, 3]²`, some up to ±10³.
pub fn texcoords() -> impl Strategy<Value = Vec2> + Clone {
    prop_oneof![
        4 => (-3.0f32..3.0, -3.0f32..3.0).prop_map(|(u, v)| Vec2::new(u, v)),
        1 => (-1e3f32..1e3, -1e3f32..1e3).prop_map(|(u, v)| Vec2::new(u, v)),
    ]
}

/// Names a texel for messages.
pub(super) fn texel_name(i: u32, j: u32) -> String {
    format!("(column {i}, row {j} from the top)")
}

/// Where `colour` is in `texture`, if it is one of its texels.
pub(super) fn find_texel(texture: &Texture, colour: Vec3) -> Option<(u32, u32)> {
    (0..texture.height)
        .flat_map(|j| (0..texture.width).map(move |i| (i, j)))
        .find(|&(i, j)| texture.texel(i, j) == colour)
}

/// The centre of texel `(i, j)` in texture space.
pub fn texel_centre(texture: &Texture, i: u32, j: u32) -> Vec2 {
    Vec2::new(
        (i as f32 + 0.5) / texture.width as f32,
        1.0 - (j as f32 + 0.5) / texture.height as f32,
    )
}
