//! A lab's deterministic snapshots, grouped by the part of its contract they exercise: each
//! scene is rendered with the student's code for that one part and the base everywhere else,
//! and compared pixel by pixel with the reference's render (`raylab golden` writes those).

use std::path::PathBuf;
use std::sync::Arc;

use pipeline::render::render;
use pipeline::{Pipeline, View};
use raylab_core::Error;
use raylab_core::film::Film;
use raylab_core::render::RenderSettings;
use raylab_core::scene::Scene;

use crate::{LabContext, PixelTolerance};

/// A snapshot scene of a lab.
pub trait SnapshotScene: Copy + PartialEq + 'static {
    /// The snapshot's file name (without `.exr`).
    fn name(self) -> &'static str;
    /// The scene.
    fn scene(self) -> Result<Scene, Error>;
}

/// The parts of a lab's contract, each with the snapshot scenes that exercise it.
pub trait PartSnapshots: Copy + PartialEq + Sized + 'static {
    /// The lab's contract.
    type Contract: ?Sized + contracts::Part + contracts::Mix;
    /// A snapshot scene.
    type Shot: SnapshotScene;

    /// Every part with the scenes its snapshots render.
    const PARTS: &'static [(Self, &'static [Self::Shot])];
    /// Size and sampling of the snapshots.
    const SETTINGS: RenderSettings;
    /// The depth limit of the snapshots.
    const MAX_DEPTH: u32;
    /// Per-pixel tolerance of the snapshots.
    const TOLERANCE: PixelTolerance;

    /// The contract method whose code this part is (the student's in a
    /// [`PartSlot`](pipeline::PartSlot)).
    fn function(self) -> &'static str;

    /// The pipeline of this part's snapshots: `student` for this part only, `base` for the
    /// rest, shaded, with the depth limit [`Self::MAX_DEPTH`].
    fn pipeline(self, student: &Arc<Self::Contract>, base: &Pipeline) -> Pipeline {
        let mut pipeline = base.with_student_function(self.function(), student);
        pipeline.view = View::Shaded;
        pipeline.max_depth = Self::MAX_DEPTH;
        pipeline
    }

    /// Renders one snapshot scene through `pipeline`.
    fn render_shot(shot: Self::Shot, pipeline: &Pipeline) -> Result<Film, Error> {
        render(&shot.scene()?, pipeline, &Self::SETTINGS)
    }

    /// Compares the renders of this part's scenes with `student` in its slot with the lab's
    /// snapshots.
    fn check_snapshots(
        self,
        student: &Arc<Self::Contract>,
        ctx: &LabContext,
    ) -> Result<(), String> {
        let (_, shots) = Self::PARTS
            .iter()
            .find(|p| p.0 == self)
            .expect("every part is listed");
        let pipeline = self.pipeline(student, &ctx.base);
        for &shot in *shots {
            let film = Self::render_shot(shot, &pipeline).map_err(|e| e.to_string())?;
            ctx.check_snapshot(shot.name(), &film, &Self::TOLERANCE)?;
        }
        Ok(())
    }

    /// Writes the renders of `shots`, each with `reference` in the slot of the part that lists
    /// it, as the lab's snapshots (`snapshots/NAME.exr`), and says which files.
    fn save_snapshots(
        shots: &[Self::Shot],
        reference: &Arc<Self::Contract>,
        ctx: &LabContext,
    ) -> Result<Vec<PathBuf>, Error> {
        let mut written = Vec::new();
        for &shot in shots {
            let (part, _) = Self::PARTS
                .iter()
                .find(|(_, shots)| shots.contains(&shot))
                .expect("every shot belongs to a part");
            let film = Self::render_shot(shot, &part.pipeline(reference, &ctx.base))?;
            let path = ctx.snapshot_path(&format!("{}.exr", shot.name()));
            raylab_core::film::write_exr(&film, &path)?;
            written.push(path);
        }
        Ok(written)
    }
}
