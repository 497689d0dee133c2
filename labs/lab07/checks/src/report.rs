//! Lab 07's figures: the default scene at pixel subdivisions 1 to 4 side by side (a magnified
//! cut-out, so the staircases show) with the render times, and the image error against a
//! converged render as a function of the number of rays per pixel, as a log–log plot
//! ([`figures::plot`]) and as a table (the Week 7 questions: how render time and aliasing error depend on the
//! subdivision level).

use std::fmt::Write as _;

use crate::checks::mean_squared_error;
use raylab_core::Error;
use raylab_core::film::{Film, ToneMap};
use raylab_core::render::RenderSettings;
use raylab_core::scene::builtin_scene;

use figures::plot::{BLUE, Guide, LogLogPlot, Series};
use figures::{Figure, Panel, ReportContext, settings, timed};

/// The subdivisions of the side-by-side figure.
const PANEL_SUBDIVISIONS: [u32; 4] = [1, 2, 3, 4];
/// The cut-out of the panels, as fractions of the image: left, top, width, height (the right
/// edge of the red sphere, the mirror sphere's shadow and the torus).
const CROP: [f32; 4] = [0.29, 0.365, 0.25, 0.25];
/// Magnification of the cut-out (nearest neighbour, so each pixel shows as a block).
const ZOOM: u32 = 3;
/// The subdivisions of the error plot.
const PLOT_SUBDIVISIONS: [u32; 8] = [1, 2, 3, 4, 5, 6, 7, 8];

/// The figures of lab 07.
pub fn figures(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    Ok(vec![subdivision_panels(ctx)?, error_plot(ctx)?])
}

fn subdivided(w: u32, h: u32, s: u32, seed: u64) -> RenderSettings {
    RenderSettings {
        pixel_subdivisions: s,
        seed,
        ..settings(w, h, 1)
    }
}

/// The cut-out [`CROP`] of `film`, magnified [`ZOOM`] times.
fn crop_zoom(film: &Film) -> Film {
    figures::crop_zoom(film, CROP, ZOOM)
}

fn subdivision_panels(ctx: &ReportContext) -> Result<Figure, Error> {
    let (w, h) = ctx.size(512, 384);
    let scene = builtin_scene("default")?;
    let mut panels = Vec::new();
    let mut times = Vec::new();
    for s in PANEL_SUBDIVISIONS {
        let (film, seconds) = ctx.render_timed(&scene, &ctx.pipeline, &subdivided(w, h, s, 0))?;
        panels.push(Panel::new(
            crop_zoom(&film),
            timed(&format!("s = {s}"), seconds),
        ));
        times.push(seconds);
    }
    let file = "subdivisions-1-to-4.png";
    ctx.save_panels(&[panels], file, ToneMap::default())?;
    let mut table = String::from(
        "| subdivision s | rays per pixel s² | render time (s) | time relative to s = 1 |\n| --- | --- | --- | --- |\n",
    );
    for (s, t) in PANEL_SUBDIVISIONS.iter().zip(&times) {
        let _ = writeln!(table, "| {s} | {} | {t:.3} | {:.1} |", s * s, t / times[0]);
    }
    let (cw, ch) = ((CROP[2] * w as f32) as u32, (CROP[3] * h as f32) as u32);
    Ok(Figure {
        file: file.into(),
        caption: "The default scene with pixel subdivision s = 1, 2, 3 and 4 (left to right)"
            .into(),
        parameters: format!(
            "each panel is a {cw}×{ch} cut-out of a {w}×{h} render (the red sphere's right edge, the mirror sphere and the torus), magnified {ZOOM}× with nearest-neighbour pixels; s = 1 traces one ray through each pixel centre, s > 1 traces s × s jittered subpixel rays and averages them; seed 0, clamp tone map. Render time of each whole image:\n\n{table}\nAll four renders together"
        ),
        seconds: Some(times.iter().sum()),
    })
}

/// Least-squares slope of `ln y` against `ln x`.
fn log_log_slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = points.iter().map(|(x, y)| (x.ln(), y.ln())).unzip();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

fn error_plot(ctx: &ReportContext) -> Result<Figure, Error> {
    let (w, h) = if ctx.quick { (64, 48) } else { (256, 192) };
    let converged_s = if ctx.quick { 12 } else { 24 };
    let scene = builtin_scene("default")?;
    let (converged, converged_time) =
        ctx.render_timed(&scene, &ctx.pipeline, &subdivided(w, h, converged_s, 1000))?;
    let mut rows = Vec::new();
    for s in PLOT_SUBDIVISIONS {
        let (film, seconds) = ctx.render_timed(&scene, &ctx.pipeline, &subdivided(w, h, s, 0))?;
        let rmse = mean_squared_error(&film, &converged).sqrt();
        rows.push((s, seconds, rmse));
    }
    let points: Vec<(f64, f64)> = rows.iter().map(|&(s, _, e)| ((s * s) as f64, e)).collect();
    let slope = log_log_slope(&points[1..]);
    let file = "error-vs-rays-per-pixel.png";
    let figure = LogLogPlot {
        x_decades: (0, 2),
        x_label: "rays per pixel",
        y_label: "RMS error",
        series: vec![Series {
            name: "measured (s = 1 to 8)",
            points: &points,
            colour: BLUE,
            markers: true,
        }],
        // Slopes −1/2 and −3/4 through the s = 2 point.
        guides: vec![
            Guide {
                slope: -0.5,
                through: points[1],
                name: "slope -1/2 (random)",
            },
            Guide {
                slope: -0.75,
                through: points[1],
                name: "slope -3/4 (jittered, edges)",
            },
        ],
    };
    ctx.save_plot(&figure, file)?;

    let mut table = String::from(
        "| s | rays per pixel s² | render time (s) | RMS error | error relative to s = 1 |\n| --- | --- | --- | --- | --- |\n",
    );
    for &(s, t, e) in &rows {
        let _ = writeln!(
            table,
            "| {s} | {} | {t:.3} | {e:.5} | {:.3} |",
            s * s,
            e / rows[0].2
        );
    }
    Ok(Figure {
        file: file.into(),
        caption: "RMS error against rays per pixel, log–log".into(),
        parameters: format!(
            "the default scene at {w}×{h}, rendered with s = 1 … 8 (seed 0) and compared with a converged render at s = {converged_s} ({} rays per pixel, seed 1000, {converged_time:.2} s); the error is the root mean square over pixels and channels of the difference in linear radiance. Blue: the measured errors (s = 1 is one ray through the pixel centre). Dashed grey lines through the s = 2 point: slopes −1/2 (the error of independent random samples, ∝ 1/√N) and −3/4 (jittered samples on edges, ∝ N^(−3/4)). Least-squares slope of the measured errors from s = 2 to 8: {slope:.2}.\n\n{table}\nAll eight renders together (the converged render not included)",
            converged_s * converged_s
        ),
        seconds: Some(rows.iter().map(|r| r.1).sum()),
    })
}

/// Makes the lab's report: its figures through `pipeline` (`raylab report`).
pub fn make(
    job: &pipeline::job::ReportJob,
    pipeline: pipeline::Pipeline,
) -> Result<(), raylab_core::Error> {
    figures::make(job, crate::checks::LAB, pipeline, figures)
}
