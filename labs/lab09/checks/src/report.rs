//! Lab 09's figures (the Week 10 report): the textured default scene read with nearest and
//! with bilinear lookups at pixel subdivisions 1 to 4 (a magnified cut-out of the ground near
//! the camera, where the texture is magnified), with the render times; the ground's texture
//! at frequency 1 against 10; and the three addressing modes on a letter, seen head on over
//! texture coordinates from −1 to 2.

use std::fmt::Write as _;
use std::sync::Arc;

use crate::checks::{GROUND_TEX_SCALE, textured_scene};
use contracts::lab09::{Addressing, TextureFilter};
use pipeline::Pipeline;
use raylab_core::Error;
use raylab_core::film::{Film, ToneMap};
use raylab_core::glam::Vec3;
use raylab_core::render::RenderSettings;
use raylab_core::scene::{
    CameraSetup, DirectionalLight, Light, Material, MaterialId, Mesh, Plane, Scene,
    SceneDescription, Texture,
};

use figures::{Figure, Panel, ReportContext, settings, timed};

/// The subdivisions of the side-by-side figures.
const SUBDIVISIONS: [u32; 4] = [1, 2, 3, 4];
/// The cut-out of the panels, as fractions of the image: left, top, width, height (the ground
/// in front of the torus and the red sphere, where a texel covers many pixels).
const CROP: [f32; 4] = [0.2, 0.72, 0.3, 0.26];
/// Magnification of the cut-out (nearest neighbour, so each pixel shows as a block).
const ZOOM: u32 = 3;
/// The texture frequencies of the scale figure: repeats per `GROUND_TEX_SCALE` metres.
const FREQUENCIES: [f32; 2] = [1.0, 10.0];

/// The figures of lab 09.
pub fn figures(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    Ok(vec![
        filter_panels(ctx, TextureFilter::Nearest)?,
        filter_panels(ctx, TextureFilter::Bilinear)?,
        scale_panels(ctx)?,
        addressing_panels(ctx)?,
    ])
}

fn subdivided(w: u32, h: u32, s: u32) -> RenderSettings {
    RenderSettings {
        pixel_subdivisions: s,
        ..settings(w, h, 1)
    }
}

/// The cut-out [`CROP`] of `film`, magnified [`ZOOM`] times.
fn crop_zoom(film: &Film) -> Film {
    figures::crop_zoom(film, CROP, ZOOM)
}

fn with_filter(ctx: &ReportContext, filter: TextureFilter) -> Pipeline {
    let mut pipeline = ctx.pipeline.clone();
    pipeline.texture_filter = filter;
    pipeline
}

fn filter_panels(ctx: &ReportContext, filter: TextureFilter) -> Result<Figure, Error> {
    let (w, h) = ctx.size(512, 384);
    let scene = textured_scene(1.0)?;
    let pipeline = with_filter(ctx, filter);
    let mut panels = Vec::new();
    let mut times = Vec::new();
    for s in SUBDIVISIONS {
        let (film, seconds) = ctx.render_timed(&scene, &pipeline, &subdivided(w, h, s))?;
        panels.push(Panel::new(
            crop_zoom(&film),
            timed(&format!("s = {s}"), seconds),
        ));
        times.push(seconds);
    }
    let name = match filter {
        TextureFilter::Nearest => "nearest",
        TextureFilter::Bilinear => "bilinear",
    };
    let file = format!("{name}-subdivisions-1-to-4.png");
    ctx.save_panels(&[panels], &file, ToneMap::default())?;
    let mut table = String::from(
        "| subdivision s | rays per pixel s² | render time (s) |\n| --- | --- | --- |\n",
    );
    for (s, t) in SUBDIVISIONS.iter().zip(&times) {
        let _ = writeln!(table, "| {s} | {} | {t:.3} |", s * s);
    }
    let (cw, ch) = ((CROP[2] * w as f32) as u32, (CROP[3] * h as f32) as u32);
    Ok(Figure {
        file,
        caption: format!(
            "The textured default scene with {name} texture lookups at pixel subdivision s = 1, 2, 3 and 4 (left to right)"
        ),
        parameters: format!(
            "each panel is a {cw}×{ch} cut-out of a {w}×{h} render (the ground in front of the torus, a 16×16-texel checkerboard repeated every {GROUND_TEX_SCALE} m), magnified {ZOOM}× with nearest-neighbour pixels; repeat addressing; seed 0, clamp tone map. Render time of each whole image:\n\n{table}\nAll four renders together"
        ),
        seconds: Some(times.iter().sum()),
    })
}

fn scale_panels(ctx: &ReportContext) -> Result<Figure, Error> {
    let (w, h) = ctx.size(384, 288);
    let pipeline = with_filter(ctx, TextureFilter::Bilinear);
    let mut panels = Vec::new();
    let mut seconds = 0.0;
    let mut lines = String::new();
    for f in FREQUENCIES {
        let scene = textured_scene(f)?;
        let (film, t) = ctx.render_timed(&scene, &pipeline, &subdivided(w, h, 2))?;
        panels.push(Panel::new(film, timed(&format!("frequency {f}"), t)));
        seconds += t;
        let _ = write!(
            lines,
            "{}tex_scale = {} m per repeat: {t:.3} s",
            if lines.is_empty() { "" } else { "; " },
            GROUND_TEX_SCALE / f
        );
    }
    let file = "texture-scale-1-and-10.png";
    ctx.save_panels(&[panels], file, ToneMap::default())?;
    Ok(Figure {
        file: file.into(),
        caption:
            "The ground's texture at frequency 1 (left) and 10 (right): ten times as many repeats"
                .into(),
        parameters: format!(
            "{w}×{h}, pixel subdivision 2, bilinear lookups, repeat addressing, seed 0, clamp tone map; {lines}. Ten times the frequency is a tenth of the plane's tex_scale (world units per repeat), as the Week 10 report's scale 10 multiplies the coordinates. Both renders together"
        ),
        seconds: Some(seconds),
    })
}

/// Texels per side of [`letter_texture`].
const LETTER_TEXELS: u32 = 16;
/// The texture coordinates the addressing figure shows: `[LOW, LOW + SPAN]` in u and v.
const LOW: f32 = -1.0;
const SPAN: f32 = 3.0;

/// A 16×16 texture that is upright only one way up and mirrored only one way round: a dark
/// red letter F on cream, with a blue left column and a green bottom row (the edges that clamp
/// stretches out to the left and downwards).
pub fn letter_texture() -> Texture {
    let (cream, red) = (Vec3::new(0.92, 0.88, 0.78), Vec3::new(0.6, 0.08, 0.08));
    let (blue, green) = (Vec3::new(0.15, 0.3, 0.85), Vec3::new(0.2, 0.65, 0.25));
    let n = LETTER_TEXELS;
    Texture::from_fn("<letter F>", n, n, |i, j| {
        let stem = (4..7).contains(&i) && (2..14).contains(&j);
        let top = (4..13).contains(&i) && (2..5).contains(&j);
        let middle = (4..11).contains(&i) && (7..10).contains(&j);
        if j == n - 1 {
            green
        } else if i == 0 {
            blue
        } else if stem || top || middle {
            red
        } else {
            cream
        }
    })
}

/// The letter on the plane `z = 0` seen head on: u along +x (to the right), v along +y (up),
/// one texture repeat per unit, the camera framing `[LOW, LOW + SPAN]²`; lit by a directional
/// light of irradiance π straight on, so a white surface's radiance is the texel.
pub fn letter_scene() -> Result<Scene, Error> {
    let mut material = Material::lambertian("letter", Vec3::ONE);
    material.diffuse_texture = Some(Arc::new(letter_texture()));
    let mut plane = Plane::new(Vec3::ZERO, Vec3::Z, MaterialId(0));
    plane.tangent = Vec3::X;
    plane.bitangent = Vec3::Y;
    plane.tex_scale = 1.0;
    let centre = LOW + 0.5 * SPAN;
    // The image plane is one unit high at the focal distance: SPAN units at SPAN times it.
    let focal_distance = 1.0;
    Scene::new(SceneDescription {
        name: "a letter seen head on".into(),
        camera: Some(CameraSetup {
            eye: Vec3::new(centre, centre, SPAN * focal_distance),
            look_at: Vec3::new(centre, centre, 0.0),
            up: Vec3::Y,
            focal_distance,
        }),
        materials: vec![material],
        lights: vec![Light::Directional(DirectionalLight {
            direction: Vec3::NEG_Z,
            emission: Vec3::splat(std::f32::consts::PI),
        })],
        planes: vec![plane],
        mesh: Mesh::default(),
        ..SceneDescription::default()
    })
}

/// Draws the outline of the texture's own square `[0, 1]²` into a render of [`letter_scene`]
/// (black, one pixel wide, dashed so that the texels under it stay visible).
fn outline_unit_square(film: &mut Film) {
    let (w, h) = (film.width, film.height);
    let at = |t: f32, n: u32| ((t - LOW) / SPAN * n as f32).round() as i64;
    let (x0, x1) = (at(0.0, w), at(1.0, w));
    let (y0, y1) = (h as i64 - at(1.0, h), h as i64 - at(0.0, h));
    let mut dot = |x: i64, y: i64| {
        if (0..w as i64).contains(&x) && (0..h as i64).contains(&y) && (x + y) % 6 < 3 {
            film.set(x as u32, y as u32, Vec3::ZERO);
        }
    };
    for x in x0..=x1 {
        dot(x, y0);
        dot(x, y1);
    }
    for y in y0..=y1 {
        dot(x0, y);
        dot(x1, y);
    }
}

fn addressing_panels(ctx: &ReportContext) -> Result<Figure, Error> {
    let (w, h) = ctx.size(240, 240);
    let scene = letter_scene()?;
    let mut rows = Vec::new();
    let mut seconds = 0.0;
    for filter in [TextureFilter::Nearest, TextureFilter::Bilinear] {
        let mut row = Vec::new();
        for mode in Addressing::ALL {
            let pipeline = {
                let mut pipeline = with_filter(ctx, filter);
                pipeline.texture_addressing = mode;
                pipeline
            };
            let (mut film, t) = ctx.render_timed(&scene, &pipeline, &subdivided(w, h, 2))?;
            outline_unit_square(&mut film);
            row.push(Panel::new(film, timed(&format!("{mode:?}, {filter:?}"), t)));
            seconds += t;
        }
        rows.push(row);
    }
    let file = "addressing-modes.png";
    ctx.save_panels(&rows, file, ToneMap::default())?;
    Ok(Figure {
        file: file.into(),
        caption: "Repeat, mirror and clamp addressing (left to right) of a letter F, with nearest (top) and bilinear (bottom) lookups, over texture coordinates from −1 to 2".into(),
        parameters: format!(
            "a {LETTER_TEXELS}×{LETTER_TEXELS}-texel letter F (dark red on cream, its left column blue and its bottom row green) on a plane seen head on, u to the right and v up, one repeat per unit; the dashed square is the texture's own [0, 1]², where every mode shows the letter upright; {w}×{h}, pixel subdivision 2, seed 0, clamp tone map. Repeat tiles the letter unchanged; mirror flips every other copy about the edge it shares with the next (the blue columns meet at u = 0, the green rows at v = 0); clamp stretches the edge texels out to infinity: the blue column to the left, the green row below, and each corner texel over its quadrant. All six renders together"
        ),
        seconds: Some(seconds),
    })
}

/// Makes the lab's report: its figures through `pipeline` (`raylab report`).
pub fn make(
    job: &pipeline::job::ReportJob,
    pipeline: pipeline::Pipeline,
) -> Result<(), raylab_core::Error> {
    figures::make(job, crate::checks::LAB, pipeline, figures)
}
