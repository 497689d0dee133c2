//! `raylab bench`: throughput of the framework's ray-tracing core (BVH plus built-in
//! intersection kernels) in rays per second, for closest-hit and any-hit queries, on camera
//! rays and on one diffuse bounce per hit, on 1 and 2 threads; the BVH build time; and the same
//! figures for peers on the very same rays — obvhs (pure Rust) with the `obvhs` feature, Embree 3
//! with the `embree` feature, both in its default mode and in its robust one (which, like the core,
//! lets no ray slip through shared edges) — with a check that every engine finds the same hits.
//! docs/performance.md explains the measurement and records the figures.

mod agreement;
mod engine;
#[cfg(feature = "embree")]
mod peer_embree;
#[cfg(feature = "obvhs")]
mod peer_obvhs;
mod scenes;

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use raylab_core::Error;
use raylab_core::glam::Vec3;
use raylab_core::math::{Aabb, Ray};
use raylab_core::scene::{Mesh, Scene, builtin_scene, load_obj};
use rayon::prelude::*;

use agreement::compare;
use engine::{Core, Engine, SceneQuery, Work, check_triangles_only};
#[cfg(feature = "obvhs")]
use peer_obvhs::{Kernel, Obvhs};
use scenes::{bumpy_sphere, camera_rays, diffuse_rays, mesh_scene, triangles};

/// Options of `raylab bench`.
#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Rays per query set: camera rays through an N×N grid of pixel centres.
    #[arg(long, default_value_t = 512, value_parser = crate::arguments::pixels, allow_negative_numbers = true)]
    pub resolution: u32,
    /// Timed repetitions per measurement; the median is reported.
    #[arg(long, default_value_t = 5)]
    pub runs: usize,
    /// An OBJ mesh to measure besides the Cornell box, such as the Stanford bunny that
    /// `labs/raylab/scripts/fetch-bunny.sh` fetches (default: a generated sphere of 70 300
    /// triangles with bumps, about the size of the bunny).
    #[arg(long)]
    pub mesh: Option<PathBuf>,
    /// Place the mesh this many times side by side, on a grid with a gap of a fifth of its
    /// size (8: a 2×2×2 block), for a scene that many times larger made of the same real mesh.
    #[arg(long, default_value_t = 1)]
    pub copies: u32,
}

/// One engine under test, with its median BVH build time (none where the scene builds it).
struct Entry<'a> {
    name: &'static str,
    engine: Box<dyn Engine + 'a>,
    build_seconds: Option<f64>,
}

/// Seconds `f` takes.
fn time(f: &mut impl FnMut()) -> f64 {
    let start = Instant::now();
    f();
    start.elapsed().as_secs_f64()
}

/// The median of `values` (the mean of the middle two for an even count; 0 for none), which
/// it sorts.
pub fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

/// Builds every engine over the scene's triangles, timing each build (median of `runs`).
fn engines<'a>(scene: &'a Scene, tris: &[[Vec3; 3]], runs: usize) -> Result<Vec<Entry<'a>>, Error> {
    let mut entries = Vec::new();
    let mut timed = |name, build: &mut dyn FnMut() -> Result<Box<dyn Engine + 'a>, Error>| {
        let mut times = Vec::new();
        let mut engine = None;
        for _ in 0..runs {
            let start = Instant::now();
            let built = build()?;
            times.push(start.elapsed().as_secs_f64());
            engine = Some(built);
        }
        entries.push(Entry {
            name,
            engine: engine.expect("at least one run"),
            build_seconds: Some(median(&mut times)),
        });
        Ok::<_, Error>(())
    };
    timed("raylab core", &mut || Ok(Box::new(Core::build(tris))))?;
    #[cfg(feature = "embree")]
    timed("Embree 3", &mut || {
        Ok(Box::new(peer_embree::Embree::build(tris, false)?))
    })?;
    #[cfg(feature = "embree")]
    timed("Embree 3, robust", &mut || {
        Ok(Box::new(peer_embree::Embree::build(tris, true)?))
    })?;
    #[cfg(feature = "obvhs")]
    timed("obvhs", &mut || {
        Ok(Box::new(Obvhs::build(tris, Kernel::Obvhs)))
    })?;
    #[cfg(feature = "obvhs")]
    timed("obvhs + raylab kernel", &mut || {
        Ok(Box::new(Obvhs::build(tris, Kernel::Framework)))
    })?;
    entries.push(Entry {
        name: "Scene::trace_to_*",
        engine: Box::new(SceneQuery(scene)),
        build_seconds: None,
    });
    Ok(entries)
}

fn thread_pool(threads: usize) -> Result<rayon::ThreadPool, Error> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::Failed {
            what: "thread pool".into(),
            reason: e.to_string(),
        })
}

fn work_cell(w: Work) -> String {
    let count = |x: Option<f64>| x.map_or("–".to_string(), |x| format!("{x:.1}"));
    format!(
        "{} | {} | {:.1}",
        count(w.nodes),
        count(w.leaves),
        w.triangles
    )
}

fn measure(scene: &Scene, args: &BenchArgs) -> Result<(), Error> {
    check_triangles_only(scene)?;
    let tris = triangles(scene);
    println!("\n## {}: {} triangles\n", scene.name, tris.len());
    let entries = engines(scene, &tris, args.runs)?;
    println!("| engine | BVH build (ms, 1 thread) |\n| --- | --- |");
    for e in &entries {
        if let Some(s) = e.build_seconds {
            println!("| {} | {:.1} |", e.name, s * 1e3);
        }
    }
    let primary = camera_rays(scene, args.resolution);
    let diffuse = diffuse_rays(scene, &primary);
    let sets = [("primary", &primary), ("diffuse", &diffuse)];

    println!(
        "\nWork per ray (nodes: interior nodes visited; leaves: leaves reached, whose triangles the \
         core tests four at a time; tris: triangle tests)\n\n\
         | rays | engine | closest nodes | closest leaves | closest tris | any nodes | any leaves | any tris |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- |"
    );
    for (kind, rays) in sets {
        for e in &entries {
            if let Some((closest, any)) = e.engine.work(rays) {
                println!(
                    "| {kind} | {} | {} | {} |",
                    e.name,
                    work_cell(closest),
                    work_cell(any)
                );
            }
        }
    }

    println!(
        "\nAgreement with the raylab core (same hit/miss and t within {} relative)\n\n\
         | rays | engine | hits | closest agree | same triangle | hit vs miss | t differs | any-hit agree |\n\
         | --- | --- | --- | --- | --- | --- | --- | --- |",
        agreement::T_TOLERANCE
    );
    for (kind, rays) in sets {
        let reference: Vec<_> = rays
            .par_iter()
            .map(|r| entries[0].engine.closest(r))
            .collect();
        let hits = reference.iter().filter(|h| h.is_some()).count();
        for e in &entries[1..] {
            let a = compare(e.engine.as_ref(), rays, &reference);
            println!(
                "| {kind} | {} | {hits} of {} | {:.4} % | {:.4} % | {} | {} | {:.4} % |",
                e.name,
                rays.len(),
                100.0 * a.closest_rate(),
                100.0 * a.same_triangle as f64 / hits.max(1) as f64,
                a.hit_miss,
                a.distance,
                100.0 * a.any_rate(),
            );
        }
    }

    println!(
        "\nThroughput (Mrays/s, median of {} runs, engines interleaved; ratio = raylab core ÷ engine)\n\n\
         | rays | threads | engine | closest-hit | any-hit | ratio closest | ratio any |\n\
         | --- | --- | --- | --- | --- | --- | --- |",
        args.runs
    );
    for (kind, rays) in sets {
        for threads in [1, 2] {
            let pool = thread_pool(threads)?;
            let rates = pool.install(|| throughput(&entries, rays, args.runs));
            let (core_closest, core_any) = rates[0];
            for (e, (closest, any)) in entries.iter().zip(&rates) {
                println!(
                    "| {kind} ({}) | {threads} | {} | {closest:.2} | {any:.2} | {:.2} | {:.2} |",
                    rays.len(),
                    e.name,
                    core_closest / closest,
                    core_any / any,
                );
            }
        }
    }
    Ok(())
}

/// Closest-hit and any-hit rates (Mrays/s) of every engine on `rays` in the current thread
/// pool: median of `runs`, the engines taking turns within each run so that all of them see the
/// same machine load.
fn throughput(entries: &[Entry<'_>], rays: &[Ray], runs: usize) -> Vec<(f64, f64)> {
    let mut times = vec![(Vec::new(), Vec::new()); entries.len()];
    for _ in 0..runs {
        for (e, (closest, any)) in entries.iter().zip(&mut times) {
            closest.push(time(&mut || {
                let hits = rays.par_iter().filter(|r| e.engine.closest(r).is_some());
                std::hint::black_box(hits.count());
            }));
            any.push(time(&mut || {
                std::hint::black_box(rays.par_iter().filter(|r| e.engine.any(r)).count());
            }));
        }
    }
    let rate = |mut t: Vec<f64>| rays.len() as f64 / median(&mut t) / 1e6;
    times
        .into_iter()
        .map(|(closest, any)| (rate(closest), rate(any)))
        .collect()
}

/// Checks `raylab bench`'s numbers.
pub fn check(args: &BenchArgs) -> Result<(), Error> {
    if args.resolution == 0 || args.runs == 0 || !(1..=64).contains(&args.copies) {
        return Err(Error::Invalid {
            what: format!(
                "--resolution {} --runs {} --copies {}",
                args.resolution, args.runs, args.copies
            ),
            reason: "expected whole numbers of at least 1 (and at most 64 copies)".into(),
        });
    }
    Ok(())
}

/// Runs `raylab bench`.
pub fn run(args: &BenchArgs) -> Result<(), Error> {
    check(args)?;
    if cfg!(debug_assertions) {
        eprintln!(
            "warning: this is a debug build; measure with `cargo run --release -p raylab -- bench`"
        );
    }
    if !cfg!(feature = "embree") {
        eprintln!(
            "note: Embree is not measured; build with `--features raylab/embree` (needs libembree-dev)"
        );
    }
    // Load the mesh first, so that a bad path fails before the long measurements.
    let mesh = match &args.mesh {
        Some(path) => {
            let mut obj = load_obj(path)?;
            obj.mesh = placed_copies(&obj.mesh, args.copies);
            let name = match args.copies {
                1 => path.display().to_string(),
                n => format!("{} ×{n}", path.display()),
            };
            pipeline::job::framed_scene(&name, obj, false)?
        }
        None => mesh_scene(
            "bumpy sphere",
            placed_copies(&bumpy_sphere(190, 185), args.copies),
        )?,
    };
    measure(&builtin_scene("cornell")?, args)?;
    measure(&mesh, args)
}

/// `copies` copies of `mesh` on a grid of ⌈∛copies⌉ per side, each cell the mesh's bounding
/// box and a fifth of its size apart.
fn placed_copies(mesh: &Mesh, copies: u32) -> Mesh {
    let bounds = Aabb::from_points(mesh.positions.iter().copied());
    let step = (bounds.max - bounds.min) * 1.2;
    let side = (1..).find(|k: &u32| k.pow(3) >= copies).unwrap_or(1);
    let mut placed = Mesh::default();
    for k in 0..copies {
        let cell = Vec3::new(
            (k % side) as f32,
            (k / side % side) as f32,
            (k / (side * side)) as f32,
        );
        let mut copy = mesh.clone();
        for p in &mut copy.positions {
            *p += cell * step;
        }
        placed.append(&copy);
    }
    placed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn copies_are_placed_apart_with_every_face() {
        let mesh = bumpy_sphere(8, 8);
        let placed = placed_copies(&mesh, 8);
        assert_eq!(placed.faces.len(), 8 * mesh.faces.len());
        assert_eq!(placed.positions.len(), 8 * mesh.positions.len());
        // The last copy sits one cell up, right and back (a 2×2×2 block), 1.2 sizes away.
        let n = mesh.positions.len();
        let bounds = Aabb::from_points(mesh.positions.iter().copied());
        let size = bounds.max - bounds.min;
        let offset = placed.positions[7 * n] - mesh.positions[0];
        assert!((offset - 1.2 * size).length() < 1e-4, "{offset} for {size}");
        assert_eq!(placed_copies(&mesh, 1).faces, mesh.faces);
    }

    #[test]
    fn missing_mesh_is_an_error_naming_the_path() {
        let args = BenchArgs {
            resolution: 4,
            runs: 1,
            mesh: Some(PathBuf::from("no/such/bunny.obj")),
            copies: 1,
        };
        let err = run(&args).unwrap_err().to_string();
        assert!(err.contains("no/such/bunny.obj"), "{err}");
    }
}
