//! Running git: the handout is a git repository (`raylab handout`), its releases are commits
//! (`raylab handout --update`), and `raylab reset` takes a stub's original text from its
//! history.

use std::path::Path;
use std::process::{Command, Stdio};

use raylab_core::Error;

/// The e-mail address of the handout's own commits (`raylab handout` and its releases):
/// `raylab reset` finds the stubs as they were handed out by it.
pub const HANDOUT_EMAIL: &str = "raylab@localhost";

/// Runs `git ARGS` in `dir` and returns its standard output; an error naming the command and
/// what git said when it cannot run or fails.
pub fn git(dir: &Path, args: &[&str]) -> Result<Vec<u8>, Error> {
    let output = Command::new("git")
        // The identity the handout's commits are made with, given on the command line so that
        // they are made the same on a machine where git has no identity configured.
        .args(["-c", "user.name=raylab", "-c"])
        .arg(format!("user.email={HANDOUT_EMAIL}"))
        .args(["-c", "commit.gpgsign=false"])
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => Error::Failed {
                what: format!("git {}", args.join(" ")),
                reason: "git is not installed (or not on PATH); the handout is a git repository, install git".into(),
            },
            _ => Error::io(Path::new("git"), e),
        })?;
    if !output.status.success() {
        return Err(Error::Failed {
            what: format!("git {} (in {})", args.join(" "), dir.display()),
            reason: String::from_utf8_lossy(&output.stderr).trim().to_string(),
        });
    }
    Ok(output.stdout)
}

/// [`git`]'s output as text (lossy: git's own messages and hashes are ASCII).
pub fn git_text(dir: &Path, args: &[&str]) -> Result<String, Error> {
    Ok(String::from_utf8_lossy(&git(dir, args)?).into_owned())
}
