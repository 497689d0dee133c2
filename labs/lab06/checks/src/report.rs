//! Lab 06's figures: the Cornell box solved by progressive refinement with the hemicube, flat
//! and smoothed by nodal averaging; without occlusion (the analytic form factor); the unshot
//! power against the shots; and the worksheet's questions — the light source's subdivision,
//! the hemicube's resolution, and radiosity against ray tracing.

use std::time::Instant;

use contracts::lab06::Radiosity;
use pipeline::radiosity::solver::{
    FormFactors, Shading, Solution, SolveSettings, render_solution, solve,
};
use pipeline::radiosity::{MeshingOptions, PatchMesh};
use raylab_core::Error;
use raylab_core::film::ToneMap;
use raylab_core::glam::Vec3;
use raylab_core::scene::{Scene, builtin_scene};

use figures::plot::{LogLogPlot, RED, Series};
use figures::{Figure, Panel, ReportContext, settings, timed};

/// Meshing of the report's Cornell box: 5 cm patches, 2.5 cm on the light.
pub const MESHING: MeshingOptions = MeshingOptions {
    max_size: 0.05,
    max_light_size: 0.025,
};

/// The report's solver: a 64 × 64 hemicube down to 1 % unshot power.
pub const SOLVE: SolveSettings = SolveSettings {
    form_factors: FormFactors::Hemicube(64),
    threshold: 0.01,
    max_shots: 100_000,
};

/// A solved mesh, its patch and vertex colours, and how long the solve took.
struct Solved {
    mesh: PatchMesh,
    solution: Solution,
    flat: Vec<Vec3>,
    smooth: Vec<Vec3>,
    seconds: f64,
}

fn solved(
    r: &dyn Radiosity,
    scene: &Scene,
    meshing: MeshingOptions,
    solve_settings: &SolveSettings,
) -> Solved {
    let start = Instant::now();
    let mesh = PatchMesh::from_scene(scene, meshing);
    let solution = solve(r, &mesh, solve_settings);
    let flat = r.patch_colours(&solution.radiosity);
    let smooth = r.vertex_colours(&mesh.patches, mesh.vertices.len(), &flat);
    Solved {
        seconds: start.elapsed().as_secs_f64(),
        mesh,
        solution,
        flat,
        smooth,
    }
}

fn describe(s: &Solved, settings: &SolveSettings) -> String {
    let method = match settings.form_factors {
        FormFactors::Analytic => "analytic point-to-patch form factors (no occlusion)".to_string(),
        FormFactors::Hemicube(n) => format!("a {n}×{n} hemicube"),
    };
    format!(
        "{} patches, {method}, {} shots to {:.2} % unshot power (form factors {:.2} s, shooting {:.3} s)",
        s.mesh.patches.len(),
        s.solution.shots(),
        100.0 * s.solution.unshot_fraction.last().copied().unwrap_or(0.0),
        s.solution.form_factor_time.as_secs_f64(),
        s.solution.shoot_time.as_secs_f64()
    )
}

/// The figures of lab 06. A radiosity solution needs every exercise, so an unfinished one
/// stops the report with its name (the ray-traced figures of other labs lose pixels instead).
pub fn figures(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    raylab_core::catch_quietly(
        "lab 06's report (a radiosity solution calls every exercise of the lab)",
        || solved_figures(ctx),
    )?
}

fn solved_figures(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    let r = ctx.pipeline.code::<dyn contracts::lab06::Radiosity>();
    let r = r.as_ref();
    let scene = builtin_scene("cornell")?;
    let (w, h) = ctx.size(512, 512);
    let meshing = if ctx.quick {
        MeshingOptions {
            max_size: 0.1,
            max_light_size: 0.05,
        }
    } else {
        MeshingOptions { ..MESHING }
    };
    let tone = ToneMap::default();
    let draw = |s: &Solved, smooth: bool| {
        let shading = if smooth {
            Shading::Smooth(&s.smooth)
        } else {
            Shading::Flat(&s.flat)
        };
        render_solution(&ctx.pipeline, &scene, &s.mesh, shading, w, h)
    };
    let mut figures = Vec::new();

    // The solution, flat and smooth.
    let main = solved(r, &scene, meshing, &SOLVE);
    let params = describe(&main, &SOLVE);
    for (file, smooth, caption) in [
        (
            "cornell-flat.png",
            false,
            "The Cornell box by progressive refinement with the hemicube, flat patches",
        ),
        (
            "cornell-smooth.png",
            true,
            "The same solution smoothed by nodal averaging (Gouraud-interpolated vertex colours)",
        ),
    ] {
        let what = if smooth { "smoothed" } else { "flat" };
        ctx.save_labelled(draw(&main, smooth), timed(what, main.seconds), file, tone)?;
        figures.push(Figure {
            file: file.into(),
            caption: caption.into(),
            parameters: format!("{w}×{h} pixels; {params}"),
            seconds: Some(main.seconds),
        });
    }

    // Unshot power against shots.
    let points = unshot_points(&main.solution.unshot_fraction);
    let shots = points.last().map_or(1.0, |p| p.0);
    let plot = LogLogPlot {
        x_decades: (0, shots.log10().ceil().max(1.0) as i32),
        x_label: "shots",
        y_label: "unshot power / emitted power",
        series: vec![Series {
            name: "progressive refinement (6.5, 6.6)",
            points: &points,
            colour: RED,
            markers: false,
        }],
        guides: Vec::new(),
    };
    ctx.save_plot(&plot, "unshot-power.png")?;
    figures.push(Figure {
        file: "unshot-power.png".into(),
        caption: "Unshot power over emitted power against the number of shots (log–log)".into(),
        parameters: params.clone(),
        seconds: None,
    });

    // Without occlusion: the analytic form factor of Exercise 6.1.
    let analytic = SolveSettings {
        form_factors: FormFactors::Analytic,
        ..SOLVE
    };
    let coarse = MeshingOptions {
        max_size: meshing.max_size.max(0.05),
        max_light_size: meshing.max_light_size.max(0.05),
    };
    let a = solved(r, &scene, coarse, &analytic);
    ctx.save_labelled(
        draw(&a, true),
        timed("analytic form factors", a.seconds),
        "cornell-analytic.png",
        tone,
    )?;
    figures.push(Figure {
        file: "cornell-analytic.png".into(),
        caption: "Analytic point-to-patch form factors: no occlusion, so no shadows under the blocks, and light leaks through them".into(),
        parameters: format!("{w}×{h} pixels; {}", describe(&a, &analytic)),
        seconds: Some(a.seconds),
    });

    // The light source's subdivision.
    let mut panels = Vec::new();
    let mut lines = Vec::new();
    let mut seconds = 0.0;
    for light in [1.0, 0.1, 0.025] {
        let m = MeshingOptions {
            max_size: meshing.max_size.max(0.05),
            max_light_size: light,
        };
        let s = solved(r, &scene, m, &SOLVE);
        seconds += s.seconds;
        lines.push(format!(
            "light patches ≤ {light} m: {}",
            describe(&s, &SOLVE)
        ));
        panels.push(Panel::new(
            draw(&s, true),
            timed(&format!("light ≤ {light} m"), s.seconds),
        ));
    }
    ctx.save_panels(&[panels], "light-subdivision.png", tone)?;
    figures.push(Figure {
        file: "light-subdivision.png".into(),
        caption:
            "The light source as 1 patch, as patches of 10 cm and of 2.5 cm (walls 5 cm, smoothed)"
                .into(),
        parameters: lines.join("; "),
        seconds: Some(seconds),
    });

    // The hemicube's resolution.
    let (mut panels, mut lines, mut seconds) = (Vec::new(), Vec::new(), 0.0);
    for n in [4, 8, 16, 64] {
        let settings = SolveSettings {
            form_factors: FormFactors::Hemicube(n),
            ..SOLVE
        };
        let s = solved(r, &scene, meshing, &settings);
        seconds += s.seconds;
        lines.push(describe(&s, &settings));
        panels.push(Panel::new(
            draw(&s, false),
            timed(&format!("{n}×{n} hemicube"), s.seconds),
        ));
    }
    ctx.save_panels(&[panels], "hemicube-resolution.png", tone)?;
    figures.push(Figure {
        file: "hemicube-resolution.png".into(),
        caption: "Hemicubes of 4, 8, 16 and 64 pixels across (flat patches): aliasing of the item buffer at low resolution".into(),
        parameters: lines.join("; "),
        seconds: Some(seconds),
    });

    // Radiosity against ray tracing: the same box by lab 3's area-light ray tracer, lit as the
    // radiosity solution is, by the ceiling light alone (`cornell-ceiling`: `cornell` without
    // the point light that the patches know nothing of).
    let spp = if ctx.quick { 1 } else { 4 };
    let traced_pipeline = {
        let mut pipeline = ctx.pipeline.clone();
        pipeline.area_light_samples = 4;
        pipeline
    };
    let ceiling_only = builtin_scene("cornell-ceiling")?;
    let (traced, t) = ctx.render_timed(&ceiling_only, &traced_pipeline, &settings(w, h, spp))?;
    let panels = vec![
        Panel::new(draw(&main, true), timed("radiosity", main.seconds)),
        Panel::new(traced, timed("ray tracing", t)),
    ];
    ctx.save_panels(&[panels], "radiosity-vs-ray-tracing.png", tone)?;
    figures.push(Figure {
        file: "radiosity-vs-ray-tracing.png".into(),
        caption: "Radiosity (left: every diffuse interreflection, colour bleeding) against the ray tracer of labs 3–4 (right: direct light only), both lit by the ceiling light alone: the ray tracer's ceiling and the blocks' shadowed sides are black, and it has no colour bleeding; the soft shadows are the area light's in both".into(),
        parameters: format!("{w}×{h} pixels; both the Cornell box lit by its ceiling light alone (the ray tracer's scene `cornell-ceiling`, without the point light of `cornell`); right: {spp} sample(s) per pixel, 4×4 area-light samples"),
        seconds: Some(t),
    });
    Ok(figures)
}

/// The unshot power after each shot, as `(shots, fraction)` points for a log–log plot: every
/// shot from the first, thinned to at most 500 points.
fn unshot_points(values: &[f64]) -> Vec<(f64, f64)> {
    let step = (values.len() / 500).max(1);
    values
        .iter()
        .enumerate()
        .skip(1)
        .filter(|(k, _)| k % step == 0 || *k == values.len() - 1)
        .filter(|(_, v)| **v > 0.0)
        .map(|(k, &v)| (k as f64, v))
        .collect()
}

/// Makes the lab's report: its figures through `pipeline` (`raylab report`).
pub fn make(
    job: &pipeline::job::ReportJob,
    pipeline: pipeline::Pipeline,
) -> Result<(), raylab_core::Error> {
    figures::make(job, crate::checks::LAB, pipeline, figures)
}
