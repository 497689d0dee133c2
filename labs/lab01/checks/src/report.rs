//! Lab 01's figure: the default scene through the camera, in flat colours.

use pipeline::View;
use raylab_core::Error;
use raylab_core::film::ToneMap;
use raylab_core::scene::builtin_scene;

use figures::{Figure, ReportContext, settings, timed};

/// The figures of lab 01.
pub fn figures(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    let (w, h) = ctx.size(512, 384);
    let scene = builtin_scene("default")?;
    let pipeline = {
        let mut pipeline = ctx.pipeline.clone();
        pipeline.view = View::BaseColour;
        pipeline
    };
    let (film, seconds) = ctx.render_timed(&scene, &pipeline, &settings(w, h, 1))?;
    ctx.save_labelled(
        film,
        timed(&format!("{w}×{h}, 1 ray per pixel"), seconds),
        "default-base-colour.png",
        ToneMap::default(),
    )?;
    Ok(vec![Figure {
        file: "default-base-colour.png".into(),
        caption: "The default scene seen through the camera (flat colours)".into(),
        parameters: format!("{w}×{h} pixels, 1 ray through each pixel centre"),
        seconds: Some(seconds),
    }])
}

/// Makes the lab's report: its figures through `pipeline` (`raylab report`).
pub fn make(
    job: &pipeline::job::ReportJob,
    pipeline: pipeline::Pipeline,
) -> Result<(), raylab_core::Error> {
    figures::make(job, crate::checks::LAB, pipeline, figures)
}
