//! Lab 10's figures (the Week 11 report's): the default scene's glass and glossy spheres with
//! lab 04's fixed weights against the Fresnel weights, with a magnified cut-out of the glass
//! sphere where the reflections at grazing angles show; and the absorbing volumes (`illum 11`
//! and 12, the worksheet's Kd 0.8 0.1 0.3) beside the old glossy shader. Each panel with its
//! render time, and a table of the reflectance against the angle of incidence.

use std::fmt::Write as _;

use crate::checks::volume_default_scene;
use grading::scenes::glossy_default_scene;
use pipeline::Pipeline;
use raylab_core::Error;
use raylab_core::film::{Film, ToneMap};
use raylab_core::scene::{IllumModel, Scene, builtin_scene};

use figures::{Figure, Panel, ReportContext, settings, timed};

/// The cut-out of the glass sphere, as fractions of the image: left, top, width, height.
const CROP: [f32; 4] = [0.62, 0.36, 0.22, 0.28];
/// Magnification of the cut-out (nearest neighbour).
const ZOOM: u32 = 3;
/// Angles of incidence of the reflectance table, in degrees.
const TABLE_ANGLES: [f32; 10] = [0.0, 15.0, 30.0, 45.0, 56.31, 60.0, 70.0, 80.0, 85.0, 89.0];

/// One render of a figure: its film, what it shows and its time.
struct Shot {
    film: Film,
    caption: &'static str,
    seconds: f64,
}

/// The figures of lab 10.
pub fn figures(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    let (w, h) = ctx.size(512, 384);
    let spp = if ctx.quick { 1 } else { 4 };
    let at_lab = |lab: u32| ctx.pipeline.clone().through(lab);
    // Start the worker threads before the first timed render.
    ctx.render_timed(
        &builtin_scene("default")?,
        &at_lab(10),
        &settings(32, 24, 1),
    )?;
    let render = |caption: &'static str, scene: &Scene, lab: u32| -> Result<Shot, Error> {
        let (film, seconds) = ctx.render_timed(scene, &at_lab(lab), &settings(w, h, spp))?;
        Ok(Shot {
            film,
            caption,
            seconds,
        })
    };
    let default = builtin_scene("default")?;
    let glossy = glossy_default_scene()?;
    let weights = [
        render("glass (illum 4), lab 04: refraction only", &default, 4)?,
        render("glass (illum 4), lab 10: R and 1 − R", &default, 10)?,
        render(
            "glossy (illum 5), lab 04: 0.1 Phong + 0.1 reflection + 0.9 refraction",
            &glossy,
            4,
        )?,
        render(
            "glossy (illum 5), lab 10: Phong highlight + R and 1 − R",
            &glossy,
            10,
        )?,
    ];
    let volumes = [
        render(
            "illum 11 (absorbing volume), lab 10",
            &volume_default_scene(IllumModel::AbsorbingVolume)?,
            10,
        )?,
        render(
            "illum 12 (absorbing glossy volume), lab 10",
            &volume_default_scene(IllumModel::GlossyVolume)?,
            10,
        )?,
        // The worksheet's comparison: the old glossy shader on the same sphere.
        render(
            "illum 5, lab 04's glossy shader (fixed weights, no absorption)",
            &glossy,
            4,
        )?,
    ];
    let common = format!(
        "{w}×{h}, {spp} sample(s) per pixel, seed 0, depth limit {}, clamp tone map",
        ctx.pipeline.max_depth
    );
    Ok(vec![
        panels_figure(
            ctx,
            "fixed-weights-vs-fresnel.png",
            "Glass and glossy spheres with lab 04's fixed weights and with the Fresnel weights",
            &weights,
            &format!(
                "the default scene, {common}. The Fresnel reflectance R at the glass sphere (η = 1.5), from `fresnel_reflectance` in the pipeline's lab 10 slot:\n\n{}",
                reflectance_table(&ctx.pipeline)
            ),
        )?,
        closeup_figure(ctx, &weights[0], &weights[1], w, h)?,
        panels_figure(
            ctx,
            "absorption.png",
            "Absorption: the worksheet's glass ball as an absorbing volume and an absorbing glossy volume, beside the old glossy shader",
            &volumes,
            &format!(
                "the default scene with the glass sphere's Kd = (0.8, 0.1, 0.3), so σ = 1/Kd − 1 = (0.25, 9, 2.33) per unit length; the sphere's diameter is 1 unit. {common}"
            ),
        )?,
    ])
}

/// A figure of panels side by side, with their captions and times in the parameters.
fn panels_figure(
    ctx: &ReportContext,
    file: &str,
    caption: &str,
    panels: &[Shot],
    parameters: &str,
) -> Result<Figure, Error> {
    let labelled = panels
        .iter()
        .map(|p| Panel::new(p.film.clone(), timed(p.caption, p.seconds)))
        .collect();
    ctx.save_panels(&[labelled], file, ToneMap::default())?;
    let mut table = String::from("| panel (left to right) | render time (s) |\n| --- | --- |\n");
    for p in panels {
        let _ = writeln!(table, "| {} | {:.3} |", p.caption, p.seconds);
    }
    Ok(Figure {
        file: file.into(),
        caption: caption.into(),
        parameters: format!("{parameters}\n\n{table}\nAll panels together"),
        seconds: Some(panels.iter().map(|p| p.seconds).sum()),
    })
}

/// The cut-out [`CROP`] of `film`, magnified [`ZOOM`] times.
fn crop_zoom(film: &Film) -> Film {
    figures::crop_zoom(film, CROP, ZOOM)
}

fn closeup_figure(
    ctx: &ReportContext,
    fixed: &Shot,
    fresnel: &Shot,
    w: u32,
    h: u32,
) -> Result<Figure, Error> {
    let file = "glass-sphere-closeup.png";
    let panels = vec![
        Panel::new(crop_zoom(&fixed.film), "refraction only"),
        Panel::new(crop_zoom(&fresnel.film), "Fresnel weights"),
    ];
    ctx.save_panels(&[panels], file, ToneMap::default())?;
    Ok(Figure {
        file: file.into(),
        caption: "The glass sphere close up: refraction only (left) and Fresnel weights (right)"
            .into(),
        parameters: format!(
            "a cut-out of the first two panels of the first figure ({w}×{h}), magnified {ZOOM}× with nearest-neighbour pixels. Towards the sphere's rim the angle of incidence grows and R rises to 1: the Fresnel sphere mirrors the sky and the ground there, where the refraction-only sphere shows the refracted scene up to its edge"
        ),
        seconds: Some(fixed.seconds + fresnel.seconds),
    })
}

/// A table of the reflectance at [`TABLE_ANGLES`] from air into glass and back, or the
/// message of the unfinished exercise that stopped it.
fn reflectance_table(pipeline: &Pipeline) -> String {
    let fresnel = pipeline.code::<dyn contracts::lab10::Fresnel>();
    let rows = raylab_core::catch_quietly("lab 10's reflectance table", || {
        let mut table = String::from(
            "| angle of incidence θ₁ | R, air → glass (1 → 1.5) | R, glass → air (1.5 → 1) |\n| --- | --- | --- |\n",
        );
        for degrees in TABLE_ANGLES {
            let c = degrees.to_radians().cos();
            let into = fresnel.fresnel_reflectance(c, 1.0, 1.5);
            let out = fresnel.fresnel_reflectance(c, 1.5, 1.0);
            let _ = writeln!(table, "| {degrees}° | {into:.4} | {out:.4} |");
        }
        table
    });
    match rows {
        Ok(mut table) => {
            table.push_str(
                "\n(56.31° is Brewster's angle into glass, atan 1.5; from glass into air total internal reflection sets in at asin(1/1.5) = 41.81°.)",
            );
            table
        }
        Err(panic) => format!("(no table: {})", panic.message),
    }
}

/// Makes the lab's report: its figures through `pipeline` (`raylab report`).
pub fn make(
    job: &pipeline::job::ReportJob,
    pipeline: pipeline::Pipeline,
) -> Result<(), raylab_core::Error> {
    figures::make(job, crate::checks::LAB, pipeline, figures)
}
