//! Lab 12's figures: the Cornell box path traced (phoe_ray's Figure 19), the same at four path
//! depths (direct light against global illumination), its convergence, and the BSDF seen from
//! above at four roughnesses, the directions Exercise 12.3 draws against the density Exercise
//! 12.2 gives (as Mitsuba's χ² test shows a sampler); the sky's figures are in [`sky`].

mod sky;

use glam::Vec3;
use raylab_core::Error;
use raylab_core::film::{Film, ToneMap};
use raylab_core::render::PANICKED_COLOUR;

use contracts::lab12::{PathMaterial, PathTracing};
use contracts::math::Onb;
use contracts::sampling::Rng;
use figures::plot::{Guide, LogLogPlot, RED, Series};
use figures::{Figure, Panel, ReportContext, settings, timed};
use raylab_core::scene::builtin_scene;

/// The roughnesses of the figure's columns.
const ROUGHNESS: [f32; 4] = [1.0, 0.5, 0.25, 0.1];

/// The glossy exponent `n = 2/r² − 2` of roughness `r` (docs/lab12.md, "The material").
fn exponent(roughness: f32) -> f32 {
    2.0 / (roughness * roughness) - 2.0
}

/// The figures of lab 12.
pub fn figures(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    let mut figures = cornell(ctx)?;
    figures.extend(convergence(ctx)?);
    figures.extend(lobes(ctx)?);
    figures.extend(sky::figures(ctx)?);
    Ok(figures)
}

/// The path depths of the depth figure.
const DEPTHS: [u32; 4] = [0, 1, 2, 10];

/// The Cornell box lit by its ceiling, path traced; then at four path depths.
fn cornell(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    let scene = builtin_scene("cornell-ceiling")?;
    let (w, h) = ctx.size(320, 320);
    let spp = if ctx.quick { 16 } else { 256 };
    let (film, seconds) = ctx.render_timed(&scene, &ctx.pipeline, &settings(w, h, spp))?;
    let main = "cornell-path-traced.png";
    ctx.save_labelled(
        film,
        timed(
            &format!("{spp} spp, {} bounces", ctx.pipeline.max_depth),
            seconds,
        ),
        main,
        ToneMap::default(),
    )?;
    let (w, h) = ctx.size(160, 160);
    let spp = if ctx.quick { 8 } else { 128 };
    let mut panels = Vec::new();
    let mut total = 0.0;
    for depth in DEPTHS {
        let mut pipeline = ctx.pipeline.clone();
        pipeline.max_depth = depth;
        let (film, seconds) = ctx.render_timed(&scene, &pipeline, &settings(w, h, spp))?;
        total += seconds;
        let what = match depth {
            0 => "depth 0: emitters".to_string(),
            1 => "depth 1: direct light".to_string(),
            d => format!("depth {d}"),
        };
        panels.push(Panel::new(film, timed(&what, seconds)));
    }
    let depths = "cornell-depths.png";
    ctx.save_panels(&[panels], depths, ToneMap::default())?;
    Ok(vec![
        Figure {
            file: main.into(),
            caption: "The Cornell box lit by its ceiling alone (Ke = (17, 12, 4)), path traced with next-event estimation and multiple importance sampling (Exercise 12.8 with 12.2–12.7): soft shadows, and the walls' colours bled onto the blocks' sides, which the light does not reach (phoe_ray's Figure 19)"
                .into(),
            parameters: format!(
                "{}×{} pixels, {} samples per pixel, at most {} bounces, roulette from the third",
                ctx.size(320, 320).0,
                ctx.size(320, 320).1,
                if ctx.quick { 16 } else { 256 },
                ctx.pipeline.max_depth
            ),
            seconds: Some(seconds),
        },
        Figure {
            file: depths.into(),
            caption: "The same box with paths of at most 0, 1, 2 and 10 bounces: the emitter alone, direct light (the ceiling black but for its lamp), then each bounce adding indirect light".into(),
            parameters: format!("{w}×{h} pixels, {spp} samples per pixel each"),
            seconds: Some(total),
        },
    ])
}

/// Samples per pixel of the convergence figure.
const CONVERGENCE_SPP: [u32; 7] = [1, 4, 16, 64, 256, 1024, 4096];

/// The error of the box against a render of four times the largest count, from 1 to 4096
/// samples per pixel, on log–log axes: a Monte Carlo estimate's error falls as 1/√N.
fn convergence(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    let scene = builtin_scene("cornell-ceiling")?;
    let (w, h) = if ctx.quick { (16, 16) } else { (32, 32) };
    let counts: Vec<u32> = CONVERGENCE_SPP
        .iter()
        .copied()
        .filter(|&n| !ctx.quick || n <= 64)
        .collect();
    let most = *counts.last().expect("counts");
    let reference_spp = 4 * most;
    let (reference, mut seconds) = ctx.render_timed(
        &scene,
        &ctx.pipeline,
        &raylab_core::render::RenderSettings {
            seed: 999,
            ..settings(w, h, reference_spp)
        },
    )?;
    let mut points = Vec::new();
    let mut panels = Vec::new();
    for &n in &counts {
        let (film, s) = ctx.render_timed(&scene, &ctx.pipeline, &settings(w, h, n))?;
        seconds += s;
        let squares: f64 = film
            .pixels
            .iter()
            .zip(&reference.pixels)
            .map(|(a, b)| f64::from((*a - *b).length_squared()) / 3.0)
            .sum();
        let rmse = (squares / film.pixels.len() as f64).sqrt();
        if rmse.is_finite() && rmse > 0.0 {
            points.push((f64::from(n), rmse));
        }
    }
    // The images themselves, larger: phoe_ray's Figure 18.
    let (pw, ph) = ctx.size(160, 160);
    for n in [1, 16, 256] {
        let (film, s) = ctx.render_timed(&scene, &ctx.pipeline, &settings(pw, ph, n))?;
        seconds += s;
        panels.push(Panel::new(film, timed(&format!("{n} spp"), s)));
    }
    let images = "cornell-spp.png";
    ctx.save_panels(&[panels], images, ToneMap::default())?;
    let plot = LogLogPlot {
        x_decades: (0, (f64::from(most)).log10().ceil() as i32),
        x_label: "samples per pixel",
        y_label: "RMS error",
        series: vec![Series {
            name: "path tracer (12.2-12.8)",
            points: &points,
            colour: RED,
            markers: true,
        }],
        // Through the last point, where the error is an average over many paths per pixel; at a
        // few samples rare bright paths (fireflies) dominate it.
        guides: points
            .last()
            .map(|&through| Guide {
                slope: -0.5,
                through,
                name: "slope -1/2 (1/sqrt N)",
            })
            .into_iter()
            .collect(),
    };
    let plot_file = "cornell-convergence.png";
    ctx.save_plot(&plot, plot_file)?;
    let table: Vec<String> = points
        .iter()
        .map(|(n, e)| format!("{n} spp: {e:.4}"))
        .collect();
    Ok(vec![
        Figure {
            file: images.into(),
            caption: "The box at 1, 16 and 256 samples per pixel: the noise of a Monte Carlo estimate, a quarter as much at sixteen times the samples (phoe_ray's Figure 18)".into(),
            parameters: format!("{pw}×{ph} pixels, 10 bounces"),
            seconds: None,
        },
        Figure {
            file: plot_file.into(),
            caption: format!(
                "The RMS error against the reference falls as 1/√N, the slope −½ of every unbiased Monte Carlo estimate once there are enough samples per pixel that rare bright paths (fireflies) no longer dominate it (the last point includes the reference's own noise, a quarter of the variance; 1 spp traces pixel centres): {}",
                table.join(", ")
            ),
            parameters: format!("{w}×{h} pixels; the reference {reference_spp} spp"),
            seconds: Some(seconds),
        },
    ])
}

/// The BSDF's lobes at four roughnesses: drawn against their density.
fn lobes(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    let code = ctx
        .pipeline
        .part::<dyn PathTracing>()
        .ok_or_else(|| Error::Failed {
            what: "the report of lab 12".into(),
            reason: "the pipeline holds no code of lab 12".into(),
        })?;
    let size = if ctx.quick { 64 } else { 160 };
    let samples = if ctx.quick { 50_000 } else { 1_000_000 };
    let normal = Vec3::Z;
    // From the left, so that the mirror direction is right of the centre.
    let wo = Vec3::new(-(0.5f32.sqrt()), 0.0, 0.5f32.sqrt());
    let (mut drawn, mut density) = (Vec::new(), Vec::new());
    let mut notes = Vec::new();
    for roughness in ROUGHNESS {
        let material = PathMaterial {
            diffuse: Vec3::splat(0.2),
            glossy: Vec3::splat(0.7),
            exponent: exponent(roughness),
        };
        let label = format!("r = {roughness} (n = {:.0})", material.exponent);
        let histogram = raylab_core::catch_quietly("Exercise 12.3", || {
            histogram(code.as_ref(), &material, normal, wo, size, samples)
        });
        let pdf = raylab_core::catch_quietly("Exercise 12.2", || {
            projected_density(code.as_ref(), &material, normal, wo, size)
        });
        // Each column scaled by the peak of its density, so that the two rows compare.
        let peak = pdf
            .as_ref()
            .ok()
            .map(|f| f.pixels.iter().map(|p| p.x).fold(0.0f32, f32::max))
            .filter(|&p| p > 0.0 && p.is_finite())
            .unwrap_or(1.0);
        let scaled = |mut film: Film| {
            film.pixels.iter_mut().for_each(|p| *p /= peak);
            film
        };
        for (result, row, what, exercise) in [
            (histogram, &mut drawn, "drawn", "12.3"),
            (pdf, &mut density, "density", "12.2"),
        ] {
            row.push(match result {
                Ok(film) => Panel::new(scaled(film), format!("{label}, {what} ({exercise})")),
                Err(e) => {
                    notes.push(format!("Exercise {exercise} panicked: {}", e.message));
                    Panel::new(failed(size), format!("{label}: {exercise} panicked"))
                }
            });
        }
    }
    notes.dedup();
    let file = "bsdf-lobes.png";
    ctx.save_panels(&[drawn, density], file, ToneMap::default())?;
    let note = if notes.is_empty() {
        String::new()
    } else {
        format!(" — {}", notes.join("; "))
    };
    Ok(vec![Figure {
        file: file.into(),
        caption: format!(
            "The BSDF of a surface with ρ_d = 0.2 and ρ_s = 0.7 seen from 45°, from the roughest lobe (left) to a near mirror (right), looking down the normal (orthographic: the disc is the hemisphere, the mirror direction right of the centre). Top: the density of {samples} directions drawn by sample_bsdf, counted per pixel; bottom: the density bsdf returns. The rows match when the sampler draws the density it returns{note}"
        ),
        parameters: format!(
            "{size}×{size} pixels per panel, {samples} directions per panel, each column scaled by the peak of its density"
        ),
        seconds: None,
    }])
}

/// A panel marked as failed.
fn failed(size: u32) -> Film {
    let mut film = Film::new(size, size);
    film.pixels.fill(PANICKED_COLOUR);
    film
}

/// The pixel of the orthographic view down `normal` that the direction `d` falls in.
fn pixel_of(onb: &Onb, d: Vec3, size: u32) -> Option<usize> {
    let l = onb.to_local(d);
    if l.z <= 0.0 {
        return None;
    }
    let x = ((l.x * 0.5 + 0.5) * size as f32) as u32;
    let y = ((0.5 - l.y * 0.5) * size as f32) as u32;
    (x < size && y < size).then(|| (y * size + x) as usize)
}

/// The local direction through the centre of pixel `(x, y)`, `None` outside the disc.
fn centre(x: u32, y: u32, size: u32) -> Option<Vec3> {
    let px = (x as f32 + 0.5) / size as f32 * 2.0 - 1.0;
    let py = 1.0 - (y as f32 + 0.5) / size as f32 * 2.0;
    let r2 = px * px + py * py;
    (r2 < 1.0).then(|| Vec3::new(px, py, (1.0 - r2).sqrt()))
}

/// The orthographic area of one pixel, in the unit disc's units.
fn pixel_area(size: u32) -> f32 {
    let side = 2.0 / size as f32;
    side * side
}

/// The density per unit solid angle of `samples` directions of `sample_bsdf`, counted per
/// pixel: an orthographic pixel of area `a` at `cos θ` spans the solid angle `a / cos θ`.
fn histogram(
    code: &dyn PathTracing,
    material: &PathMaterial,
    normal: Vec3,
    wo: Vec3,
    size: u32,
    samples: usize,
) -> Film {
    let onb = Onb::from_w(normal);
    let mut film = Film::new(size, size);
    let mut rng = Rng::new(12, 12);
    let weight = 1.0 / (samples as f32 * pixel_area(size));
    for _ in 0..samples {
        if let Some(s) = code.sample_bsdf(material, normal, wo, &mut rng)
            && let Some(p) = pixel_of(&onb, s.direction, size)
        {
            film.pixels[p] += Vec3::splat(weight);
        }
    }
    for (i, p) in film.pixels.iter_mut().enumerate() {
        let (x, y) = (i as u32 % size, i as u32 / size);
        *p *= centre(x, y, size).map_or(0.0, |c| c.z);
    }
    film
}

/// The density `bsdf` returns at each pixel's centre (black outside the disc).
fn projected_density(
    code: &dyn PathTracing,
    material: &PathMaterial,
    normal: Vec3,
    wo: Vec3,
    size: u32,
) -> Film {
    let onb = Onb::from_w(normal);
    let mut film = Film::new(size, size);
    for y in 0..size {
        for x in 0..size {
            if let Some(local) = centre(x, y, size) {
                let wi = onb.to_world(local).normalize();
                let pdf = code.bsdf(material, normal, wo, wi).pdf;
                film.pixels[(y * size + x) as usize] = Vec3::splat(pdf);
            }
        }
    }
    film
}

/// Makes the lab's report: its figures through `pipeline` (`raylab report`).
pub fn make(
    job: &pipeline::job::ReportJob,
    pipeline: pipeline::Pipeline,
) -> Result<(), raylab_core::Error> {
    figures::make(job, crate::checks::LAB, pipeline, figures)
}
