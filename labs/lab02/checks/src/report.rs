//! Lab 02's figures: the default scene and the Cornell box with Lambertian shading, and the
//! normals of the default scene.

use pipeline::View;
use raylab_core::Error;
use raylab_core::film::ToneMap;
use raylab_core::scene::builtin_scene;

use figures::{Figure, ReportContext, settings, timed};

/// The figures of lab 02.
pub fn figures(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    let (w, h) = ctx.size(512, 384);
    let mut figures = Vec::new();
    for (scene_name, view, file, caption) in [
        (
            "default",
            View::Normals,
            "default-normals.png",
            "Shading normals of the default scene",
        ),
        (
            "default",
            View::Shaded,
            "default-lambertian.png",
            "The default scene, Lambertian, point and directional light, no shadows",
        ),
        (
            "cornell",
            View::Shaded,
            "cornell-lambertian.png",
            "The Cornell box lit by a point light under the ceiling lamp, no shadows",
        ),
    ] {
        let scene = builtin_scene(scene_name)?;
        let pipeline = {
            let mut pipeline = ctx.pipeline.clone();
            pipeline.view = view;
            pipeline
        };
        let (film, seconds) = ctx.render_timed(&scene, &pipeline, &settings(w, h, 1))?;
        ctx.save_labelled(
            film,
            timed(&format!("{scene_name} scene, {w}×{h}"), seconds),
            file,
            ToneMap::default(),
        )?;
        figures.push(Figure {
            file: file.into(),
            caption: caption.into(),
            parameters: format!("{w}×{h} pixels, 1 ray per pixel, clamp tone map"),
            seconds: Some(seconds),
        });
    }
    Ok(figures)
}

/// Makes the lab's report: its figures through `pipeline` (`raylab report`).
pub fn make(
    job: &pipeline::job::ReportJob,
    pipeline: pipeline::Pipeline,
) -> Result<(), raylab_core::Error> {
    figures::make(job, crate::checks::LAB, pipeline, figures)
}
