use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::checks::*;
use contracts::lab11::AmbientOcclusion;
use grading::strategies::samples;
use grading::{GoldenFile, LabContext};
use raylab_core::Error;
use raylab_core::film::{Film, RgbeImage, write_exr};
use raylab_core::scene::{ProbeMapping, ProceduralProbe};

/// Golden cases per exercise, besides the fixed edge cases.
const CASES: usize = 64;

/// The image of the procedural probe `probe` in the mapping `mapping`, `width` texels wide
/// (an angular map is square, a latitude–longitude map twice as wide as high): each texel
/// the probe's radiance along the direction of its centre by `code`'s inverse mapping
/// (Exercises 11.6, 11.8), black outside an angular map's disc.
pub fn probe_film(
    code: &dyn AmbientOcclusion,
    probe: ProceduralProbe,
    mapping: ProbeMapping,
    width: u32,
) -> Film {
    let height = match mapping {
        ProbeMapping::Angular => width,
        ProbeMapping::Latlong => width / 2,
    };
    let mut film = Film::new(width, height);
    for y in 0..height {
        for x in 0..width {
            let uv = Vec2::new(
                (x as f32 + 0.5) / width as f32,
                (y as f32 + 0.5) / height as f32,
            );
            let d = match mapping {
                ProbeMapping::Angular => code.angular_map_direction(uv),
                ProbeMapping::Latlong => Some(code.latlong_direction(uv)),
            };
            film.set(x, y, d.map_or(Vec3::ZERO, |d| probe.radiance(d)));
        }
    }
    film
}

/// Writes lab 11's golden cases from `reference` into the lab's directory, and its two probe
/// images into `probes/`: the sky as a Radiance angular map, the studio as an OpenEXR
/// latitude–longitude map.
pub fn generate_golden(
    reference: &Arc<dyn AmbientOcclusion>,
    ctx: &LabContext,
) -> Result<Vec<PathBuf>, Error> {
    let r = reference.as_ref();
    let mut written = Vec::new();
    let probes = ctx.lab_dir.join("probes");
    let sky = probes.join(SKY_PROBE);
    RgbeImage::from_film(&probe_film(
        r,
        ProceduralProbe::Sky,
        ProbeMapping::Angular,
        256,
    ))
    .write(&sky)?;
    written.push(sky);
    let studio = probes.join(STUDIO_PROBE);
    write_exr(
        &probe_film(r, ProceduralProbe::Studio, ProbeMapping::Latlong, 256),
        &studio,
    )?;
    written.push(studio);

    let mut save = |name: &str, write: &dyn Fn(&Path) -> Result<(), Error>| {
        let path = ctx.golden_path(name);
        write(&path)?;
        written.push(path);
        Ok::<(), Error>(())
    };
    save(GOLDEN_RGBE, &|p| {
        let mut inputs = vec![
            [0, 0, 0, 0],
            [255, 255, 255, 0],
            [128, 0, 0, 129],
            [255, 128, 1, 128],
            [64, 200, 3, 136],
            [1, 2, 3, 1],
            [255, 255, 255, 255],
        ];
        inputs.extend(samples(rgbe_strategy(), CASES, 111));
        GoldenFile::record("11.4", &inputs, |&i| r.rgbe_to_rgb(i)).save(p)
    })?;
    let mut directions = vec![
        Vec3::NEG_Z,
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::new(0.6, 0.0, -0.8),
        Vec3::new(0.0, -0.6, 0.8),
    ];
    directions.extend(samples(direction_strategy(), CASES, 115));
    let mut uvs = vec![
        Vec2::new(0.5, 0.5),
        Vec2::new(0.75, 0.5),
        Vec2::new(0.5, 0.25),
        Vec2::new(0.1, 0.9),
        Vec2::new(0.95, 0.5),
        Vec2::new(0.25, 0.1),
    ];
    uvs.extend(samples(uv_strategy(), CASES, 116));
    save(GOLDEN_ANGULAR_UV, &|p| {
        GoldenFile::record("11.5", &directions, |&d| r.angular_map_uv(d)).save(p)
    })?;
    save(GOLDEN_ANGULAR_DIRECTION, &|p| {
        GoldenFile::record("11.6", &uvs, |&uv| r.angular_map_direction(uv)).save(p)
    })?;
    save(GOLDEN_LATLONG_UV, &|p| {
        GoldenFile::record("11.7", &directions, |&d| r.latlong_uv(d)).save(p)
    })?;
    save(GOLDEN_LATLONG_DIRECTION, &|p| {
        GoldenFile::record("11.8", &uvs, |&uv| Some(r.latlong_direction(uv))).save(p)
    })?;
    save(GOLDEN_SHADE, &|p| {
        let inputs = samples(shade_strategy(), CASES, 119);
        GoldenFile::record("11.9", &inputs, |(rho, o, env)| {
            r.shade_ambient_occlusion(*rho, o, *env)
        })
        .save(p)
    })?;
    Ok(written)
}
