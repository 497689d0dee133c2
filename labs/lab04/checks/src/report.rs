//! Lab 04's figures: the worksheet's image set on the default scene (Lambertian, then the
//! mirror sphere, the glass sphere, the Phong torus, and the glossy "combining it all" sphere),
//! each with its render time; the Cornell box with a mirror and a glass sphere; and two facing
//! mirrors at growing depth limits.

use crate::checks::Shot;
use grading::part_snapshots::SnapshotScene;
use grading::scenes::glossy_default_scene;

use raylab_core::Error;
use raylab_core::film::{Film, ToneMap};
use raylab_core::scene::{IllumModel, Scene, builtin_scene};

use figures::{Figure, Panel, ReportContext, settings, timed};

/// The default scene with every material whose model is not in `keep` made Lambertian, so
/// that one shader after the other can be switched on.
fn default_with(keep: &[IllumModel]) -> Result<Scene, Error> {
    let mut scene = builtin_scene("default")?;
    for m in &mut scene.materials {
        if !keep.contains(&m.illum) {
            m.illum = IllumModel::Lambertian;
        }
    }
    Ok(scene)
}

/// One step of the worksheet's image set: its render, file, caption, label and time.
struct Step {
    film: Film,
    file: &'static str,
    caption: &'static str,
    label: &'static str,
    seconds: f64,
}

/// The figures of lab 04.
pub fn figures(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    let (w, h) = ctx.size(512, 384);
    // Enough rays per pixel that the render times measure the shaders, not the start-up.
    let spp = if ctx.quick { 1 } else { 16 };
    let depth = ctx.pipeline.max_depth;
    let mut figures = Vec::new();
    let at_lab = |lab: u32| ctx.pipeline.clone().through(lab);
    // Start the worker threads before the first timed render.
    ctx.render_timed(&builtin_scene("default")?, &at_lab(4), &settings(32, 24, 1))?;

    // The worksheet's image set: each step adds one shader (and the rays it spawns).
    use IllumModel::{Mirror, Phong, Transparent};
    let steps: [(&str, &str, &str, Scene, u32); 6] = [
        (
            "default-lab2.png",
            "lab 2: Lambertian",
            "Lab 2: every surface Lambertian, no shadows",
            builtin_scene("default")?,
            2,
        ),
        (
            "default-lab3.png",
            "lab 3: shadows",
            "Lab 3: every surface Lambertian, with shadow rays",
            builtin_scene("default")?,
            3,
        ),
        (
            "default-mirror.png",
            "mirror",
            "Mirror sphere (illum 3): reflected rays",
            default_with(&[Mirror])?,
            4,
        ),
        (
            "default-glass.png",
            "glass, η = 1.5",
            "Glass sphere (illum 4, η = 1.5): refracted rays, a ball lens",
            default_with(&[Mirror, Transparent])?,
            4,
        ),
        (
            "default-phong.png",
            "Phong, s = 40",
            "Phong torus (illum 2, s = 40): the normalized Phong highlight",
            default_with(&[Mirror, Transparent, Phong])?,
            4,
        ),
        (
            "default-glossy.png",
            "glossy glass",
            "Combining it all: the glass sphere glossy (illum 5), 0.1·Phong + 0.1·reflected + 0.9·refracted",
            glossy_default_scene()?,
            4,
        ),
    ];
    let mut done = Vec::new();
    for (file, caption, label, scene, lab) in steps {
        let pipeline = at_lab(lab);
        let (film, seconds) = ctx.render_timed(&scene, &pipeline, &settings(w, h, spp))?;
        ctx.save_labelled(
            film.clone(),
            timed(label, seconds),
            file,
            ToneMap::default(),
        )?;
        figures.push(Figure {
            file: file.into(),
            caption: caption.into(),
            parameters: format!(
                "the default scene, {w}×{h} pixels, {spp} rays per pixel, pipeline at lab {lab}, depth limit {depth}, clamp tone map"
            ),
            seconds: Some(seconds),
        });
        done.push(Step {
            film,
            file,
            caption,
            label,
            seconds,
        });
    }
    let set: Vec<&Step> = done.iter().skip(2).collect();
    let panels: Vec<Panel> = set
        .iter()
        .map(|p| Panel::new(p.film.clone(), timed(p.label, p.seconds)))
        .collect();
    ctx.save_panels(&[panels], "worksheet-set.png", ToneMap::default())?;
    figures.push(Figure {
        file: "worksheet-set.png".into(),
        caption: "The worksheet's image set: mirror, glass, Phong, combined".into(),
        parameters: format!(
            "left to right: {}",
            set.iter()
                .map(|p| format!("{} ({}, {:.3} s)", p.caption, p.file, p.seconds))
                .collect::<Vec<_>>()
                .join("; ")
        ),
        seconds: Some(set.iter().map(|p| p.seconds).sum()),
    });

    // The Cornell box with a mirror and a glass sphere, lit by its area light and point light.
    let n = ctx.pipeline.area_light_samples;
    let (film, seconds) = ctx.render_timed(
        &builtin_scene("cornell-spheres")?,
        &at_lab(4),
        &settings(w, h, spp),
    )?;
    ctx.save_labelled(
        film,
        timed(&format!("{spp} rays per pixel, depth {depth}"), seconds),
        "cornell-spheres.png",
        ToneMap::default(),
    )?;
    figures.push(Figure {
        file: "cornell-spheres.png".into(),
        caption: "The Cornell box with a mirror sphere (back) and a glass sphere (front)".into(),
        parameters: format!(
            "{w}×{h} pixels, {spp} rays per pixel, {n}×{n} area-light samples per shading point, depth limit {depth}, clamp tone map"
        ),
        seconds: Some(seconds),
    });

    // Two facing mirrors: the corridor of reflections ends in black at the depth limit.
    let scene = Shot::TwoMirrors.scene()?;
    let (dw, dh) = ctx.size(320, 240);
    let mut panels = Vec::new();
    let mut times = Vec::new();
    for max_depth in [1, 2, 5, 10, 30] {
        let pipeline = {
            let mut pipeline = at_lab(4);
            pipeline.max_depth = max_depth;
            pipeline
        };
        let (film, seconds) = ctx.render_timed(&scene, &pipeline, &settings(dw, dh, spp))?;
        panels.push(Panel::new(
            film,
            timed(&format!("depth {max_depth}"), seconds),
        ));
        times.push((max_depth, seconds));
    }
    ctx.save_panels(&[panels], "two-mirrors-depth.png", ToneMap::default())?;
    figures.push(Figure {
        file: "two-mirrors-depth.png".into(),
        caption: "Two facing mirrors at depth limits 1, 2, 5, 10 and 30".into(),
        parameters: format!(
            "{dw}×{dh} pixels each, {spp} rays per pixel, clamp tone map; render times: {}",
            times
                .iter()
                .map(|(d, s)| format!("depth {d}: {s:.3} s"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        seconds: Some(times.iter().map(|(_, s)| s).sum()),
    });
    Ok(figures)
}

/// Makes the lab's report: its figures through `pipeline` (`raylab report`).
pub fn make(
    job: &pipeline::job::ReportJob,
    pipeline: pipeline::Pipeline,
) -> Result<(), raylab_core::Error> {
    figures::make(job, crate::checks::LAB, pipeline, figures)
}
