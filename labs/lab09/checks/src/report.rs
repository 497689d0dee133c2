//! Lab 09's figures (the Week 10 report): the textured default scene read with nearest and
//! with bilinear lookups at pixel subdivisions 1 to 4 (a magnified cut-out of the ground near
//! the camera, where the texture is magnified), with the render times, and the ground's
//! texture at frequency 1 against 10.

use std::fmt::Write as _;

use crate::checks::{GROUND_TEX_SCALE, textured_scene};
use contracts::lab09::TextureFilter;
use pipeline::Pipeline;
use raylab_core::Error;
use raylab_core::film::{Film, ToneMap};
use raylab_core::render::RenderSettings;

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
    Pipeline {
        texture_filter: filter,
        ..ctx.pipeline.clone()
    }
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

/// Makes the lab's report: its figures through `pipeline` (`raylab report`).
pub fn make(
    job: &grading::task::ReportJob,
    pipeline: pipeline::Pipeline,
) -> Result<(), raylab_core::Error> {
    figures::make(job, crate::checks::LAB, pipeline, figures)
}
