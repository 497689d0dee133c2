//! Lab 08's figures (the Weeks 8–9 report's Figures 3.1, 4.1 and 4.2): the caustic photon map
//! of the Cornell box with the glass sphere drawn as points over the scene, the caustics
//! alone, and the full render (direct lighting plus caustics), each with the photon count and
//! the times of tracing and rendering.

use std::time::Instant;

use pipeline::photon::{PhotonMap, PhotonSettings, trace_caustic_photons};
use pipeline::{Pipeline, View};
use raylab_core::Error;
use raylab_core::film::{Film, ToneMap};
use raylab_core::scene::{Scene, builtin_scene};

use figures::{Figure, ReportContext, settings, timed};

/// The scene of the figures.
const SCENE: &str = "cornell-spheres";

/// The photon map of the images of the estimate (Figures 4.1 and 4.2). Besides the glass
/// sphere's caustic, the mirror sphere spreads the reflection of the lights thinly over every
/// wall and the ceiling: caustic light too (a specular bounce, then a diffuse surface), but a
/// dim one. The defaults ([`PhotonSettings::DEFAULT`], two million photons, `k = 200` within
/// 5 cm) leave a faint mottle in it; four times the photons and `k = 400` within 6 cm (a
/// relative noise of `1/√400 = 5 %`) make it smooth for the figures, while the glass sphere's
/// caustic, hundreds of times denser, still finds its 400 photons within a few millimetres.
pub const ESTIMATE_PHOTONS: PhotonSettings = PhotonSettings {
    emitted: 8_000_000,
    k: 400,
    max_radius: 0.06,
    seed: 0,
};

/// The figures of lab 08.
pub fn figures(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    let scene = builtin_scene(SCENE)?;
    // The preview draws the photons of a map of the default count, each a pixel (many more
    // would cover the walls); the estimate's images gather from the denser map.
    let preview_photons = PhotonSettings {
        emitted: if ctx.quick {
            20_000
        } else {
            PhotonSettings::DEFAULT.emitted
        },
        ..PhotonSettings::DEFAULT
    };
    let photons = if ctx.quick {
        PhotonSettings {
            emitted: 100_000,
            k: 50,
            ..ESTIMATE_PHOTONS
        }
    } else {
        ESTIMATE_PHOTONS
    };
    let base = {
        let mut pipeline = ctx.pipeline.clone();
        pipeline.photons = photons;
        pipeline
    };
    let trace_map = |settings: &PhotonSettings| {
        let start = Instant::now();
        let trace = raylab_core::catch_quietly("tracing photons", || {
            trace_caustic_photons(&base, &scene, settings)
        })?;
        Ok::<_, Error>((trace, start.elapsed().as_secs_f64()))
    };
    let (preview_trace, preview_trace_seconds) = trace_map(&preview_photons)?;
    let (trace, trace_seconds) = trace_map(&photons)?;
    let stored = trace.map.len();
    let map = std::sync::Arc::new(trace.map);
    let with_map = {
        let mut pipeline = base.clone();
        pipeline.caustics = Some(map.clone());
        pipeline
    };
    let (w, h) = ctx.size(512, 512);
    let traced = |emitted: u32, stored: usize, seconds: f64| {
        format!(
            "{emitted} photons emitted from the point light and the ceiling light (by power), {stored} stored in the caustic map (at the first diffuse surface after a mirror or glass), traced in {seconds:.2} s"
        )
    };
    let about = traced(trace.emitted, stored, trace_seconds);
    let preview_stored = preview_trace.map.len();
    let preview_about = traced(preview_trace.emitted, preview_stored, preview_trace_seconds);
    let estimate = format!(
        "the k = {} photons nearest to each shading point within {} m",
        photons.k, photons.max_radius
    );
    let spp = if ctx.quick { 1 } else { 4 };

    let preview = photon_preview(ctx, &scene, &base, &preview_trace.map, w, h)?;
    ctx.save_labelled(
        preview.0,
        timed(
            &format!("{preview_stored} photons stored, {} drawn", preview.1),
            preview_trace_seconds + preview.2,
        ),
        "photon-map.png",
        ToneMap::default(),
    )?;
    let caustics_only = {
        let mut pipeline = with_map.clone();
        pipeline.view = View::Caustics;
        pipeline
    };
    let (film, caustic_seconds) = ctx.render_timed(&scene, &caustics_only, &settings(w, h, spp))?;
    ctx.save_labelled(
        film,
        timed(
            &format!("caustics only, k = {}", photons.k),
            caustic_seconds,
        ),
        "caustics-only.png",
        ToneMap::default(),
    )?;
    let (film, full_seconds) = ctx.render_timed(&scene, &with_map, &settings(w, h, spp))?;
    ctx.save_labelled(
        film,
        timed("direct + caustics", full_seconds),
        "full-render.png",
        ToneMap::default(),
    )?;

    Ok(vec![
        Figure {
            file: "photon-map.png".into(),
            caption: "The caustic photon map: each stored photon as a point over the scene (Figure 3.1)".into(),
            parameters: format!(
                "{SCENE} at {w}×{h}: the direct lighting at a third of its brightness, and over it every stored photon visible from the eye as one pixel coloured by its power (scaled so the brightest is white); {preview_about}; {} photons drawn, drawing",
                preview.1
            ),
            seconds: Some(preview_trace_seconds + preview.2),
        },
        Figure {
            file: "caustics-only.png".into(),
            caption: "Caustics only: the photon map's radiance estimate at diffuse surfaces, seen directly and through the mirror and the glass — the glass sphere's bright caustic on the floor, and the dim glow the mirror sphere reflects onto every wall and the ceiling (Figure 4.1)".into(),
            parameters: format!(
                "{SCENE} at {w}×{h}, {spp} samples per pixel, clamp tone map; {estimate}, L = ρ/π · ΣΦ/(πr²); {about}; render"
            ),
            seconds: Some(caustic_seconds),
        },
        Figure {
            file: "full-render.png".into(),
            caption: "The full render: direct lighting (point and area light, shadows, mirror and glass) plus the caustics (Figure 4.2)".into(),
            parameters: format!(
                "{SCENE} at {w}×{h}, {spp} samples per pixel, {} × {} area-light samples, clamp tone map; {estimate}; {about}; render",
                with_map.area_light_samples, with_map.area_light_samples
            ),
            seconds: Some(full_seconds),
        },
    ])
}

/// The scene's direct lighting at a third, with the photons of `map` that the eye sees drawn
/// over it; the image, the number of photons drawn and the seconds it took.
fn photon_preview(
    ctx: &ReportContext,
    scene: &Scene,
    pipeline: &Pipeline,
    map: &PhotonMap,
    w: u32,
    h: u32,
) -> Result<(Film, usize, f64), Error> {
    let (mut film, seconds) = ctx.render_timed(scene, pipeline, &settings(w, h, 1))?;
    let start = Instant::now();
    for p in &mut film.pixels {
        *p /= 3.0;
    }
    let camera = pipeline.prepare_camera(scene, raylab_core::glam::UVec2::new(w, h));
    let brightest = map
        .photons()
        .iter()
        .map(|p| p.power.max_element())
        .fold(0.0f32, f32::max)
        .max(f32::MIN_POSITIVE);
    let mut drawn = 0;
    for photon in map.photons() {
        let d = photon.position - camera.eye;
        let depth = d.dot(camera.basis.ip_normal);
        if depth <= 0.0 {
            continue;
        }
        let x_ip = camera.focal_distance * d.dot(camera.basis.ip_xaxis) / depth;
        let y_ip = camera.focal_distance * d.dot(camera.basis.ip_yaxis) / depth;
        let (x, y) = (
            x_ip * h as f32 + w as f32 / 2.0,
            h as f32 / 2.0 - y_ip * h as f32,
        );
        if !(x >= 0.0 && y >= 0.0 && x < w as f32 && y < h as f32) {
            continue;
        }
        let distance = d.length();
        let ray =
            raylab_core::math::Ray::new(camera.eye, d / distance, 0.0, distance * (1.0 - 1e-3));
        if pipeline.trace_to_any(scene, &ray) {
            continue;
        }
        film.set(x as u32, y as u32, photon.power / brightest);
        drawn += 1;
    }
    Ok((film, drawn, seconds + start.elapsed().as_secs_f64()))
}

/// Makes the lab's report: its figures through `pipeline` (`raylab report`).
pub fn make(
    job: &pipeline::job::ReportJob,
    pipeline: pipeline::Pipeline,
) -> Result<(), raylab_core::Error> {
    figures::make(job, crate::checks::LAB, pipeline, figures)
}
