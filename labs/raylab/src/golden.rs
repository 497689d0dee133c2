//! `raylab golden`: regenerate every lab's golden cases and snapshots from the reference, and
//! beside each snapshot `NAME.exr` the reference image `NAME.png` students look at.

use course::LabId;
use std::path::{Path, PathBuf};

use clap::Args;
use grading::LabContext;
use lab03_checks as lab03;
use pipeline::LabSlots;
use raylab_core::Error;
use raylab_core::film::{ToneMap, read_exr, write_png};

use crate::students::{LabCode, LabVisitor};

/// Options of `raylab golden`.
#[derive(Args, Debug)]
pub struct GoldenArgs {
    /// Only this lab (default: all).
    #[arg(long)]
    pub lab: Option<LabId>,
    /// The raylab workspace (default: found from the current directory upwards).
    #[arg(long)]
    pub root: Option<PathBuf>,
}

/// The workspace root: the nearest ancestor of the current directory with `labs/` and
/// `Cargo.toml`.
fn find_root() -> Result<PathBuf, Error> {
    let cwd = std::env::current_dir().map_err(|e| Error::io(".", e))?;
    cwd.ancestors()
        .find(|d| d.join("Cargo.toml").is_file() && d.join("labs").is_dir())
        .map(Path::to_path_buf)
        .ok_or_else(|| Error::Invalid {
            what: format!("directory {}", cwd.display()),
            reason:
                "not inside a raylab workspace (no Cargo.toml with labs/ beside it); pass --root"
                    .into(),
        })
}

/// Records a lab's golden data from the answer key.
struct Generate<'a>(&'a LabContext);

impl LabVisitor for Generate<'_> {
    type Output = Result<Vec<PathBuf>, Error>;

    fn visit<S: ?Sized + LabSlots + Send + Sync + 'static>(self, code: LabCode<S>) -> Self::Output {
        (code.generate_golden)(&code.key, self.0)
    }
}

/// Runs `raylab golden`.
pub fn run(args: &GoldenArgs) -> Result<(), Error> {
    let root = match &args.root {
        Some(r) => r.clone(),
        None => find_root()?,
    };
    let labs: Vec<LabId> = match args.lab {
        Some(l) => vec![l],
        None => crate::students::labs(),
    };
    for lab in labs {
        let dir = root.join("labs").join(format!("{lab}"));
        let ctx = LabContext::new(lab, &dir, reference::pipeline(lab.number()));
        let written = crate::students::visit(lab, Generate(&ctx))??;
        let pngs = write_reference_pngs(&written)?;
        for path in written.iter().chain(&pngs) {
            println!("{}", path.display());
        }
    }
    Ok(())
}

/// Writes `NAME.png` beside each snapshot `NAME.exr` among `written`: the reference render,
/// tone mapped as a failing image check's `NAME-reference.png` (clamp at exposure 1, sRGB), so
/// that students can look at what their render should be before a check fails. The PNG
/// encoder is deterministic, so the same snapshot gives the same bytes. Lab 03's per-pixel
/// variance is a statistic of renders, not an image of the scene (and black at exposure 1): it
/// gets none.
fn write_reference_pngs(written: &[PathBuf]) -> Result<Vec<PathBuf>, Error> {
    let not_an_image = format!("{}.exr", lab03::checks::SNAPSHOT_AREA_VARIANCE);
    let snapshots = written.iter().filter(|p| {
        p.extension().is_some_and(|e| e == "exr")
            && p.parent()
                .and_then(Path::file_name)
                .is_some_and(|d| d == "snapshots")
            && p.file_name().is_some_and(|n| *n != *not_an_image)
    });
    snapshots
        .map(|exr| {
            let png = exr.with_extension("png");
            write_png(&read_exr(exr)?, &png, ToneMap::Clamp { exposure: 1.0 })?;
            Ok(png)
        })
        .collect()
}
