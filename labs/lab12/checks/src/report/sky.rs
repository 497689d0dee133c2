//! Lab 12's figures of the sky: the path tracer's materials side by side under a real sky;
//! BSDF sampling, light sampling and both weighted by the power heuristic at equal time; and
//! the sky's distribution — the directions Exercise 12.12 draws against the density Exercise
//! 12.13 returns.

use std::f32::consts::PI;
use std::path::Path;

use glam::Vec3;

use contracts::lab12::{PathTracing, SkyDistribution};
use contracts::sampling::Rng;
use figures::{Figure, Panel, ReportContext, settings, timed};
use pipeline::Pipeline;
use pipeline::job::prepare;
use pipeline::path::PathSampling;
use raylab_core::Error;
use raylab_core::film::{Film, ToneMap};
use raylab_core::scene::{EnvironmentMap, Scene, load_scene_file};

use super::failed;
use crate::sky::{cell_of, latlong_direction};

/// The exposure of the sky's renders: the city sky is bright.
const EXPOSURE: ToneMap = ToneMap::Clamp { exposure: 0.6 };

/// The lab's sky scene, `labs/lab12/scenes/sky-spheres.toml`.
pub fn sky_scene() -> Result<Scene, Error> {
    load_scene_file(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/sky-spheres.toml"))
}

/// The figures of the sky.
pub fn figures(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    let scene = sky_scene()?;
    let mut note = String::new();
    let pipeline = prepare(ctx.pipeline.clone(), &scene, |line| {
        note.push_str(" — ");
        note.push_str(&line);
    });
    Ok(vec![
        materials(ctx, &scene, &pipeline, &note)?,
        strategies(ctx, &scene, &pipeline, &note)?,
        distribution(ctx, &scene, &pipeline)?,
    ])
}

/// The materials side by side.
fn materials(
    ctx: &ReportContext,
    scene: &Scene,
    pipeline: &Pipeline,
    note: &str,
) -> Result<Figure, Error> {
    let (w, h) = ctx.size(480, 200);
    let spp = if ctx.quick { 8 } else { 256 };
    let (film, seconds) = ctx.render_timed(scene, pipeline, &settings(w, h, spp))?;
    let file = "sky-materials.png";
    ctx.save_labelled(film, timed(&format!("{spp} spp"), seconds), file, EXPOSURE)?;
    Ok(Figure {
        file: file.into(),
        caption: format!(
            "The path tracer's materials under a city sky with a bright sun (labs/lab12/scenes/sky-spheres.toml; the sky CC0, from Debian's blender-data): Lambertian, the glossy lobe over a diffuse base at roughness 0.5, 0.25 and 0.1, and a mirror. The sky is drawn by next-event estimation by its luminance (Exercises 12.11–12.13), so the sun's sharp shadows and highlights converge like the rest{note}"
        ),
        parameters: format!(
            "{w}×{h} pixels, {spp} samples per pixel, at most {} bounces, exposure 0.6",
            pipeline.max_depth
        ),
        seconds: Some(seconds),
    })
}

/// The three strategies at equal time.
fn strategies(
    ctx: &ReportContext,
    scene: &Scene,
    pipeline: &Pipeline,
    note: &str,
) -> Result<Figure, Error> {
    let (w, h) = ctx.size(320, 134);
    let spp = if ctx.quick { 4 } else { 32 };
    let kinds = [
        (PathSampling::Bsdf, "BSDF sampling only"),
        (PathSampling::Light, "light sampling only"),
        (PathSampling::Mis, "both, power heuristic"),
    ];
    let with = |sampling| {
        let mut pipeline = pipeline.clone();
        pipeline.path_sampling = sampling;
        pipeline
    };
    // Seconds per sample of each, from a short render; the time of the weighted one at `spp`
    // samples is every strategy's budget.
    let probe = 4;
    let mut per_sample = Vec::new();
    for (sampling, _) in kinds {
        let (_, s) = ctx.render_timed(scene, &with(sampling), &settings(w, h, probe))?;
        per_sample.push(s / f64::from(probe));
    }
    let budget = per_sample[2] * f64::from(spp);
    let mut panels = Vec::new();
    let mut total = 0.0;
    let mut used = Vec::new();
    for ((sampling, name), t) in kinds.into_iter().zip(&per_sample) {
        let n = ((budget / t).round() as u32).max(1);
        let (film, s) = ctx.render_timed(scene, &with(sampling), &settings(w, h, n))?;
        total += s;
        used.push(format!("{name} {n} spp in {s:.2} s"));
        panels.push(Panel::new(film, timed(&format!("{name}, {n} spp"), s)));
    }
    let file = "sky-strategies.png";
    ctx.save_panels(&[panels], file, EXPOSURE)?;
    Ok(Figure {
        file: file.into(),
        caption: format!(
            "The same scene at equal time, the light found three ways. BSDF sampling only: the sun, a small bright source, is found by chance — fireflies on the matte sphere and the floor. Light sampling only: the sky by its luminance, the shadows clean, but the mirror and the polished sphere, whose lobes the sky sampler rarely hits, are noise. Both weighted by the power heuristic (Exercise 12.6): each light path taken from the strategy that finds it best ({}){note}",
            used.join(", ")
        ),
        parameters: format!(
            "{w}×{h} pixels per panel, samples per pixel set so that each takes the time of {spp} samples of the weighted one (from a 4-sample render of each)"
        ),
        seconds: Some(total),
    })
}

/// The sky, the density of the directions 12.12 draws and the density 12.13 returns, over the
/// image's `(u, v)` on a logarithmic scale.
fn distribution(ctx: &ReportContext, scene: &Scene, pipeline: &Pipeline) -> Result<Figure, Error> {
    let (w, h) = if ctx.quick { (128, 64) } else { (256, 128) };
    let samples = if ctx.quick { 100_000 } else { 2_000_000 };
    let env = scene.environment.as_ref().ok_or_else(|| Error::Failed {
        what: "the sky scene".into(),
        reason: "it has no [environment]".into(),
    })?;
    let code = pipeline.code::<dyn contracts::lab12::PathTracing>();
    let code = code.as_ref();
    let sky_panel = Panel::new(downsampled(env, w, h), "the sky (exposure 0.3)");
    let mut notes = Vec::new();
    let (drawn, density) = match &pipeline.sky {
        Some(sky) => {
            let drawn = raylab_core::catch_quietly("Exercise 12.12", || {
                drawn_density(code, sky, w, h, samples)
            });
            let density =
                raylab_core::catch_quietly("Exercise 12.13", || returned_density(code, sky, w, h));
            let mut films = [drawn.ok(), density.ok()];
            log_scaled(&mut films);
            let [drawn, density] = films;
            let mut panel = |film: Option<Film>, what: &str, id: &str| match film {
                Some(film) => Panel::new(film, format!("{what} ({id})")),
                None => {
                    notes.push(format!("Exercise {id} panicked"));
                    Panel::new(failed_wide(w, h), format!("{id} panicked"))
                }
            };
            (
                panel(drawn, "directions drawn", "12.12"),
                panel(density, "density returned", "12.13"),
            )
        }
        None => {
            notes.push("Exercise 12.11's distribution was refused".to_string());
            (
                Panel::new(failed_wide(w, h), "no distribution (12.11)"),
                Panel::new(failed_wide(w, h), "no distribution (12.11)"),
            )
        }
    };
    let file = "sky-distribution.png";
    ctx.save_panels(&[vec![sky_panel, drawn, density]], file, ToneMap::default())?;
    let note = if notes.is_empty() {
        String::new()
    } else {
        format!(" — {}", notes.join("; "))
    };
    Ok(Figure {
        file: file.into(),
        caption: format!(
            "The sky (left) and the density of its distribution over the image (logarithmic: black is none, white the sun): middle, {samples} directions drawn by sample_sky counted per pixel; right, sky_pdf at each pixel's centre times the Jacobian 2π² sin θ. Both follow the luminance weighted by sin θ — the sun, the bright lower sky, little near the poles — and must match{note}"
        ),
        parameters: format!("{w}×{h} pixels per panel, the sky's 1024×512 texels"),
        seconds: None,
    })
}

/// A `w × h` panel marked as failed.
fn failed_wide(w: u32, h: u32) -> Film {
    let square = failed(1);
    let mut film = Film::new(w, h);
    film.pixels.fill(square.pixels[0]);
    film
}

/// The probe averaged down to `w × h`, at the exposure 0.3.
fn downsampled(env: &EnvironmentMap, w: u32, h: u32) -> Film {
    let t = &env.texture;
    let mut film = Film::new(w, h);
    for (i, p) in film.pixels.iter_mut().enumerate() {
        let (x, y) = (i as u32 % w, i as u32 / w);
        let (x0, x1) = (
            x * t.width / w,
            ((x + 1) * t.width / w).max(x * t.width / w + 1),
        );
        let (y0, y1) = (
            y * t.height / h,
            ((y + 1) * t.height / h).max(y * t.height / h + 1),
        );
        let mut sum = Vec3::ZERO;
        for ty in y0..y1 {
            for tx in x0..x1 {
                sum += t.texels[(ty * t.width + tx) as usize];
            }
        }
        *p = sum * env.scale * 0.3 / ((x1 - x0) * (y1 - y0)) as f32;
    }
    film
}

/// The density over `(u, v)` of `samples` directions of `sample_sky`, per pixel.
fn drawn_density(
    code: &dyn PathTracing,
    sky: &SkyDistribution,
    w: u32,
    h: u32,
    samples: usize,
) -> Film {
    let mut film = Film::new(w, h);
    let mut rng = Rng::new(12, 13);
    let weight = (w * h) as f32 / samples as f32;
    for _ in 0..samples {
        let Some(s) = code.sample_sky(sky, &mut rng) else {
            continue;
        };
        film.pixels[cell_of(s.direction, w as usize, h as usize)] += Vec3::splat(weight);
    }
    film
}

/// `sky_pdf` at each pixel's centre, over `(u, v)`: times `2π² sin θ`.
fn returned_density(code: &dyn PathTracing, sky: &SkyDistribution, w: u32, h: u32) -> Film {
    let mut film = Film::new(w, h);
    for (i, p) in film.pixels.iter_mut().enumerate() {
        let u = ((i as u32 % w) as f64 + 0.5) / w as f64;
        let v = ((i as u32 / w) as f64 + 0.5) / h as f64;
        let d = latlong_direction(u, v).as_vec3();
        let jacobian = 2.0 * PI * PI * (PI * v as f32).sin();
        *p = Vec3::splat(code.sky_pdf(sky, d) * jacobian);
    }
    film
}

/// The densities on one logarithmic scale, `log(1 + 100 p) / log(1 + 100 p_max)`, `p_max` the
/// largest of their peaks (the uniform density is 1).
fn log_scaled(films: &mut [Option<Film>]) {
    let peak = films
        .iter()
        .flatten()
        .flat_map(|f| f.pixels.iter().map(|p| p.x))
        .filter(|x| x.is_finite())
        .fold(0.0f32, f32::max);
    let top = (1.0 + 100.0 * peak).ln().max(1e-6);
    for film in films.iter_mut().flatten() {
        for p in film.pixels.iter_mut() {
            *p = Vec3::splat((1.0 + 100.0 * p.x.max(0.0)).ln() / top);
        }
    }
}
