use std::path::PathBuf;
use std::sync::Arc;

use glam::Vec2;

use super::checks::*;
use contracts::lab09::{Addressing, TextureFilter, Texturing};
use grading::strategies::samples;
use grading::{GoldenFile, LabContext};
use raylab_core::Error;

/// Writes lab 09's golden cases and snapshots from `reference` into the lab's directory.
pub fn generate_golden(
    reference: &Arc<dyn Texturing>,
    ctx: &LabContext,
) -> Result<Vec<PathBuf>, Error> {
    let r = reference.as_ref();
    let mut written = Vec::new();
    let mut save = |path: PathBuf, result: Result<(), Error>| result.map(|()| written.push(path));

    let planes: Vec<_> = samples(plane_input(), 32, 91)
        .into_iter()
        .map(|input| {
            let (plane, position, _) = plane_case(input);
            (plane, position)
        })
        .collect();
    let path = ctx.golden_path(GOLDEN_PLANE);
    let file = GoldenFile::record("9.1", &planes, |(plane, p)| r.plane_texcoord(plane, *p));
    save(path.clone(), file.save(&path))?;

    let spheres: Vec<_> = samples(sphere_input(), 32, 92)
        .into_iter()
        .map(sphere_case)
        .collect();
    let path = ctx.golden_path(GOLDEN_SPHERE);
    let file = GoldenFile::record("9.2", &spheres, |(sphere, p)| r.sphere_texcoord(sphere, *p));
    save(path.clone(), file.save(&path))?;

    let triangles = samples(triangle_input(), 32, 93);
    let path = ctx.golden_path(GOLDEN_TRIANGLE);
    let file = GoldenFile::record("9.3", &triangles, |(uvs, bary)| {
        r.triangle_texcoord(*uvs, *bary)
    });
    save(path.clone(), file.save(&path))?;

    let mut coordinates: Vec<(f32, Addressing)> = samples(address_input(), 48, 94)
        .into_iter()
        .map(|(x, k, mode)| (x + k as f32, mode))
        .collect();
    for mode in Addressing::ALL {
        coordinates.extend([-2.5f32, -1.0, -0.25, 1.0, 1.75, 3.0].map(|t| (t, mode)));
    }
    let path = ctx.golden_path(GOLDEN_ADDRESS);
    let file = GoldenFile::record("9.4", &coordinates, |(t, mode)| r.address(*t, *mode));
    save(path.clone(), file.save(&path))?;

    // Lookups away from ties between texel centres, with the reference's corresponders.
    let lookups: Vec<_> = samples((texture_case(), texcoords(), addressing()), 64, 95)
        .into_iter()
        .filter(|(case, uv, mode)| {
            let a = Vec2::new(r.address(uv.x, *mode), r.address(uv.y, *mode));
            closest_texel(&random_texture(*case), a).is_some()
        })
        .take(40)
        .collect();
    let path = ctx.golden_path(GOLDEN_NEAREST);
    let file = GoldenFile::record("9.5", &lookups, |(case, uv, mode)| {
        r.sample_nearest(&random_texture(*case), *uv, &|t| r.address(t, *mode))
    });
    save(path.clone(), file.save(&path))?;
    let path = ctx.golden_path(GOLDEN_BILINEAR);
    let file = GoldenFile::record("9.6", &lookups, |(case, uv, mode)| {
        r.sample_bilinear(&random_texture(*case), *uv, &|t| r.address(t, *mode))
    });
    save(path.clone(), file.save(&path))?;

    for (part, filter) in [
        (Part::Nearest, TextureFilter::Nearest),
        (Part::Bilinear, TextureFilter::Bilinear),
    ] {
        let (name, _) = snapshot_of(part);
        let film = render_textured(&part_pipeline(part, reference, &ctx.base, filter))?;
        let path = ctx.snapshot_path(&format!("{name}.exr"));
        save(path.clone(), raylab_core::film::write_exr(&film, &path))?;
    }
    Ok(written)
}
