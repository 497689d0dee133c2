//! Lab 11's figures, the hand-in's Figures 4.1 and 4.3: ambient occlusion with rejection
//! against cosine-weighted sampling at 100, 200 and 300 rays per shading point, under a
//! uniform white environment (the image is the accessibility times the reflectance); and the
//! scene lit by the lab's two light probes — the sky (an angular map in Radiance RGBE) and the
//! studio (a latitude–longitude map in OpenEXR) — with the probe behind it and in the mirror.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::checks::{SKY_PROBE, STUDIO_PROBE};
use contracts::lab11::HemisphereSampler;

use raylab_core::Error;
use raylab_core::film::ToneMap;
use raylab_core::glam::Vec3;
use raylab_core::scene::{EnvironmentMap, ProbeMapping, Scene, Texture, load_scene_file};

use figures::{Figure, Panel, ReportContext, settings, timed};

/// The rays per shading point of Figure 4.1.
const RAYS: [u32; 3] = [100, 200, 300];

fn lab_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The lab's scene, lit by the probe file `probe` of `labs/lab11/probes/`.
pub fn probe_scene(probe: Option<(&str, ProbeMapping)>) -> Result<Scene, Error> {
    let mut scene = load_scene_file(&lab_dir().join("scenes/probe-spheres.toml"))?;
    scene.environment = Some(match probe {
        Some((file, mapping)) => {
            EnvironmentMap::load(&lab_dir().join("probes").join(file), mapping, 1.0)?
        }
        // A uniform white environment of radiance 1: the render is ρ·A.
        None => EnvironmentMap {
            texture: Arc::new(Texture {
                path: PathBuf::from("uniform white"),
                width: 1,
                height: 1,
                texels: vec![Vec3::ONE],
            }),
            mapping: ProbeMapping::Latlong,
            scale: 1.0,
        },
    });
    Ok(scene)
}

/// The figures of lab 11.
pub fn figures(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    let (w, h) = ctx.size(320, 240);
    let with = |rays: u32, sampler: HemisphereSampler| {
        let mut pipeline = ctx.pipeline.clone();
        pipeline.occlusion_rays = (if ctx.quick { rays / 10 } else { rays }, sampler);
        pipeline
    };
    let white = probe_scene(None)?;
    // Start the worker threads before the first timed render.
    ctx.render_timed(
        &white,
        &with(4, HemisphereSampler::Cosine),
        &settings(32, 24, 1),
    )?;

    let mut rows = Vec::new();
    let mut times = Vec::new();
    let mut total = 0.0;
    for sampler in [HemisphereSampler::Rejection, HemisphereSampler::Cosine] {
        let mut row = Vec::new();
        for rays in RAYS {
            let pipeline = with(rays, sampler);
            let (film, t) = ctx.render_timed(&white, &pipeline, &settings(w, h, 1))?;
            let what = format!("{sampler:?}, {} rays", pipeline.occlusion_rays.0);
            row.push(Panel::new(film, timed(&what, t)));
            times.push(format!("{sampler:?} {rays}: {t:.2} s"));
            total += t;
        }
        rows.push(row);
    }
    let file = "ao-rejection-vs-cosine.png";
    ctx.save_panels(&rows, file, ToneMap::default())?;
    let mut figures = vec![Figure {
        file: file.into(),
        caption: "Figure 4.1: ambient occlusion, rejection sampling (top) against cosine-weighted sampling (bottom), 100, 200 and 300 rays per shading point (left to right)".into(),
        parameters: format!(
            "The lab's scene (labs/lab11/scenes/probe-spheres.toml) under a uniform white environment of radiance 1, so each pixel is ρ·A (reflectance times accessibility) plus the mirror's reflection of it; {w}×{h}, one camera ray per pixel, seed 0. The same estimator (Exercise 11.3) weights each free ray by cos θ/(π·pdf): both samplers converge to the same image, the cosine-weighted one with less noise at the same number of rays. Times: {}",
            times.join(", ")
        ),
        seconds: Some(total),
    }];

    let (w, h) = ctx.size(480, 360);
    let rays = if ctx.quick { 16 } else { 200 };
    // The studio's softboxes are small and bright: where the bent normal of a shading point
    // lies near one, whether it falls inside changes from estimate to estimate, so that
    // figure averages four times as many camera rays (each its own 200-ray estimate).
    for (probe, mapping, caption, file, spp, note) in [
        (
            SKY_PROBE,
            ProbeMapping::Angular,
            "Figure 4.3a: lit by the sky probe (angular map, Radiance RGBE)",
            "probe-sky.png",
            4,
            "",
        ),
        (
            STUDIO_PROBE,
            ProbeMapping::Latlong,
            "Figure 4.3b: lit by the studio probe (latitude–longitude map, OpenEXR); the bright, grainy patches on the spheres' sides and on the floor by them are where the bent normal points into a softbox",
            "probe-studio.png",
            16,
            ". The shader takes the probe's radiance along the bent normal alone (the nearest texel, no blur), so a shading point whose bent normal points into one of the studio's small, bright softboxes takes the softbox's full radiance: the bright patches on the spheres' sides facing a softbox and on the floor beside them. Their edges are grainy because the bent normal is itself an estimate from the rays: near a softbox's edge it falls inside for some estimates and outside for others. More rays per shading point sharpen the patches; more rays per pixel smooth their edges (16 here, against 4 for the sky)",
        ),
    ] {
        let scene = probe_scene(Some((probe, mapping)))?;
        let pipeline = with(rays, HemisphereSampler::Cosine);
        let spp = if ctx.quick { 1 } else { spp };
        let (film, t) = ctx.render_timed(&scene, &pipeline, &settings(w, h, spp))?;
        ctx.save_labelled(
            film,
            timed(&format!("{} map, {rays} rays", mapping.name()), t),
            file,
            ToneMap::Reinhard {
                key: 0.18,
                white: 4.0,
            },
        )?;
        figures.push(Figure {
            file: file.into(),
            caption: caption.into(),
            parameters: format!(
                "labs/lab11/probes/{probe} ({} mapping) behind the scene and in the mirror sphere; the diffuse surfaces by the ambient-occlusion shader (Exercise 11.9): ρ·A·L(bent normal), {rays} cosine-weighted rays per shading point; {w}×{h}, {spp} rays per pixel, seed 0; Reinhard's operator, key 0.18, L_white = 4{note}",
                mapping.name()
            ),
            seconds: Some(t),
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
