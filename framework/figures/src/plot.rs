//! The reports' drawings that carry text: the log–log error plot (axes, ticks, a legend and
//! labelled guide lines) and the label strip under each render panel. Both are drawn with
//! `plotters` into 8-bit sRGB pixels, with the Hack typeface of `epaint_default_fonts`
//! registered once, so no system font is needed.

use std::sync::Once;

use image::RgbImage;
use plotters::coord::Shift;
use plotters::prelude::*;

/// The plot's size in pixels.
const PLOT_SIZE: (u32, u32) = (720, 480);
/// The font family the drawings use (the registered Hack typeface).
const FONT: &str = "sans-serif";
/// The colour of a plot's first series.
pub const BLUE: RGBColor = RGBColor(5, 60, 180);
/// The colour of a plot's second series.
pub const ORANGE: RGBColor = RGBColor(217, 84, 5);
/// A red series.
pub const RED: RGBColor = RGBColor(200, 25, 25);
/// The colour of the guide lines.
const GUIDE: RGBColor = RGBColor(90, 90, 90);

/// Registers the typeface with plotters, once per process.
fn register_font() {
    static REGISTER: Once = Once::new();
    REGISTER.call_once(|| {
        // The bytes are a valid TrueType font; a failure would only leave the text undrawn.
        let _ = plotters::style::register_font(
            FONT,
            FontStyle::Normal,
            epaint_default_fonts::HACK_REGULAR,
        );
    });
}

/// Draws with `draw` on a white `width × height` area and returns the pixels; a drawing
/// error (which only a font without a glyph could cause) leaves what was drawn so far.
fn drawn(
    width: u32,
    height: u32,
    draw: impl FnOnce(&DrawingArea<BitMapBackend, Shift>) -> Result<(), String>,
) -> RgbImage {
    register_font();
    let mut image = RgbImage::from_pixel(width, height, image::Rgb([255; 3]));
    {
        let root = BitMapBackend::with_buffer(&mut image, (width, height)).into_drawing_area();
        let _ = draw(&root);
        let _ = root.present();
    }
    image
}

/// One series of a [`LogLogPlot`]: its name in the legend, its `(x, y)` points and their
/// colour.
pub struct Series<'a> {
    /// The legend's entry.
    pub name: &'a str,
    /// The points, `x` and `y` positive.
    pub points: &'a [(f64, f64)],
    /// The colour of the polyline and its markers.
    pub colour: RGBColor,
    /// Whether each point gets a marker (for a few measured points, not a dense curve).
    pub markers: bool,
}

/// A dashed guide line `y = y0 · (x / x0)^slope` of a [`LogLogPlot`], named in the legend.
pub struct Guide<'a> {
    /// The slope on the log–log axes.
    pub slope: f64,
    /// A point `(x0, y0)` it goes through.
    pub through: (f64, f64),
    /// The legend's entry (for example "slope −1/2").
    pub name: &'a str,
}

/// A log–log plot of a few series with guide lines, axes, ticks and a legend.
pub struct LogLogPlot<'a> {
    /// The decades of the x axis: `10^lo … 10^hi`.
    pub x_decades: (i32, i32),
    /// The x axis's title.
    pub x_label: &'a str,
    /// The y axis's title.
    pub y_label: &'a str,
    /// The data.
    pub series: Vec<Series<'a>>,
    /// The guide lines.
    pub guides: Vec<Guide<'a>>,
}

impl LogLogPlot<'_> {
    /// The y range: whole decades around the data (three decades below 1 when no series
    /// has a point, as when every series is unfinished).
    fn y_range(&self) -> (f64, f64) {
        let ys = || {
            self.series
                .iter()
                .flat_map(|s| s.points.iter().map(|q| q.1))
        };
        let y_min = ys().filter(|y| *y > 0.0).fold(f64::INFINITY, f64::min);
        let y_max = ys().fold(0.0, f64::max);
        let lo = if y_min.is_finite() {
            y_min.log10().floor()
        } else {
            -3.0
        };
        let hi = if y_max > 0.0 {
            y_max.log10().ceil()
        } else {
            0.0
        }
        .max(lo + 1.0);
        (10f64.powf(lo), 10f64.powf(hi))
    }

    /// Draws the plot.
    pub fn draw(&self) -> RgbImage {
        drawn(PLOT_SIZE.0, PLOT_SIZE.1, |root| {
            root.fill(&WHITE).map_err(|e| e.to_string())?;
            let x = (10f64.powi(self.x_decades.0), 10f64.powi(self.x_decades.1));
            let y = self.y_range();
            let mut chart = ChartBuilder::on(root)
                .margin(18)
                .x_label_area_size(56)
                .y_label_area_size(84)
                // A hair wider than the decades, so that their end ticks are labelled too.
                .build_cartesian_2d(
                    (x.0 * 0.999..x.1 * 1.001).log_scale(),
                    (y.0 * 0.999..y.1 * 1.001).log_scale(),
                )
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .x_desc(self.x_label)
                .y_desc(self.y_label)
                .label_style((FONT, 15))
                .axis_desc_style((FONT, 17))
                .x_label_formatter(&|v| number(*v))
                .y_label_formatter(&|v| number(*v))
                .light_line_style(RGBColor(235, 235, 235))
                .bold_line_style(RGBColor(200, 200, 200))
                .draw()
                .map_err(|e| e.to_string())?;
            for (k, guide) in self.guides.iter().enumerate() {
                // Dashes for the first guide, dots for the second, and so on.
                let (dash, space) = [(7, 5), (2, 4), (12, 4)][k % 3];
                let at = |x: f64| guide.through.1 * (x / guide.through.0).powf(guide.slope);
                // Points along the line, so the dashes are clipped to the plot like the data.
                let points: Vec<(f64, f64)> = (0..=64)
                    .map(|k| x.0 * (x.1 / x.0).powf(k as f64 / 64.0))
                    .map(|x| (x, at(x)))
                    .filter(|(_, v)| *v >= y.0 && *v <= y.1)
                    .collect();
                let style = GUIDE.stroke_width(1);
                chart
                    .draw_series(DashedLineSeries::new(points, dash, space, style))
                    .map_err(|e| e.to_string())?
                    .label(guide.name)
                    .legend(move |(x, y)| {
                        // Four dashes of the line's pattern.
                        let dash_at = |k: i32| {
                            let at = (k * (dash + space)).min(20);
                            PathElement::new(vec![(at, 0), ((at + dash).min(20), 0)], style)
                        };
                        EmptyElement::at((x, y)) + dash_at(0) + dash_at(1) + dash_at(2) + dash_at(3)
                    });
            }
            for series in &self.series {
                let colour = series.colour;
                chart
                    .draw_series(LineSeries::new(
                        series.points.iter().copied(),
                        colour.stroke_width(2),
                    ))
                    .map_err(|e| e.to_string())?
                    .label(series.name)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                    });
                if series.markers {
                    chart
                        .draw_series(
                            series
                                .points
                                .iter()
                                .map(|&p| Circle::new(p, 4, colour.filled())),
                        )
                        .map_err(|e| e.to_string())?;
                }
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .label_font((FONT, 15))
                .background_style(WHITE.mix(0.9))
                .border_style(BLACK)
                .draw()
                .map_err(|e| e.to_string())
        })
    }
}

/// A tick label: a power of ten as a plain decimal (`0.001`, `1`, `100`), any other value
/// with three significant digits.
fn number(v: f64) -> String {
    let decade = v.log10().round();
    if (v.log10() - decade).abs() < 1e-9 {
        let d = decade as i32;
        if d >= 0 {
            format!("{}", 10f64.powi(d))
        } else {
            format!("{:.*}", (-d) as usize, 10f64.powi(d))
        }
    } else {
        format!("{v:.3}")
    }
}

/// The height of a label strip for labels of `width` pixels.
pub fn label_height(width: u32) -> u32 {
    label_font_size(width) + 8
}

/// The largest font size of a label in a strip of `width` pixels: 15 px, smaller in narrow
/// strips (quick mode's small panels).
fn label_font_size(width: u32) -> u32 {
    (width / 16).clamp(8, 15)
}

/// `text` centred in a white strip `width` pixels wide, [`label_height`] high (clipped at the
/// strip's edges when it is longer).
pub fn label_strip(text: &str, width: u32) -> RgbImage {
    let height = label_height(width);
    drawn(width, height, |root| {
        // Smaller for a long text, so that it fits (a Hack glyph is 0.6 em wide).
        let fit = (width as f64 / (0.6 * text.chars().count().max(1) as f64)) as u32;
        let size = label_font_size(width).min(fit).max(7);
        let style = TextStyle::from((FONT, size).into_font()).color(&BLACK).pos(
            plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Center,
                plotters::style::text_anchor::VPos::Center,
            ),
        );
        root.draw(&Text::new(
            text,
            ((width / 2) as i32, (height / 2) as i32),
            style,
        ))
        .map_err(|e| e.to_string())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// How many pixels of `image` are not white.
    fn inked(image: &RgbImage) -> usize {
        image.chunks(3).filter(|p| p != &[255, 255, 255]).count()
    }

    #[test]
    fn a_label_is_drawn_in_ink_and_a_longer_one_takes_more() {
        let short = label_strip("n = 1", 320);
        let long = label_strip("n = 1 · 0.25 s", 320);
        assert_eq!(short.height(), label_height(320));
        assert!(inked(&short) > 20, "the label was not drawn");
        assert!(inked(&long) > inked(&short));
        assert_eq!(inked(&label_strip("", 320)), 0);
    }

    #[test]
    fn the_plot_draws_its_series_legend_and_guides() {
        const POINTS: [(f64, f64); 3] = [(1.0, 0.5), (10.0, 0.16), (100.0, 0.05)];
        let plot = |series: Vec<Series<'static>>, guides| {
            LogLogPlot {
                x_decades: (0, 2),
                x_label: "samples",
                y_label: "relative error",
                series,
                guides,
            }
            .draw()
        };
        let series = || {
            vec![Series {
                name: "area sampling",
                points: &POINTS,
                colour: BLUE,
                markers: true,
            }]
        };
        let guide = Guide {
            slope: -0.5,
            through: (1.0, 0.5),
            name: "slope -1/2",
        };
        let with = plot(series(), vec![guide]);
        let without_guide = plot(series(), Vec::new());
        let empty = plot(Vec::new(), Vec::new());
        assert_eq!(with.dimensions(), PLOT_SIZE);
        let count = |image: &RgbImage, keep: &dyn Fn(&[u8]) -> bool| {
            image.chunks(3).filter(|p| keep(p)).count()
        };
        let blue = |p: &[u8]| p == [BLUE.0, BLUE.1, BLUE.2];
        // The guide's grey (anti-aliased: any neutral grey darker than the grid).
        let grey = |p: &[u8]| p[0] == p[1] && p[1] == p[2] && (40..190).contains(&p[0]);
        assert!(count(&with, &blue) > 200, "{}", count(&with, &blue));
        assert_eq!(count(&empty, &blue), 0);
        assert!(
            count(&with, &grey) > count(&without_guide, &grey) + 100,
            "{} against {}",
            count(&with, &grey),
            count(&without_guide, &grey)
        );
        // The legend's box and text: more black than the axes and tick labels alone.
        let black = |p: &[u8]| p.iter().all(|c| *c < 60);
        assert!(
            count(&without_guide, &black) > count(&empty, &black) + 150,
            "{} against {}",
            count(&without_guide, &black),
            count(&empty, &black)
        );
    }

    #[test]
    fn tick_labels_are_plain_decimals() {
        assert_eq!(number(0.001), "0.001");
        assert_eq!(number(1.0), "1");
        assert_eq!(number(100.0), "100");
        assert_eq!(number(0.5), "0.500");
    }
}
