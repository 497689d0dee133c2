//! `raylab bench`: throughput of the framework's ray-tracing core (BVH plus built-in
//! intersection kernels) in rays per second, for closest-hit and any-hit queries, on camera
//! rays and on one diffuse bounce per hit, on 1 and 2 threads; and the BVH build time.
//! docs/performance.md explains the measurement and records the figures.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use framework::Error;
use framework::glam::{UVec2, Vec2, Vec3};
use framework::math::{Aabb, Onb, RAY_EPSILON, Ray};
use framework::sampling::Rng;
use framework::scene::{
    CameraSetup, Material, MaterialId, Mesh, Scene, SceneDescription, builtin_scene, load_obj,
};
use rayon::prelude::*;

/// Options of `raylab bench`.
#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Rays per query set: camera rays through an N×N grid of pixel centres.
    #[arg(long, default_value_t = 512)]
    pub resolution: u32,
    /// Timed repetitions per measurement; the median is reported.
    #[arg(long, default_value_t = 5)]
    pub runs: usize,
    /// An OBJ mesh to measure besides the Cornell box (default: a generated sphere of 70 300
    /// triangles with bumps, about the size of the Stanford bunny).
    #[arg(long)]
    pub mesh: Option<PathBuf>,
}

/// A sphere of `rings × segments × 2` triangles with a few percent of radial bumps, seen by a
/// camera that frames it.
fn bumpy_sphere(rings: u32, segments: u32) -> Mesh {
    let mut mesh = Mesh::default();
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..segments {
            let phi = 2.0 * std::f32::consts::PI * s as f32 / segments as f32;
            let bump = 1.0 + 0.03 * (7.0 * theta).sin() * (11.0 * phi).cos();
            mesh.positions.push(
                bump * Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                ),
            );
        }
    }
    for r in 0..rings {
        for s in 0..segments {
            let i = |r: u32, s: u32| r * segments + s % segments;
            let (a, b, c, d) = (i(r, s), i(r, s + 1), i(r + 1, s), i(r + 1, s + 1));
            mesh.faces.push([a, c, b]);
            mesh.faces.push([b, c, d]);
        }
    }
    mesh.face_materials = vec![MaterialId(0); mesh.faces.len()];
    mesh
}

/// A scene of one mesh, with a camera looking at its bounding box from the front.
fn mesh_scene(name: &str, mesh: Mesh) -> Result<Scene, Error> {
    let bounds = Aabb::from_points(mesh.positions.iter().copied());
    let centre = bounds.centroid();
    let extent = bounds.diagonal().max_element();
    Scene::new(SceneDescription {
        name: name.into(),
        camera: Some(CameraSetup {
            eye: centre + Vec3::new(0.0, 0.2, 1.6) * extent,
            look_at: centre,
            up: Vec3::Y,
            focal_distance: 1.2,
        }),
        materials: vec![Material::lambertian("grey", Vec3::splat(0.7))],
        mesh,
        ..SceneDescription::default()
    })
}

/// Camera rays through the pixel centres of an `n × n` image (the reference camera).
fn camera_rays(scene: &Scene, n: u32) -> Vec<Ray> {
    let pipeline = reference::pipeline(1);
    let camera = pipeline.prepare_camera(scene, UVec2::splat(n));
    (0..n * n)
        .map(|k| {
            pipeline.camera_ray(
                &camera,
                Vec2::new((k % n) as f32 + 0.5, (k / n) as f32 + 0.5),
            )
        })
        .collect()
}

/// One cosine-distributed diffuse bounce from each hit of `rays` (on the side the ray came from).
fn diffuse_rays(scene: &Scene, rays: &[Ray]) -> Vec<Ray> {
    rays.iter()
        .enumerate()
        .filter_map(|(k, ray)| {
            let hit = scene.trace_to_closest(ray)?;
            let n = if hit.geometric_normal.dot(ray.direction) < 0.0 {
                hit.geometric_normal
            } else {
                -hit.geometric_normal
            };
            let mut rng = Rng::for_sample(5, k as u32, 0, 0);
            let u = rng.next_vec2();
            let (r, phi) = (u.x.sqrt(), 2.0 * std::f32::consts::PI * u.y);
            let local = Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u.x).max(0.0).sqrt());
            Some(Ray::unbounded(
                hit.position,
                Onb::from_w(n).to_world(local).normalize(),
                RAY_EPSILON,
            ))
        })
        .collect()
}

/// Median of `runs` timings of `f`, in seconds.
fn median_seconds(runs: usize, mut f: impl FnMut()) -> f64 {
    let mut times: Vec<f64> = (0..runs.max(1))
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64()
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn measure(scene: &Scene, args: &BenchArgs) -> Result<(), Error> {
    let build = median_seconds(args.runs, || {
        let bounds: Vec<Aabb> = (0..scene.mesh.faces.len())
            .map(|f| Aabb::from_points(scene.mesh.triangle(f)))
            .collect();
        std::hint::black_box(framework::accel::Bvh::build(&bounds));
    });
    println!(
        "{}: {} triangles, BVH build {:.1} ms (median of {})",
        scene.name,
        scene.mesh.faces.len(),
        build * 1e3,
        args.runs
    );
    let primary = camera_rays(scene, args.resolution);
    let diffuse = diffuse_rays(scene, &primary);
    for (kind, rays) in [("primary", &primary), ("diffuse", &diffuse)] {
        let hits = rays
            .iter()
            .filter(|r| scene.trace_to_closest(r).is_some())
            .count();
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map_err(|e| Error::Invalid {
                    what: "thread pool".into(),
                    reason: e.to_string(),
                })?;
            let closest = pool.install(|| {
                median_seconds(args.runs, || {
                    std::hint::black_box(
                        rays.par_iter()
                            .filter(|r| scene.trace_to_closest(r).is_some())
                            .count(),
                    );
                })
            });
            let any = pool.install(|| {
                median_seconds(args.runs, || {
                    std::hint::black_box(rays.par_iter().filter(|r| scene.trace_to_any(r)).count());
                })
            });
            println!(
                "  {kind:<8} {:>7} rays ({:>4.1}% hit)  {threads} thread{}  closest-hit {:>6.2} Mrays/s  any-hit {:>6.2} Mrays/s",
                rays.len(),
                100.0 * hits as f64 / rays.len().max(1) as f64,
                if threads == 1 { " " } else { "s" },
                rays.len() as f64 / closest / 1e6,
                rays.len() as f64 / any / 1e6,
            );
        }
    }
    Ok(())
}

/// Runs `raylab bench`.
pub fn run(args: &BenchArgs) -> Result<(), Error> {
    if args.resolution == 0 || args.runs == 0 {
        return Err(Error::Invalid {
            what: format!("--resolution {} --runs {}", args.resolution, args.runs),
            reason: "expected whole numbers of at least 1".into(),
        });
    }
    if cfg!(debug_assertions) {
        eprintln!(
            "warning: this is a debug build; measure with `cargo run --release -p raylab -- bench`"
        );
    }
    measure(&builtin_scene("cornell")?, args)?;
    let mesh = match &args.mesh {
        Some(path) => mesh_scene(&path.display().to_string(), load_obj(path)?.mesh)?,
        None => mesh_scene("bumpy sphere", bumpy_sphere(190, 185))?,
    };
    measure(&mesh, args)
}
