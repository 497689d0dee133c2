//! Lab 05's figures: the convergence of the two Monte Carlo estimators of the irradiance from
//! an area light (Exercises 5.8 and 5.9) — the RMS relative error against the number of
//! samples on log–log axes, for a small light (where area sampling wins) and a large light
//! close above (where cosine sampling wins), with the numbers as a table.

use std::fmt::Write as _;
use std::time::Instant;

use crate::checks::{BIG_LIGHT, Estimator, LightCase, estimates, light_cases};
use contracts::lab05::Radiometry;
use raylab_core::Error;

use figures::plot::{BLUE, Guide, LogLogPlot, ORANGE, Series};
use figures::{Figure, ReportContext};

/// The sample counts of the plot: 1 to 4096.
const SAMPLE_COUNTS: [u32; 7] = [1, 4, 16, 64, 256, 1024, 4096];
/// Independent estimates per sample count, whose RMS error is plotted.
const ESTIMATES: u32 = 200;

/// The figures of lab 05.
pub fn figures(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    let cases = light_cases();
    Ok(vec![
        convergence(ctx, &cases[0], "convergence-small-light.png")?,
        convergence(ctx, &cases[BIG_LIGHT], "convergence-large-light.png")?,
    ])
}

/// `(samples, RMS relative error)` at each sample count and the seconds they took, or the
/// message of the panic that stopped them.
type Convergence = Result<(Vec<(f64, f64)>, f64), String>;

/// RMS relative error of [`ESTIMATES`] estimates at each sample count, and the time they took;
/// or the panic of an unfinished exercise.
fn errors(
    code: &dyn Radiometry,
    estimator: Estimator,
    case: &LightCase,
    exact: f64,
    quick: bool,
) -> Convergence {
    let counts = if quick {
        &SAMPLE_COUNTS[..4]
    } else {
        &SAMPLE_COUNTS[..]
    };
    let start = Instant::now();
    let points = raylab_core::catch_quietly("the report of lab 05", || {
        counts
            .iter()
            .map(|&n| {
                let x = estimates(code, estimator, case, n, ESTIMATES, 7 + n as u64);
                let mse = x.iter().map(|e| (e / exact - 1.0).powi(2)).sum::<f64>() / x.len() as f64;
                (n as f64, mse.sqrt())
            })
            .collect::<Vec<_>>()
    })
    .map_err(|p| p.message)?;
    Ok((points, start.elapsed().as_secs_f64()))
}

fn convergence(ctx: &ReportContext, case: &LightCase, file: &str) -> Result<Figure, Error> {
    let code = ctx.pipeline.code::<dyn contracts::lab05::Radiometry>();
    let code = code.as_ref();
    let exact = case.exact();
    let area = errors(code, Estimator::Area, case, exact, ctx.quick);
    let cosine = errors(code, Estimator::Cosine, case, exact, ctx.quick);
    let mut series = Vec::new();
    let mut notes = String::new();
    let mut seconds = 0.0;
    for (result, colour, name, legend) in [
        (
            &area,
            BLUE,
            "blue: uniform area sampling (5.8)",
            "area sampling (5.8)",
        ),
        (
            &cosine,
            ORANGE,
            "orange: cosine-weighted sampling (5.9)",
            "cosine sampling (5.9)",
        ),
    ] {
        match result {
            Ok((points, t)) => {
                series.push(Series {
                    name: legend,
                    points,
                    colour,
                    markers: true,
                });
                seconds += t;
                let _ = write!(notes, "{name}; ");
            }
            Err(message) => {
                let _ = write!(notes, "{name} is not plotted ({message}); ");
            }
        }
    }
    let guide = series.first().map(|s| s.points[0]);
    let plot = LogLogPlot {
        x_decades: (0, if ctx.quick { 2 } else { 4 }),
        x_label: "samples",
        y_label: "relative error",
        series,
        guides: guide
            .map(|through| Guide {
                slope: -0.5,
                through,
                name: "slope -1/2 (1/sqrt N)",
            })
            .into_iter()
            .collect(),
    };
    ctx.save_plot(&plot, file)?;

    let mut table = String::from(
        "| samples N | RMS relative error, area sampling | RMS relative error, cosine sampling |\n| --- | --- | --- |\n",
    );
    let column = |r: &Convergence, k: usize| match r {
        Ok((p, _)) => format!("{:.3e}", p[k].1),
        Err(_) => "unfinished".into(),
    };
    let rows = if ctx.quick { 4 } else { SAMPLE_COUNTS.len() };
    for (k, n) in SAMPLE_COUNTS.iter().take(rows).enumerate() {
        let _ = writeln!(
            table,
            "| {n} | {} | {} |",
            column(&area, k),
            column(&cosine, k)
        );
    }
    let l = &case.light;
    Ok(Figure {
        file: file.into(),
        caption: format!("Convergence of the irradiance estimators: {}", case.what),
        parameters: format!(
            "{}: corner {}, edges {} and {}, radiance {} W/(m² sr); receiver at {} with normal {}; exact irradiance E = {exact:.6} W/m² (Lambert's polygon formula, docs/lab05.md). Each point is the root mean square of (estimate/E − 1) over {ESTIMATES} independent estimates (generator `Rng::new(7 + N, k)` for estimate k) with N samples each. {notes}dashed: slope −1/2 (error ∝ 1/√N) through the first point.\n\n{table}\nTime: both estimators at every N together",
            case.what,
            l.corner,
            l.edge_u,
            l.edge_v,
            l.radiance_w_per_m2_sr,
            case.receiver.position,
            case.receiver.normal,
        ),
        seconds: Some(seconds),
    })
}

/// Makes the lab's report: its figures through `pipeline` (`raylab report`).
pub fn make(
    job: &pipeline::job::ReportJob,
    pipeline: pipeline::Pipeline,
) -> Result<(), raylab_core::Error> {
    figures::make(job, crate::checks::LAB, pipeline, figures)
}
