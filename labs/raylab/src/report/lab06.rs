//! Lab 06's figures: the Cornell box solved by progressive refinement with the hemicube, flat
//! and smoothed by nodal averaging; without occlusion (the analytic form factor); the unshot
//! power against the shots; and the worksheet's questions — the light source's subdivision,
//! the hemicube's resolution, and radiosity against ray tracing.

use std::time::Instant;

use framework::Error;
use framework::contracts::lab06::Radiosity;
use framework::film::{Film, ToneMap};
use framework::glam::Vec3;
use framework::radiosity::solver::{
    FormFactors, Shading, Solution, SolveSettings, render_solution, solve,
};
use framework::radiosity::{MeshingOptions, PatchMesh};
use framework::scene::{Scene, builtin_scene};

use super::{Figure, ReportContext, montage, settings};

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
    framework::catch_quietly(
        "lab 06's report (a radiosity solution calls every exercise of the lab)",
        || solved_figures(ctx),
    )?
}

fn solved_figures(ctx: &ReportContext) -> Result<Vec<Figure>, Error> {
    let r = ctx.pipeline.radiosity.clone();
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
        ctx.save(&draw(&main, smooth), file, tone)?;
        figures.push(Figure {
            file: file.into(),
            caption: caption.into(),
            parameters: format!("{w}×{h} pixels; {params}"),
            seconds: Some(main.seconds),
        });
    }

    // Unshot power against shots.
    let plot = plot_log(&main.solution.unshot_fraction, ctx.size(640, 320));
    ctx.save(&plot, "unshot-power.png", ToneMap::Clamp { exposure: 1.0 })?;
    figures.push(Figure {
        file: "unshot-power.png".into(),
        caption: "Unshot power over emitted power against the number of shots (log scale, 10⁰ at the top to 10⁻³ at the bottom; grid lines at each decade)".into(),
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
    ctx.save(&draw(&a, true), "cornell-analytic.png", tone)?;
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
        panels.push(draw(&s, true));
    }
    ctx.save(&montage(&panels, 4), "light-subdivision.png", tone)?;
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
        panels.push(draw(&s, false));
    }
    ctx.save(&montage(&panels, 4), "hemicube-resolution.png", tone)?;
    figures.push(Figure {
        file: "hemicube-resolution.png".into(),
        caption: "Hemicubes of 4, 8, 16 and 64 pixels across (flat patches): aliasing of the item buffer at low resolution".into(),
        parameters: lines.join("; "),
        seconds: Some(seconds),
    });

    // Radiosity against ray tracing: the same box by lab 3's area-light ray tracer.
    let spp = if ctx.quick { 1 } else { 4 };
    let traced_pipeline = framework::pipeline::Pipeline {
        lab: 4,
        area_light_samples: 4,
        ..ctx.pipeline.clone()
    };
    let (traced, t) = ctx.render_timed(&scene, &traced_pipeline, &settings(w, h, spp))?;
    ctx.save(
        &montage(&[draw(&main, true), traced], 4),
        "radiosity-vs-ray-tracing.png",
        tone,
    )?;
    figures.push(Figure {
        file: "radiosity-vs-ray-tracing.png".into(),
        caption: "Radiosity (left: every diffuse interreflection, colour bleeding) against the ray tracer of labs 3–4 (right: direct light only, from the scene's point light and its area light: a black ceiling, no colour bleeding, hard shadows from the point light)".into(),
        parameters: format!("{w}×{h} pixels; right: {spp} sample(s) per pixel, 4×4 area-light samples"),
        seconds: Some(t),
    });
    Ok(figures)
}

/// A plot of `values` (fractions in `(0, 1]`) on a log scale from 10⁰ down to 10⁻³.
fn plot_log(values: &[f64], (w, h): (u32, u32)) -> Film {
    let mut film = Film::new(w, h);
    film.pixels.fill(Vec3::ONE);
    let decades = 3.0;
    let y_of = |v: f64| {
        let t = (-v.max(1e-12).log10() / decades).clamp(0.0, 1.0);
        ((h - 1) as f64 * t) as u32
    };
    for d in 0..=3 {
        let y = y_of(10f64.powi(-d));
        for x in 0..w {
            film.set(x, y, Vec3::splat(0.8));
        }
    }
    let n = values.len().max(2) - 1;
    let mut last: Option<(u32, u32)> = None;
    for x in 0..w {
        let k = (x as usize * n) / (w as usize - 1).max(1);
        let y = y_of(values[k.min(values.len() - 1)]);
        let (y0, y1) = match last {
            Some((_, py)) => (py.min(y), py.max(y)),
            None => (y, y),
        };
        for yy in y0..=y1 {
            film.set(x, yy, Vec3::new(0.8, 0.1, 0.1));
        }
        last = Some((x, y));
    }
    film
}
