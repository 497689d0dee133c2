use std::path::PathBuf;
use std::sync::Arc;

use proptest::prelude::*;

use super::checks::*;
use contracts::lab01::CameraRays;
use grading::strategies::{raster_in, resolution, samples, unit_vector};
use grading::{GoldenFile, LabContext};
use raylab_core::Error;

/// Writes lab 01's golden cases and snapshots from `reference` into the lab's directory.
pub fn generate_golden(
    reference: &Arc<dyn CameraRays>,
    ctx: &LabContext,
) -> Result<Vec<PathBuf>, Error> {
    let mut written = Vec::new();
    let mut save = |name: &str, write: &dyn Fn(&std::path::Path) -> Result<(), Error>| {
        let path = ctx.golden_path(name);
        write(&path)?;
        written.push(path);
        Ok::<_, Error>(())
    };
    let r = reference.as_ref();

    let inputs = samples(
        resolution().prop_flat_map(|res| (raster_in(res), Just(res))),
        64,
        11,
    );
    save(GOLDEN_IMAGE_PLANE, &|p| {
        GoldenFile::record("1.1", &inputs, |&(raster, res)| {
            r.image_plane_coords(raster, res)
        })
        .save(p)
    })?;

    let inputs = samples(basis_input(), 64, 12);
    save(GOLDEN_BASIS, &|p| {
        GoldenFile::record("1.2", &inputs, |&(e, l, u)| r.camera_basis(e, l, u)).save(p)
    })?;

    let inputs = samples(0.05f32..10.0, 32, 13);
    save(GOLDEN_FOV, &|p| {
        GoldenFile::record("1.3", &inputs, |&d| r.field_of_view(d)).save(p)
    })?;

    let inputs = samples(
        (
            basis_input(),
            0.2f32..5.0,
            -1.0f32..1.0,
            -0.5f32..0.5,
            unit_vector(),
        ),
        64,
        14,
    )
    .into_iter()
    .map(|((e, l, u), d, x, y, _)| (r.camera_basis(e, l, u), d, glam::Vec2::new(x, y)))
    .collect::<Vec<_>>();
    save(GOLDEN_DIRECTION, &|p| {
        GoldenFile::record("1.4", &inputs, |(b, d, ip)| r.ray_direction(b, *d, *ip)).save(p)
    })?;

    let film = render_snapshot(&camera_pipeline(reference.clone(), &ctx.base))?;
    let path = ctx.snapshot_path(&format!("{SNAPSHOT_DEFAULT}.exr"));
    raylab_core::film::write_exr(&film, &path)?;
    written.push(path);
    Ok(written)
}
