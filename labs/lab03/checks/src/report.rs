//! Lab 03's figures: hard shadows from the point light, soft shadows from the area light, the
//! penumbra as the number of light samples grows with the render times (ELUMI Fig. 4.8 and
//! Table 4.1), and the penumbra of a grid of cell centres against jittered samples (ELUMI
//! Fig. 4.5).

use std::fmt::Write as _;
use std::sync::Arc;

use crate::checks::snapshot_scene;
use contracts::lab02::LightSample;
use contracts::lab03::Shadows;

use raylab_core::Error;
use raylab_core::film::{Film, ToneMap};
use raylab_core::glam::{Vec2, Vec3};
use raylab_core::math::Ray;
use raylab_core::sampling::Rng;

use figures::{Figure, Panel, ReportContext, settings, timed};

/// The area light is dim next to the point light: the figures scale radiance by this before
/// clamping.
const EXPOSURE: f32 = 3.0;

/// The `n` of the penumbra montage: 1, 4, 9, 25, 100 and 225 light samples (ELUMI Fig. 4.8).
const LIGHT_SAMPLES: [u32; 6] = [1, 2, 3, 5, 10, 15];

/// The region of a 512 × 512 render cut out for the penumbra panels: the shadow of the tall
/// block on the red wall and the floor.
const CROP: (u32, u32, u32, u32) = (48, 248, 176, 208);

/// The figures of lab 03.
pub fn figures(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    let (w, h) = ctx.size(512, 512);
    let tonemap = ToneMap::Clamp { exposure: EXPOSURE };
    let point_scene = snapshot_scene(true)?;
    let area_scene = snapshot_scene(false)?;
    let mut figures = Vec::new();

    let (film, seconds) = ctx.render_timed(&point_scene, &ctx.pipeline, &settings(w, h, 1))?;
    ctx.save_labelled(
        film,
        timed("1 shadow ray", seconds),
        "cornell-hard-shadows.png",
        ToneMap::default(),
    )?;
    figures.push(Figure {
        file: "cornell-hard-shadows.png".into(),
        caption: "Hard shadows: the Cornell box lit by the point light under the ceiling lamp"
            .into(),
        parameters: format!(
            "{w}×{h} pixels, 1 ray per pixel through the pixel centre, one shadow ray per shading point, clamp tone map"
        ),
        seconds: Some(seconds),
    });

    let n = 10;
    let pipeline = {
        let mut pipeline = ctx.pipeline.clone();
        pipeline.area_light_samples = n;
        pipeline
    };
    let (film, seconds) = ctx.render_timed(&area_scene, &pipeline, &settings(w, h, 1))?;
    ctx.save_labelled(
        film,
        timed(&format!("{n}×{n} light samples"), seconds),
        "cornell-soft-shadows.png",
        tonemap,
    )?;
    figures.push(Figure {
        file: "cornell-soft-shadows.png".into(),
        caption: "Soft shadows: the Cornell box lit by its area light (the ceiling lamp)".into(),
        parameters: format!(
            "{w}×{h} pixels, 1 ray per pixel, {n}×{n} = {} stratified light samples per shading point, clamp tone map with exposure {EXPOSURE}",
            n * n
        ),
        seconds: Some(seconds),
    });

    // The penumbra as the number of light samples grows.
    let mut panels = Vec::new();
    let mut times = Vec::new();
    for n in LIGHT_SAMPLES {
        let pipeline = {
            let mut pipeline = ctx.pipeline.clone();
            pipeline.area_light_samples = n;
            pipeline
        };
        let (film, seconds) = ctx.render_timed(&area_scene, &pipeline, &settings(w, h, 1))?;
        panels.push(Panel::new(
            crop(&film, w),
            timed(&format!("n = {}", n * n), seconds),
        ));
        times.push((n, seconds));
    }
    let total: f64 = times.iter().map(|t| t.1).sum();
    ctx.save_panels(&[panels], "penumbra-light-samples.png", tonemap)?;
    let mut table = String::from(
        "| light samples | 1 | 4 | 9 | 25 | 100 | 225 |\n| --- | --- | --- | --- | --- | --- | --- |\n| render time (s) |",
    );
    for (_, t) in &times {
        let _ = write!(table, " {t:.3} |");
    }
    table.push_str("\n| relative render time |");
    for (_, t) in &times {
        let _ = write!(table, " {:.1} |", t / times[0].1);
    }
    figures.push(Figure {
        file: "penumbra-light-samples.png".into(),
        caption: "The penumbra of the tall block with 1, 4, 9, 25, 100 and 225 light samples (left to right)".into(),
        parameters: format!(
            "each panel cut from a {w}×{h} render of the Cornell box lit by its area light only, 1 ray per pixel, n×n stratified jittered light samples per shading point (n = 1, 2, 3, 5, 10, 15), clamp tone map with exposure {EXPOSURE}. Render time of each whole image:\n\n{table}\n\nAll six renders together"
        ),
        seconds: Some(total),
    });

    // Cell centres against jittered samples: banding against noise.
    let n = 3;
    let mut panels = Vec::new();
    let mut total = 0.0;
    for jitter in [false, true] {
        let shadows: Arc<dyn Shadows> = if jitter {
            ctx.pipeline.code::<dyn contracts::lab03::Shadows>()
        } else {
            Arc::new(CellCentres(
                ctx.pipeline.code::<dyn contracts::lab03::Shadows>(),
            ))
        };
        let pipeline = {
            let mut pipeline = ctx.pipeline.clone().with_part(shadows);
            pipeline.area_light_samples = n;
            pipeline
        };
        let (film, seconds) = ctx.render_timed(&area_scene, &pipeline, &settings(w, h, 1))?;
        let what = if jitter { "jittered" } else { "cell centres" };
        panels.push(Panel::new(crop(&film, w), timed(what, seconds)));
        total += seconds;
    }
    ctx.save_panels(&[panels], "penumbra-grid-vs-jitter.png", tonemap)?;
    figures.push(Figure {
        file: "penumbra-grid-vs-jitter.png".into(),
        caption: "Nine light samples at the cell centres (left: nine point lights, a banded penumbra) and jittered within their cells (right: noise instead of bands)".into(),
        parameters: format!(
            "cut from {w}×{h} renders, 1 ray per pixel, 3×3 light samples, clamp tone map with exposure {EXPOSURE}; the time is that of both renders"
        ),
        seconds: Some(total),
    });
    Ok(figures)
}

/// The penumbra region of a render of width `w` (the [`CROP`] of a 512-pixel image, scaled).
fn crop(film: &Film, w: u32) -> Film {
    let s = |v: u32| (v as u64 * w as u64 / 512) as u32;
    let (x0, y0, cw, ch) = (s(CROP.0), s(CROP.1), s(CROP.2).max(1), s(CROP.3).max(1));
    let mut out = Film::new(cw, ch);
    for y in 0..ch {
        for x in 0..cw {
            out.set(x, y, film.get(x0 + x, y0 + y));
        }
    }
    out
}

/// Another lab-03 implementation whose stratified samples are the cell centres (no jitter).
struct CellCentres(Arc<dyn Shadows>);

impl Shadows for CellCentres {
    fn shadow_ray(&self, position: Vec3, light: &LightSample) -> Ray {
        self.0.shadow_ray(position, light)
    }
    fn stratified_samples(&self, n: u32, _rng: &mut Rng) -> Vec<Vec2> {
        (0..n * n)
            .map(|k| (Vec2::new((k % n) as f32, (k / n) as f32) + 0.5) / n as f32)
            .collect()
    }
    fn sample_triangle(&self, triangle: [Vec3; 3], u: Vec2) -> Vec3 {
        self.0.sample_triangle(triangle, u)
    }
    fn area_light_sample(
        &self,
        position: Vec3,
        light_point: Vec3,
        light_normal: Vec3,
        emission: Vec3,
        pdf_area: f32,
    ) -> LightSample {
        self.0
            .area_light_sample(position, light_point, light_normal, emission, pdf_area)
    }
}

/// Makes the lab's report: its figures through `pipeline` (`raylab report`).
pub fn make(
    job: &pipeline::job::ReportJob,
    pipeline: pipeline::Pipeline,
) -> Result<(), raylab_core::Error> {
    figures::make(job, crate::checks::LAB, pipeline, figures)
}
