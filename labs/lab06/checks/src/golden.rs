use std::path::PathBuf;
use std::sync::Arc;

use super::checks::*;
use contracts::lab06::Radiosity;
use grading::strategies::samples;
use grading::{GoldenFile, LabContext};
use raylab_core::Error;

/// Writes lab 06's golden cases and its two Cornell-box snapshots (flat and smoothed) from
/// `reference` into the lab's directory.
pub fn generate_golden(
    reference: &Arc<dyn Radiosity>,
    ctx: &LabContext,
) -> Result<Vec<PathBuf>, Error> {
    let r = reference.as_ref();
    let mut written = Vec::new();
    let mut save = |path: PathBuf, result: Result<(), Error>| -> Result<(), Error> {
        result?;
        written.push(path);
        Ok(())
    };

    let inputs: Vec<PointInput> = samples(point_input(), 48, 61);
    let path = ctx.golden_path(GOLDEN_POINT);
    save(
        path.clone(),
        GoldenFile::record("6.1", &inputs, |&(x, nx, y, ny, a)| {
            r.point_form_factor(x, nx, y, ny, a)
        })
        .save(&path),
    )?;

    let inputs: Vec<DeltaInput> = samples(top_input(), 32, 62);
    let path = ctx.golden_path(GOLDEN_TOP);
    save(
        path.clone(),
        GoldenFile::record("6.2", &inputs, |&(x, y, a)| {
            r.delta_form_factor_top(x, y, a)
        })
        .save(&path),
    )?;

    let inputs: Vec<DeltaInput> = samples(side_input(), 32, 63);
    let path = ctx.golden_path(GOLDEN_SIDE);
    save(
        path.clone(),
        GoldenFile::record("6.3", &inputs, |&(u, z, a)| {
            r.delta_form_factor_side(u, z, a)
        })
        .save(&path),
    )?;

    let inputs: Vec<AccumulateInput> = samples(accumulate_input(), 12, 64);
    let path = ctx.golden_path(GOLDEN_ACCUMULATE);
    save(
        path.clone(),
        GoldenFile::record("6.4", &inputs, |(items, delta, n)| {
            r.accumulate_form_factors(items, delta, *n)
        })
        .save(&path),
    )?;

    let inputs: Vec<ShooterInput> = samples(shooter_input(), 24, 65);
    let path = ctx.golden_path(GOLDEN_SHOOTER);
    save(
        path.clone(),
        GoldenFile::record("6.5", &inputs, |(p, u)| r.select_shooter(p, u)).save(&path),
    )?;

    let inputs: Vec<ShootInput> = samples(shoot_input(), 24, 66);
    let path = ctx.golden_path(GOLDEN_SHOOT);
    save(
        path.clone(),
        GoldenFile::record("6.6", &inputs, |(p, f, i, b, u)| {
            let (mut b, mut u) = (b.clone(), u.clone());
            r.shoot(p, f, *i, &mut b, &mut u);
            (b, u)
        })
        .save(&path),
    )?;

    let inputs: Vec<Vec<glam::Vec3>> = samples(colours_input(), 12, 67);
    let path = ctx.golden_path(GOLDEN_COLOURS);
    save(
        path.clone(),
        GoldenFile::record("6.7", &inputs, |b| r.patch_colours(b)).save(&path),
    )?;

    let inputs: Vec<VerticesInput> = samples(vertices_input(), 16, 68);
    let path = ctx.golden_path(GOLDEN_VERTICES);
    save(
        path.clone(),
        GoldenFile::record("6.8", &inputs, |(p, n, c)| r.vertex_colours(p, *n, c)).save(&path),
    )?;

    for (name, smooth) in [(SNAPSHOT_FLAT, false), (SNAPSHOT_SMOOTH, true)] {
        let film = cornell_image(r, &ctx.base, smooth)?;
        let path = ctx.snapshot_path(&format!("{name}.exr"));
        save(path.clone(), raylab_core::film::write_exr(&film, &path))?;
    }
    Ok(written)
}
