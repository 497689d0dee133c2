use std::path::PathBuf;
use std::sync::Arc;

use super::checks::*;
use contracts::lab05::Radiometry;
use grading::strategies::samples;
use grading::{GoldenFile, LabContext};
use raylab_core::Error;

/// Golden cases per closed-form exercise, besides the worksheet's.
const CASES: usize = 48;

/// The worksheet's inputs first, then `CASES` drawn from `strategy` with `seed`.
fn inputs<S: proptest::strategy::Strategy>(
    worksheet: &[S::Value],
    strategy: S,
    seed: u8,
) -> Vec<S::Value>
where
    S::Value: Clone,
{
    let mut all = worksheet.to_vec();
    all.extend(samples(strategy, CASES, seed));
    all
}

/// Writes lab 05's golden cases from `reference` into the lab's directory: for each
/// closed-form exercise the worksheet's question and random inputs over many orders of
/// magnitude, and for the Monte Carlo exercises the variance of the reference's estimates on
/// each configuration of [`light_cases`].
pub fn generate_golden(
    reference: &Arc<dyn Radiometry>,
    ctx: &LabContext,
) -> Result<Vec<PathBuf>, Error> {
    let r = reference.as_ref();
    let mut written = Vec::new();
    let mut save = |name: &str, write: &dyn Fn(&std::path::Path) -> Result<(), Error>| {
        let path = ctx.golden_path(name);
        write(&path)?;
        written.push(path);
        Ok::<(), Error>(())
    };
    save(GOLDEN_PHOTONS, &|p| {
        let i = inputs(&[WORKSHEET_PHOTONS], photons_strategy(), 51);
        GoldenFile::record("5.1", &i, |&(a, b, c)| r.photons_per_second(a, b, c)).save(p)
    })?;
    save(GOLDEN_BULB, &|p| {
        let i = inputs(&[WORKSHEET_BULB], bulb_strategy(), 52);
        GoldenFile::record("5.2", &i, |&(a, b, c, d)| r.spherical_bulb(a, b, c, d)).save(p)
    })?;
    save(GOLDEN_OBSERVATION, &|p| {
        let i = inputs(
            &[WORKSHEET_OBSERVATION, WORKSHEET_TABLE],
            observation_strategy(),
            53,
        );
        GoldenFile::record("5.3", &i, |&(a, b, c)| r.observe_point_source(a, b, c)).save(p)
    })?;
    save(GOLDEN_ILLUMINANCE, &|p| {
        let i = inputs(&[WORKSHEET_ILLUMINANCE], illuminance_strategy(), 54);
        GoldenFile::record("5.4", &i, |&(a, b)| r.illuminance_lux(a, b)).save(p)
    })?;
    save(GOLDEN_EQUIVALENT, &|p| {
        let i = inputs(&[WORKSHEET_EQUIVALENT], equivalent_strategy(), 55);
        GoldenFile::record("5.5", &i, |&(a, b, c)| r.equivalent_intensity_cd(a, b, c)).save(p)
    })?;
    save(GOLDEN_EMITTER, &|p| {
        let i = inputs(&[WORKSHEET_EMITTER], emitter_strategy(), 56);
        GoldenFile::record("5.6", &i, |&(a, b)| r.diffuse_emitter(a, b)).save(p)
    })?;
    save(GOLDEN_RADIOSITY, &|p| {
        let i = inputs(&[WORKSHEET_RADIOSITY], radiosity_strategy(), 57);
        GoldenFile::record("5.7", &i, |(profile, steps)| {
            r.radiosity_from_radiance(&|t, f| profile.radiance(t, f), *steps)
        })
        .save(p)
    })?;
    save(GOLDEN_VARIANCE, &|p| {
        let cases = light_cases();
        let i: Vec<u32> = (0..cases.len() as u32).collect();
        GoldenFile::record("5.8", &i, |&k| {
            let case = &cases[k as usize];
            let var = |e| mean_and_variance(&estimates(r, e, case, MC_SAMPLES, MC_ESTIMATES, 11)).1;
            EstimatorVariance {
                area: var(Estimator::Area),
                cosine: var(Estimator::Cosine),
            }
        })
        .save(p)
    })?;
    Ok(written)
}
