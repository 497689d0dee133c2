//! The figures of a lab's report (`raylab report --lab N`): what a lab's figure code draws with
//! (labelled panels, plots, timed renders), and the report around them — PNG files with a
//! `report.md` and a `report.html` beside them that give each figure's parameters and render
//! time. Each lab's figures are its checks' `report` module, run in the lab's program.

pub mod plot;

use std::cell::RefCell;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use course::LabId;
use image::{RgbImage, imageops};
use pipeline::Pipeline;
use pipeline::job::ReportJob;
use pipeline::render::render_partial;
use raylab_core::Error;
use raylab_core::film::{Film, ToneMap, write_srgb8_png};
use raylab_core::glam::Vec3;
use raylab_core::render::{PixelFailures, RenderSettings};
use raylab_core::scene::Scene;

/// A lab's figures: each written to the report's directory, and said what it is.
pub type LabFigures = fn(&ReportContext) -> Result<Vec<Figure>, Error>;

/// What a lab's figure code gets.
pub struct ReportContext {
    /// The lab.
    pub lab: LabId,
    /// The pipeline at this lab, with the student's code in the lab's slots when asked for.
    pub pipeline: Pipeline,
    /// Where the figures go.
    pub dir: PathBuf,
    /// Quick mode: small images, few samples.
    pub quick: bool,
    /// Whose code renders, in words ("Reference", "Student").
    pub whose: String,
    /// The failed pixels of every render so far, and how many pixels were rendered.
    pub failures: RefCell<(PixelFailures, usize)>,
    /// The student's written answers, shown after the figures.
    pub answers: Option<String>,
}

/// One figure of a report.
pub struct Figure {
    /// File name of the PNG in the report directory.
    pub file: String,
    /// What it shows.
    pub caption: String,
    /// The parameters it was made with.
    pub parameters: String,
    /// Render time in seconds (all panels together for a montage), if it is a render.
    pub seconds: Option<f64>,
}

impl ReportContext {
    /// Renders and times a scene, marked as `raylab render` marks it: magenta where the
    /// computation panicked (an unfinished exercise), cyan where the radiance is NaN or
    /// infinite. The failures are counted in [`ReportContext::failures`].
    pub fn render_timed(
        &self,
        scene: &Scene,
        pipeline: &Pipeline,
        settings: &RenderSettings,
    ) -> Result<(Film, f64), Error> {
        let start = Instant::now();
        let rendered = render_partial(scene, pipeline, settings)?;
        let seconds = start.elapsed().as_secs_f64();
        let mut failures = self.failures.borrow_mut();
        failures.0.merge(&rendered.failures);
        failures.1 += rendered.film.pixels.len();
        Ok((rendered.marked(), seconds))
    }

    /// Writes rows of labelled panels as a PNG figure (see [`labelled`]).
    pub fn save_panels(
        &self,
        rows: &[Vec<Panel>],
        file: &str,
        tonemap: ToneMap,
    ) -> Result<PathBuf, Error> {
        let path = self.dir.join(file);
        write_rgb8(&labelled(rows, tonemap), &path)?;
        Ok(path)
    }

    /// Writes one render as a PNG figure with `label` under it.
    pub fn save_labelled(
        &self,
        film: Film,
        label: impl Into<String>,
        file: &str,
        tonemap: ToneMap,
    ) -> Result<PathBuf, Error> {
        self.save_panels(&[vec![Panel::new(film, label)]], file, tonemap)
    }

    /// Writes a plot as a PNG figure.
    pub fn save_plot(&self, plot: &plot::LogLogPlot, file: &str) -> Result<PathBuf, Error> {
        let path = self.dir.join(file);
        write_rgb8(&plot.draw(), &path)?;
        Ok(path)
    }

    /// A size scaled down in quick mode.
    pub fn size(&self, width: u32, height: u32) -> (u32, u32) {
        if self.quick {
            (width / 4, height / 4)
        } else {
            (width, height)
        }
    }
}

/// The white gap between the panels of a figure, pixels.
const GAP: u32 = 4;

/// One render of a figure and the label printed under it inside the image: what varies
/// between the panels and the render time.
pub struct Panel {
    /// The render.
    pub film: Film,
    /// The label (for example "n = 9, 0.840 s").
    pub label: String,
}

impl Panel {
    /// A panel labelled `label`.
    pub fn new(film: Film, label: impl Into<String>) -> Self {
        Self {
            film,
            label: label.into(),
        }
    }
}

/// The label of a render made in `seconds`: "`what`, 0.123 s" (just the time when `what` is
/// empty).
pub fn timed(what: &str, seconds: f64) -> String {
    if what.is_empty() {
        format!("{seconds:.3} s")
    } else {
        format!("{what}, {seconds:.3} s")
    }
}

/// The height of a row of panels: its tallest.
fn row_height(row: &[Panel]) -> u32 {
    row.iter().map(|p| p.film.height).max().unwrap_or(0)
}

/// The rows of panels as one film: the panels of a row side by side, the rows one above the
/// other, [`GAP`] white pixels between them; and each panel's place `(x, width)` in its row.
fn grid(rows: &[Vec<Panel>]) -> (Film, Vec<(u32, u32)>) {
    let row_width = |row: &[Panel]| {
        row.iter().map(|p| p.film.width).sum::<u32>() + GAP * row.len().saturating_sub(1) as u32
    };
    let width = rows.iter().map(|r| row_width(r)).max().unwrap_or(0);
    let height =
        rows.iter().map(|r| row_height(r)).sum::<u32>() + GAP * rows.len().saturating_sub(1) as u32;
    let mut film = Film::new(width, height);
    film.pixels.fill(Vec3::ONE);
    let mut places = Vec::new();
    let mut y0 = 0;
    for row in rows {
        let mut x0 = 0;
        for panel in row {
            let p = &panel.film;
            for y in 0..p.height {
                for x in 0..p.width {
                    film.set(x0 + x, y0 + y, p.get(x, y));
                }
            }
            places.push((x0, p.width));
            x0 += p.width + GAP;
        }
        y0 += row_height(row) + GAP;
    }
    (film, places)
}

/// The rows of panels tone-mapped together (as one image, so the tone map sees them all) to
/// 8-bit sRGB, with each panel's label in a strip under its row.
pub fn labelled(rows: &[Vec<Panel>], tonemap: ToneMap) -> RgbImage {
    let (film, places) = grid(rows);
    let toned = RgbImage::from_raw(film.width, film.height, film.to_srgb8(tonemap))
        .expect("three bytes a pixel");
    let strip = places
        .iter()
        .map(|&(_, w)| plot::label_height(w))
        .max()
        .unwrap_or(0);
    let height = film.height + strip * rows.len() as u32;
    let mut out = RgbImage::from_pixel(film.width, height, image::Rgb([255; 3]));
    let mut places = places.into_iter();
    let mut y_in = 0;
    for (k, row) in rows.iter().enumerate() {
        let h = row_height(row);
        let y_out = y_in + strip * k as u32;
        let band = imageops::crop_imm(&toned, 0, y_in, film.width, h);
        imageops::replace(&mut out, &*band, 0, i64::from(y_out));
        for (panel, (x0, w)) in row.iter().zip(&mut places) {
            let label = plot::label_strip(&panel.label, w);
            imageops::replace(&mut out, &label, i64::from(x0), i64::from(y_out + h));
        }
        y_in += h + GAP;
    }
    out
}

/// Writes 8-bit sRGB pixels as a PNG file.
fn write_rgb8(image: &RgbImage, path: &std::path::Path) -> Result<(), Error> {
    write_srgb8_png(image.as_raw(), image.width(), image.height(), path)
}

/// Makes lab `lab`'s report with `figures` through `pipeline` (with the code of `job.whose` in
/// the lab's slots): the figures, `report.md` and `report.html` in `job.dir`; says on standard
/// error which pixels panicked, and prints each file's path on standard output.
pub fn make(
    job: &ReportJob,
    lab: LabId,
    pipeline: Pipeline,
    figures: LabFigures,
) -> Result<(), Error> {
    std::fs::create_dir_all(&job.dir).map_err(|e| Error::io(&job.dir, e))?;
    let answers = job.answers.as_deref().map(read_answers).transpose()?;
    let ctx = ReportContext {
        lab,
        pipeline,
        dir: job.dir.clone(),
        quick: job.quick,
        whose: job.whose.clone(),
        failures: RefCell::default(),
        answers,
    };
    let figures = figures(&ctx)?;
    let (failures, total) = &*ctx.failures.borrow();
    let unfinished = pipeline::job::failure_lines(failures, *total);
    for line in &unfinished {
        eprintln!("{line}");
    }
    let index = write_index(&ctx, &figures, &unfinished)?;
    let page = write_page(&ctx, &figures, &unfinished)?;
    for f in &figures {
        println!("{}", ctx.dir.join(&f.file).display());
    }
    println!("{}", index.display());
    println!("{}", page.display());
    Ok(())
}

/// The written answers file at `path`, refused past [`course::answers::FILE_LIMIT`].
fn read_answers(path: &std::path::Path) -> Result<String, Error> {
    let size = std::fs::metadata(path)
        .map_err(|e| Error::io(path, e))?
        .len();
    if size > course::answers::FILE_LIMIT {
        return Err(Error::Failed {
            what: path.display().to_string(),
            reason: format!(
                "it is {size} bytes; a written answers file is at most {} bytes (put images beside it and link them)",
                course::answers::FILE_LIMIT
            ),
        });
    }
    std::fs::read_to_string(path).map_err(|e| Error::io(path, e))
}

/// "Written answers (`labs/lab01/answers.md`, 3 of 8 answered)".
fn answers_heading(lab: LabId, answers: &str) -> String {
    let parsed = course::answers::parse(answers);
    format!(
        "Written answers (`{}`, {} of {} answered)",
        lab.answers(),
        course::answers::answered(&parsed),
        parsed.len()
    )
}

/// Writes `report.md` beside the figures: each figure with its caption, parameters and time.
fn write_index(
    ctx: &ReportContext,
    figures: &[Figure],
    unfinished: &[String],
) -> Result<PathBuf, Error> {
    let mut md = String::new();
    let _ = writeln!(md, "# Lab {:02} report figures\n", ctx.lab.number());
    let _ = writeln!(md, "{}\n", made_with(ctx));
    if !unfinished.is_empty() {
        let _ = writeln!(
            md,
            "**Unfinished.** Magenta pixels are pixels whose computation panicked, over all the figures:\n"
        );
        for line in unfinished.iter().skip(1) {
            let _ = writeln!(md, "- {}", line.trim());
        }
        md.push('\n');
    }
    for f in figures {
        let time = f
            .seconds
            .map_or_else(String::new, |s| format!(" — render time {s:.3} s"));
        let _ = writeln!(
            md,
            "## {}\n\n![{}]({})\n\n{}{time}\n",
            f.caption, f.caption, f.file, f.parameters
        );
    }
    if let Some(answers) = &ctx.answers {
        let _ = writeln!(
            md,
            "---\n\n## {}\n\n{answers}",
            answers_heading(ctx.lab, answers)
        );
    }
    let path = ctx.dir.join("report.md");
    std::fs::write(&path, md).map_err(|e| Error::io(&path, e))?;
    Ok(path)
}

/// How the report's figures were made, in words: the pipeline, and quick mode if it was.
fn made_with(ctx: &ReportContext) -> String {
    format!(
        "Rendered with the {} pipeline{}.",
        ctx.whose,
        if ctx.quick {
            " in quick mode (small images, few samples)"
        } else {
            ""
        }
    )
}

/// Writes `report.html` beside the figures: the same as `report.md`, each figure shown with
/// its caption, parameters and time, for a browser.
fn write_page(
    ctx: &ReportContext,
    figures: &[Figure],
    unfinished: &[String],
) -> Result<PathBuf, Error> {
    use maud::{DOCTYPE, html};
    let title = format!("Lab {:02} report figures", ctx.lab.number());
    let page = html! {
        (DOCTYPE)
        html lang="en" {
            head {
                meta charset="utf-8";
                title { (title) }
                style { "body{font-family:sans-serif;max-width:72rem;margin:2rem auto;padding:0 1rem}\
                         figure{margin:2rem 0}img{max-width:100%;image-rendering:pixelated}\
                         figcaption{color:#333}.unfinished{background:#fde;padding:.5rem 1rem}\
                         pre.answers{white-space:pre-wrap;background:#f6f6f6;padding:1rem}" }
            }
            body {
                h1 { (title) }
                p { (made_with(ctx)) }
                @if !unfinished.is_empty() {
                    div class="unfinished" {
                        p { strong { "Unfinished." } " Magenta pixels are pixels whose computation panicked, over all the figures:" }
                        ul { @for line in unfinished.iter().skip(1) { li { (line.trim()) } } }
                    }
                }
                @for f in figures {
                    figure id=(f.file.trim_end_matches(".png")) {
                        h2 { (f.caption) }
                        img src=(f.file) alt=(f.caption);
                        figcaption {
                            (f.parameters)
                            @if let Some(s) = f.seconds { " — render time " (format!("{s:.3}")) " s" }
                        }
                    }
                }
                @if let Some(answers) = &ctx.answers {
                    section id="answers" {
                        h2 { (answers_heading(ctx.lab, answers)) }
                        pre class="answers" { (answers) }
                    }
                }
            }
        }
    };
    let path = ctx.dir.join("report.html");
    std::fs::write(&path, page.into_string()).map_err(|e| Error::io(&path, e))?;
    Ok(path)
}

/// The cut-out `crop` of `film` — `[x, y, width, height]` as fractions of the image — magnified
/// `zoom` times (nearest neighbour): a close-up beside the whole render.
pub fn crop_zoom(film: &Film, crop: [f32; 4], zoom: u32) -> Film {
    let (w, h) = (film.width as f32, film.height as f32);
    let (x0, y0) = ((crop[0] * w) as u32, (crop[1] * h) as u32);
    let (cw, ch) = ((crop[2] * w) as u32, (crop[3] * h) as u32);
    let mut out = Film::new(cw * zoom, ch * zoom);
    for y in 0..out.height {
        for x in 0..out.width {
            out.set(x, y, film.get(x0 + x / zoom, y0 + y / zoom));
        }
    }
    out
}

/// Render settings for a report figure.
pub fn settings(width: u32, height: u32, spp: u32) -> RenderSettings {
    RenderSettings {
        width,
        height,
        samples_per_pixel: spp,
        pixel_subdivisions: 1,
        seed: 0,
        progress: false,
    }
}
