//! `Task::View` in a lab's program: the scene loaded, the pipelines prepared for it as
//! `raylab render` prepares its one, and the page served (the `view` crate).

use pipeline::Pipeline;
use pipeline::job::{empty_scene_warning, load_scene, prepare};
use pipeline::photon::PhotonSettings;
use raylab_core::Error;
use raylab_core::scene::Scene;

use crate::task::ViewJob;

/// Serves `job`'s page: `own` (the code the program was built with) and, when given, the
/// answer key's pipeline beside it.
pub fn serve(job: &ViewJob, own: Pipeline, key: Option<Pipeline>) -> Result<(), Error> {
    if job.end_with_stdin {
        std::thread::spawn(|| {
            let _ = std::io::copy(&mut std::io::stdin().lock(), &mut std::io::sink());
            std::process::exit(0)
        });
    }
    let scene = load_scene(&job.scene)?;
    if let Some(warning) = empty_scene_warning(&scene, &job.scene) {
        eprintln!("{warning}");
    }
    let mut shown = vec![view::Shown {
        name: job.whose.clone(),
        pipeline: prepared(own, &scene, job),
    }];
    if let Some(key) = key {
        shown.push(view::Shown {
            name: "Reference".into(),
            pipeline: prepared(key, &scene, job),
        });
    }
    let settings = view::ViewSettings {
        width: job.width,
        height: job.height,
        seed: job.seed,
        port: job.port,
        inspect: job.inspect,
        target_error: view::TARGET_ERROR,
        idle_after: view::IDLE_AFTER,
    };
    view::serve(scene, shown, &settings)
}

/// `pipeline` with `job`'s photons, prepared for `scene` as a render's is
/// ([`pipeline::job::prepare`]).
fn prepared(mut pipeline: Pipeline, scene: &Scene, job: &ViewJob) -> Pipeline {
    pipeline.photons = PhotonSettings {
        seed: job.seed,
        max_radius: PhotonSettings::radius_for(scene),
        ..PhotonSettings::DEFAULT
    };
    prepare(pipeline, scene, |line| eprintln!("{line}"))
}
