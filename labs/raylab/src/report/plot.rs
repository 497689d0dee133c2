//! The reports' line plot: a few series on log–log axes with dashed guide lines, drawn
//! into a [`Film`] with a 5×7 pixel font (written as PNG like every figure).

use framework::film::Film;
use framework::glam::{Vec2, Vec3};

const PLOT_W: u32 = 660;
const PLOT_H: u32 = 460;
/// Plot area: left, top, right, bottom.
const AREA: [f32; 4] = [78.0, 40.0, 620.0, 390.0];
const INK: Vec3 = Vec3::new(0.0, 0.0, 0.0);
const GRID: Vec3 = Vec3::new(0.75, 0.75, 0.75);
const GUIDE: Vec3 = Vec3::new(0.35, 0.35, 0.35);
/// The colour of a plot's first series.
pub const BLUE: Vec3 = Vec3::new(0.02, 0.12, 0.7);
/// The colour of a plot's second series.
pub const ORANGE: Vec3 = Vec3::new(0.85, 0.33, 0.02);

/// One series of a [`LogLogPlot`]: its `(x, y)` points and their colour.
pub struct Series<'a> {
    /// The points, `x` and `y` positive.
    pub points: &'a [(f64, f64)],
    /// The colour of the polyline and its markers.
    pub colour: Vec3,
}

/// A log–log plot of a few series, drawn into a film (the reports' own line plot).
pub struct LogLogPlot<'a> {
    /// The decades of the x axis: `10^lo … 10^hi`.
    pub x_decades: (i32, i32),
    /// The x axis's title (lower-case letters, digits, spaces and `.`).
    pub x_label: &'a str,
    /// The y axis's title.
    pub y_label: &'a str,
    /// The data.
    pub series: Vec<Series<'a>>,
    /// Dashed guide lines: a slope and a point it goes through.
    pub guides: Vec<(f64, (f64, f64))>,
}

impl LogLogPlot<'_> {
    /// Draws the plot: each series a polyline with markers, the dashed guide lines, decade
    /// ticks and labels, axis titles.
    pub fn draw(&self) -> Film {
        plot(self)
    }
}

fn plot(p: &LogLogPlot) -> Film {
    let mut film = Film::new(PLOT_W, PLOT_H);
    film.pixels.fill(Vec3::ONE);
    let (x_lo, x_hi) = (p.x_decades.0 as f64, p.x_decades.1 as f64);
    let ys = || p.series.iter().flat_map(|s| s.points.iter().map(|q| q.1));
    let y_min = ys().fold(f64::INFINITY, f64::min);
    let y_max = ys().fold(0.0, f64::max);
    // No data (every series unfinished): an empty plot over three decades.
    let y_lo = if y_min.is_finite() && y_min > 0.0 {
        y_min.log10().floor()
    } else {
        -3.0
    };
    let y_hi = if y_max > 0.0 {
        y_max.log10().ceil()
    } else {
        0.0
    }
    .max(y_lo + 1.0);
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
        p.x_label,
        Vec2::new(0.5 * (left + right), bottom + 38.0),
        2,
    );
    text(&mut film, p.y_label, Vec2::new(left - 60.0, top - 28.0), 2);
    // Guide lines.
    let (x_min, x_max) = (10f64.powf(x_lo), 10f64.powf(x_hi));
    for &(slope, (x0, y0)) in &p.guides {
        let at = |x: f64| y0 * (x / x0).powf(slope);
        dashed(
            &mut film,
            to_screen(x_min, at(x_min)),
            to_screen(x_max, at(x_max)),
            GUIDE,
        );
    }
    // The data.
    for series in &p.series {
        let screen: Vec<Vec2> = series
            .points
            .iter()
            .map(|&(x, y)| to_screen(x, y))
            .collect();
        for pair in screen.windows(2) {
            line(&mut film, pair[0], pair[1], series.colour, 1.2);
        }
        for &q in &screen {
            disc(&mut film, q, 4.5, series.colour);
            disc(&mut film, q, 2.5, Vec3::ONE);
        }
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
        'm' => [
            "     ", "     ", "## # ", "# # #", "# # #", "# # #", "#   #",
        ],
        'n' => [
            "     ", "     ", "# ## ", "##  #", "#   #", "#   #", "#   #",
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
        't' => [
            " #   ", " #   ", "#### ", " #   ", " #   ", " #  #", "  ## ",
        ],
        'u' => [
            "     ", "     ", "#   #", "#   #", "#   #", "#  ##", " ## #",
        ],
        'v' => [
            "     ", "     ", "#   #", "#   #", "#   #", " # # ", "  #  ",
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
