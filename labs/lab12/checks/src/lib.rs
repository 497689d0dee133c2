//! Lab 12 — Path tracing: the checks of its contract ([`contracts::lab12`]) and the generator of
//! their golden data (docs/lab12.md).

pub mod checks;

pub use checks::sky;
#[cfg(feature = "report")]
pub mod report;

use std::path::PathBuf;
use std::sync::Arc;

use contracts::lab12::PathTracing;
use grading::{GoldenFile, LabContext};
use raylab_core::Error;

/// Writes lab 12's golden cases from `reference` into the lab's directory, and says which
/// files it wrote.
pub fn generate_golden(
    reference: &Arc<dyn PathTracing>,
    ctx: &LabContext,
) -> Result<Vec<PathBuf>, Error> {
    let mut written = Vec::new();
    let mut save = |name: &str, write: &dyn Fn(&PathBuf) -> Result<(), Error>| {
        let path = ctx.golden_path(name);
        write(&path)?;
        written.push(path);
        Ok::<(), Error>(())
    };
    save(checks::GOLDEN_LUMINANCE, &|path| {
        GoldenFile::record("12.1", &checks::luminance_inputs(), |&c| {
            reference.luminance(c)
        })
        .save(path)
    })?;
    save(checks::GOLDEN_BSDF, &|path| {
        let inputs = grading::strategies::samples(checks::bsdf_input(), 96, 22);
        GoldenFile::record("12.2", &inputs, |i| {
            reference.bsdf(&i.material, i.normal, i.wo, i.wi)
        })
        .save(path)
    })?;
    save(checks::GOLDEN_SAMPLE_BSDF, &|path| {
        let mut cases = Vec::new();
        for (k, case) in checks::sampler_cases().into_iter().enumerate() {
            let seed = 9000 + k as u64;
            let run =
                checks::run_sampler(reference.as_ref(), &case, seed, checks::KEY_BSDF_SAMPLES)
                    .map_err(|reason| Error::Failed {
                        what: "the answer key's BSDF sampler".into(),
                        reason,
                    })?;
            cases.push(grading::GoldenCase {
                input: case,
                expected: run.summary,
            });
        }
        GoldenFile {
            exercise: "12.3".into(),
            cases,
        }
        .save(path)
    })?;
    save(checks::GOLDEN_EMITTER_PDF, &|path| {
        let inputs = grading::strategies::samples(checks::emitter_pdf_input(), 64, 52);
        GoldenFile::record("12.5", &inputs, |c| {
            reference.emitter_pdf(c.0.triangle, c.0.position, c.1, c.2)
        })
        .save(path)
    })?;
    save(checks::GOLDEN_POWER_HEURISTIC, &|path| {
        let inputs = grading::strategies::samples((checks::density(), checks::density()), 64, 62);
        GoldenFile::record("12.6", &inputs, |&(a, b)| reference.power_heuristic(a, b)).save(path)
    })?;
    save(checks::GOLDEN_RELATIVE_ERROR, &|path| {
        let inputs = checks::relative_error_inputs();
        GoldenFile::record("12.10", &inputs[2..], |st| reference.relative_error(st)).save(path)
    })?;
    let pipeline =
        checks::cornell_pipeline(reference, &ctx.base).map_err(|reason| Error::Failed {
            what: "the reference pipeline".into(),
            reason,
        })?;
    let stats = checks::cornell_statistics(&pipeline, checks::REFERENCE_SEEDS)?;
    written.extend(ctx.save_noisy_snapshot(checks::SNAPSHOT_CORNELL, &stats)?);
    Ok(written)
}
