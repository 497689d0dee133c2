//! Lab 07's figures: the default scene at pixel subdivisions 1 to 4 side by side (a magnified
//! cut-out, so the staircases show) with the render times, and the image error against a
//! converged render as a function of the number of rays per pixel, as a log–log plot drawn
//! here and as a table (the Week 7 questions: how render time and aliasing error depend on the
//! subdivision level).

use std::fmt::Write as _;

use framework::Error;
use framework::film::{Film, ToneMap};
use framework::glam::{Vec2, Vec3};
use framework::labs::lab07::checks::mean_squared_error;
use framework::render::RenderSettings;
use framework::scene::builtin_scene;

use super::{Figure, ReportContext, montage, settings};

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
    let (w, h) = (film.width as f32, film.height as f32);
    let (x0, y0) = ((CROP[0] * w) as u32, (CROP[1] * h) as u32);
    let (cw, ch) = ((CROP[2] * w) as u32, (CROP[3] * h) as u32);
    let mut out = Film::new(cw * ZOOM, ch * ZOOM);
    for y in 0..out.height {
        for x in 0..out.width {
            out.set(x, y, film.get(x0 + x / ZOOM, y0 + y / ZOOM));
        }
    }
    out
}

fn subdivision_panels(ctx: &ReportContext) -> Result<Figure, Error> {
    let (w, h) = ctx.size(512, 384);
    let scene = builtin_scene("default")?;
    let mut panels = Vec::new();
    let mut times = Vec::new();
    for s in PANEL_SUBDIVISIONS {
        let (film, seconds) = ctx.render_timed(&scene, &ctx.pipeline, &subdivided(w, h, s, 0))?;
        panels.push(crop_zoom(&film));
        times.push(seconds);
    }
    let file = "subdivisions-1-to-4.png";
    ctx.save(&montage(&panels, 4), file, ToneMap::default())?;
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
    ctx.save(&plot(&points), file, ToneMap::default())?;

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

// ---------------------------------------------------------------------------------------------
// A log–log plot drawn into a film

const PLOT_W: u32 = 660;
const PLOT_H: u32 = 460;
/// Plot area: left, top, right, bottom.
const AREA: [f32; 4] = [78.0, 40.0, 620.0, 390.0];
const INK: Vec3 = Vec3::new(0.0, 0.0, 0.0);
const GRID: Vec3 = Vec3::new(0.75, 0.75, 0.75);
const GUIDE: Vec3 = Vec3::new(0.35, 0.35, 0.35);
const DATA: Vec3 = Vec3::new(0.02, 0.12, 0.7);

/// Plots `(x, y)` points on log–log axes: a polyline with markers, two dashed guide lines of
/// slope −1/2 and −3/4 through the second point, decade ticks and labels, axis titles.
fn plot(points: &[(f64, f64)]) -> Film {
    let mut film = Film::new(PLOT_W, PLOT_H);
    film.pixels.fill(Vec3::ONE);
    let (x_lo, x_hi) = (0.0f64, 2.0f64); // 10⁰ … 10²
    let y_min = points.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    let y_max = points.iter().map(|p| p.1).fold(0.0, f64::max);
    let y_lo = y_min.log10().floor();
    let y_hi = y_max.log10().ceil().max(y_lo + 1.0);
    let [left, top, right, bottom] = AREA;
    let to_screen = |x: f64, y: f64| {
        Vec2::new(
            left + ((x.log10() - x_lo) / (x_hi - x_lo)) as f32 * (right - left),
            bottom - ((y.log10() - y_lo) / (y_hi - y_lo)) as f32 * (bottom - top),
        )
    };
    // Grid, ticks and labels.
    for decade in x_lo as i32..=x_hi as i32 {
        for m in 1..10 {
            let x = 10f64.powi(decade) * m as f64;
            if x.log10() > x_hi + 1e-9 {
                break;
            }
            let px = to_screen(x, 10f64.powf(y_lo)).x;
            line(
                &mut film,
                Vec2::new(px, top),
                Vec2::new(px, bottom),
                GRID,
                0.5,
            );
            let len = if m == 1 { 8.0 } else { 4.0 };
            line(
                &mut film,
                Vec2::new(px, bottom),
                Vec2::new(px, bottom + len),
                INK,
                0.7,
            );
            if m == 1 {
                let label = format!("{}", 10u32.pow(decade as u32));
                text_centred(&mut film, &label, Vec2::new(px, bottom + 18.0), 2);
            }
        }
    }
    for decade in y_lo as i32..=y_hi as i32 {
        for m in 1..10 {
            let y = 10f64.powi(decade) * m as f64;
            if y.log10() > y_hi + 1e-9 {
                break;
            }
            let py = to_screen(1.0, y).y;
            line(
                &mut film,
                Vec2::new(left, py),
                Vec2::new(right, py),
                GRID,
                0.5,
            );
            let len = if m == 1 { 8.0 } else { 4.0 };
            line(
                &mut film,
                Vec2::new(left - len, py),
                Vec2::new(left, py),
                INK,
                0.7,
            );
            if m == 1 {
                let label = decimal(decade);
                let width = text_width(&label, 2) as f32;
                text(
                    &mut film,
                    &label,
                    Vec2::new(left - 12.0 - width, py - 7.0),
                    2,
                );
            }
        }
    }
    // Axes.
    line(
        &mut film,
        Vec2::new(left, bottom),
        Vec2::new(right, bottom),
        INK,
        1.0,
    );
    line(
        &mut film,
        Vec2::new(left, top),
        Vec2::new(left, bottom),
        INK,
        1.0,
    );
    text_centred(
        &mut film,
        "rays per pixel",
        Vec2::new(0.5 * (left + right), bottom + 38.0),
        2,
    );
    text(
        &mut film,
        "RMS error",
        Vec2::new(left - 60.0, top - 28.0),
        2,
    );
    // Guide lines of slope −1/2 and −3/4 through the second point.
    if let Some(&(x0, y0)) = points.get(1) {
        for slope in [-0.5, -0.75] {
            let at = |x: f64| y0 * (x / x0).powf(slope);
            dashed(
                &mut film,
                to_screen(1.0, at(1.0)),
                to_screen(100.0, at(100.0)),
                GUIDE,
            );
        }
    }
    // The data.
    let screen: Vec<Vec2> = points.iter().map(|&(x, y)| to_screen(x, y)).collect();
    for pair in screen.windows(2) {
        line(&mut film, pair[0], pair[1], DATA, 1.2);
    }
    for &p in &screen {
        disc(&mut film, p, 4.5, DATA);
        disc(&mut film, p, 2.5, Vec3::ONE);
    }
    film
}

/// `10^decade` written out as a decimal number (`0.001`, `0.1`, `1`, `10`).
fn decimal(decade: i32) -> String {
    if decade >= 0 {
        10u64.pow(decade as u32).to_string()
    } else {
        format!("0.{}1", "0".repeat((-decade - 1) as usize))
    }
}

/// Paints `colour` at pixel `(x, y)` when it lies on the film.
fn paint(film: &mut Film, x: i64, y: i64, colour: Vec3) {
    if x >= 0 && y >= 0 && (x as u32) < film.width && (y as u32) < film.height {
        film.set(x as u32, y as u32, colour);
    }
}

/// A filled disc.
fn disc(film: &mut Film, c: Vec2, r: f32, colour: Vec3) {
    let r2 = r * r;
    for y in (c.y - r).floor() as i64..=(c.y + r).ceil() as i64 {
        for x in (c.x - r).floor() as i64..=(c.x + r).ceil() as i64 {
            let d = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) - c;
            if d.length_squared() <= r2 {
                paint(film, x, y, colour);
            }
        }
    }
}

/// A line `half_width` pixels either side of the segment `a`–`b`.
fn line(film: &mut Film, a: Vec2, b: Vec2, colour: Vec3, half_width: f32) {
    let steps = ((b - a).length() * 2.0).ceil().max(1.0) as u32;
    for k in 0..=steps {
        let p = a.lerp(b, k as f32 / steps as f32);
        disc(film, p, half_width.max(0.5), colour);
    }
}

/// A dashed line clipped to the plot area.
fn dashed(film: &mut Film, a: Vec2, b: Vec2, colour: Vec3) {
    let [left, top, right, bottom] = AREA;
    let length = (b - a).length();
    let steps = (length * 2.0).ceil() as u32;
    for k in 0..=steps {
        let t = k as f32 / steps.max(1) as f32;
        let p = a.lerp(b, t);
        let on = ((t * length / 6.0) as u32).is_multiple_of(2);
        if on && p.x >= left && p.x <= right && p.y >= top && p.y <= bottom {
            disc(film, p, 0.7, colour);
        }
    }
}

/// The 5×7 glyph of `c` (rows from the top, `#` = ink), for the few characters the plot needs.
fn glyph(c: char) -> [&'static str; 7] {
    match c {
        '0' => [
            " ### ", "#   #", "#  ##", "# # #", "##  #", "#   #", " ### ",
        ],
        '1' => [
            "  #  ", " ##  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### ",
        ],
        '.' => [
            "     ", "     ", "     ", "     ", "     ", " ##  ", " ##  ",
        ],
        'a' => [
            "     ", "     ", " ### ", "    #", " ####", "#   #", " ####",
        ],
        'e' => [
            "     ", "     ", " ### ", "#   #", "#####", "#    ", " ### ",
        ],
        'i' => [
            "  #  ", "     ", " ##  ", "  #  ", "  #  ", "  #  ", " ### ",
        ],
        'l' => [
            " ##  ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### ",
        ],
        'o' => [
            "     ", "     ", " ### ", "#   #", "#   #", "#   #", " ### ",
        ],
        'p' => [
            "     ", "     ", "#### ", "#   #", "#### ", "#    ", "#    ",
        ],
        'r' => [
            "     ", "     ", "# ## ", "##  #", "#    ", "#    ", "#    ",
        ],
        's' => [
            "     ", "     ", " ####", "#    ", " ### ", "    #", "#### ",
        ],
        'x' => [
            "     ", "     ", "#   #", " # # ", "  #  ", " # # ", "#   #",
        ],
        'y' => [
            "     ", "     ", "#   #", "#   #", " ####", "    #", " ### ",
        ],
        'M' => [
            "#   #", "## ##", "# # #", "# # #", "#   #", "#   #", "#   #",
        ],
        'R' => [
            "#### ", "#   #", "#   #", "#### ", "# #  ", "#  # ", "#   #",
        ],
        'S' => [
            " ####", "#    ", "#    ", " ### ", "    #", "    #", "#### ",
        ],
        _ => ["     "; 7],
    }
}

/// Width in pixels of `s` drawn at `scale`.
fn text_width(s: &str, scale: u32) -> u32 {
    s.chars().count() as u32 * 6 * scale
}

/// Draws `s` with its top-left corner at `at`, each font pixel `scale` × `scale`.
fn text(film: &mut Film, s: &str, at: Vec2, scale: u32) {
    for (k, c) in s.chars().enumerate() {
        let x0 = at.x as i64 + (k as u32 * 6 * scale) as i64;
        for (row, bits) in glyph(c).iter().enumerate() {
            for (col, b) in bits.chars().enumerate() {
                if b != '#' {
                    continue;
                }
                for dy in 0..scale as i64 {
                    for dx in 0..scale as i64 {
                        paint(
                            film,
                            x0 + col as i64 * scale as i64 + dx,
                            at.y as i64 + row as i64 * scale as i64 + dy,
                            INK,
                        );
                    }
                }
            }
        }
    }
}

/// Draws `s` centred horizontally on `at.x`, its top at `at.y`.
fn text_centred(film: &mut Film, s: &str, at: Vec2, scale: u32) {
    let w = text_width(s, scale) as f32;
    text(film, s, Vec2::new(at.x - 0.5 * w, at.y), scale);
}
